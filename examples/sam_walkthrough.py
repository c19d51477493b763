"""Williams & Poling (2000): the spherically actuated 2-SPU platform (SAM), its printed numbers
reproduced on parakin's public API.

    python examples/sam_walkthrough.py

prints eq (15)'s nominal configuration, Table II's sixteen inverse branches, section 4.2's
trajectory (inverse pose, then Newton forward pose tracked step by step), every assembly mode of
the last step and section 4.2's inverse rates. Lengths in metres, angles printed in degrees.
"""

from __future__ import annotations

import numpy as np

import parakin
from parakin.results import Configuration, InversePose

#: eq (15): nominal pose {x y z alpha beta gamma} (m, rad) and its joint values
NOMINAL_POSE = [0.0, 0.0, 0.664, 0.0, 0.0, 0.0]
NOMINAL_ACTUATED_DEG = [0, -15, 0, 0, 15, 0]  # theta1..theta6
NOMINAL_PASSIVE = [0.687, 15, 0, 0.687, -15, 0]  # L2 phi2 phi3 L3 phi5 phi6 (m, deg)
#: section 4.2: per-step increment {dx, dy, dz, dalpha, dbeta, dgamma} (m, deg) and the twist (m/s, rad/s)
TRAJECTORY_STEP = [0.005, 0.005, 0.005, 0.0, 0.0, 0.5]
RATE_TWIST = [-0.1, -0.1, 0.1, 0.1, 0.1, 0.1]
#: the inverse branch (left, right) = (+, +), (-, +) whose joint values match eq (15)
PAPER_BRANCH = 2


def trajectory_poses(steps: int = 10) -> np.ndarray:
    """Section 4.2: the nominal pose plus k steps of 5 mm in x, y, z and 0.5 deg in gamma
    (Euler X rotation, eq 2; the text also says 'about the Z axis', which its own Fig. 5
    description contradicts, see tests/test_sam_paper.py)."""
    start = np.array(NOMINAL_POSE)
    step = np.array(TRAJECTORY_STEP, dtype=float)
    step[3:] = np.deg2rad(step[3:])
    return parakin.pose_from_xyz_euler(start + np.arange(steps + 1)[:, None] * step)


def nearest_branch(branches: InversePose, previous: np.ndarray) -> Configuration:
    """The valid branch whose actuated values are closest to ``previous`` (single pose)."""
    distance = np.abs(branches.actuated - previous).max(-1) + np.where(branches.valid, 0.0, np.inf)
    return branches.branch(int(np.argmin(distance)))


def nominal_configuration(m: parakin.Mechanism) -> Configuration:
    """Eq (15): the paper's branch of the nominal pose."""
    return m.inverse_pose(parakin.pose_from_xyz_euler(NOMINAL_POSE)).branch(PAPER_BRANCH)


def demo() -> None:
    m = parakin.load("sam")
    np.set_printoptions(precision=4, suppress=True, linewidth=120)
    print(f"{m!r}\n")
    print("eq (15) nominal configuration: inverse pose of {x y z alpha beta gamma} = {0 0 0.664 0 0 0}")
    nominal = m.inverse_pose(parakin.pose_from_xyz_euler(NOMINAL_POSE))
    config = nominal.branch(PAPER_BRANCH)
    print(f"  theta1..6 (deg)        paper {NOMINAL_ACTUATED_DEG}")
    print(f"                         ours  {np.rad2deg(config.actuated)}")
    passive = config.passive.copy()
    passive[[1, 2, 4, 5]] = np.rad2deg(passive[[1, 2, 4, 5]])
    print(f"  L2 phi2 phi3 L3 phi5 phi6 paper {NOMINAL_PASSIVE}")
    print(f"                            ours  {passive}")
    factors = m.singularities(config)
    print(
        f"  closed-loop determinant {float(factors['closed_loop_determinant']):.3g}: "
        f"u_joint_axes_parallel = {float(factors['u_joint_axes_parallel']):.3g} -> the nominal pose is a type II singularity"
    )
    print("\nTable II: the 4 x 4 inverse branches of the nominal pose (theta deg), all reproduce the pose:")
    for k in range(nominal.actuated.shape[0]):
        reached = m.platform_pose(nominal.actuated[k], nominal.passive[k])
        error = np.abs(reached - nominal.pose).max()
        print(
            f"  branch {k:2d} signs {nominal.branches[k]}  {np.rad2deg(nominal.actuated[k])}  |pose error| {error:.1e}"
        )

    print("\nsection 4.2 trajectory: inverse pose, then forward pose (Newton tracking from the previous step)")
    previous = config
    for k, pose in enumerate(trajectory_poses()):
        branch = nearest_branch(m.inverse_pose(pose), previous.actuated)
        try:
            forward = m.forward_pose(branch.actuated, guess=previous)
            error = np.abs(forward.pose - pose).max()
            fk = f"FK iterations {int(forward.iterations)} |pose error| {error:.1e}"
            previous = forward
        except parakin.SingularConfigurationError as singular:
            fk = f"FK: {type(singular).__name__} (type II, as the nominal pose is)"
            previous = branch
        print(f"  step {k:2d} theta (deg) {np.rad2deg(branch.actuated)}  {fk}")

    modes = m.forward_pose_all(previous.actuated)
    degree = m.manifest.capabilities.forward.degree if m.manifest.capabilities.forward else None
    print(f"\nforward_pose_all at step 10 (closed form, degree {degree} polynomial): {int(modes.count)} modes")
    for number, slot in enumerate(np.nonzero(modes.valid)[0]):  # numbered as modes.mode(number)
        print(
            f"  mode {number}: {{x y z alpha beta gamma}} = {parakin.xyz_euler_from_pose(modes.poses[slot])}"
            f"  residual {modes.residual[slot]:.1e}"
        )

    print(f"\nsection 4.2 inverse rate at the nominal pose, twist {RATE_TWIST} (m/s, rad/s):")
    rates = m.inverse_rate(config, RATE_TWIST)
    print(f"  theta_dot (rad/s) {rates.actuated}")
    print(f"  passive rates     {rates.passive}")


if __name__ == "__main__":
    demo()
