"""Worked examples from the papers, printed by ``parakin demo NAME`` and ``make demo``."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

import parakin
from parakin import demos_gough, demos_sps
from parakin.errors import SingularConfigurationError
from parakin.pose import pose_from_xyz_euler, xyz_euler_from_pose
from parakin.results import Configuration

#: eq (15) of Williams & Poling: nominal pose and its joint values (lengths m, angles deg)
SAM_NOMINAL_POSE = [0.0, 0.0, 0.664, 0.0, 0.0, 0.0]
SAM_NOMINAL_ACTUATED_DEG = [0, -15, 0, 0, 15, 0]
SAM_NOMINAL_PASSIVE = [0.687, 15, 0, 0.687, -15, 0]  # L2 phi2 phi3 L3 phi5 phi6 (m, deg)
#: section 4.2: per-step increment {dx, dy, dz, dalpha, dbeta, dgamma} (m, deg) and twist
SAM_TRAJECTORY_STEP = [0.005, 0.005, 0.005, 0.0, 0.0, 0.5]
SAM_RATE_TWIST = [-0.1, -0.1, 0.1, 0.1, 0.1, 0.1]
#: the inverse branch (left, right) = (+, +), (-, +) whose joint values match eq (15)
SAM_PAPER_BRANCH = 2


def sam_trajectory_poses(steps: int = 10) -> np.ndarray:
    """Section 4.2: the nominal pose plus k steps of 5 mm in x, y, z and 0.5 deg in gamma
    (Euler X rotation, eq 2; the text also says 'about the Z axis', which its own Fig. 5
    description contradicts, see tests/test_sam_paper.py)."""
    start = np.array(SAM_NOMINAL_POSE)
    step = np.array(SAM_TRAJECTORY_STEP, dtype=float)
    step[3:] = np.deg2rad(step[3:])
    return pose_from_xyz_euler(start + np.arange(steps + 1)[:, None] * step)


def nearest_branch(branches: parakin.InversePose, previous: np.ndarray) -> Configuration:
    """The valid branch whose actuated values are closest to ``previous`` (single pose)."""
    distance = np.abs(branches.actuated - previous).max(-1) + np.where(branches.valid, 0.0, np.inf)
    return branches.branch(int(np.argmin(distance)))


def sam() -> None:
    m = parakin.load("sam")
    np.set_printoptions(precision=4, suppress=True, linewidth=120)
    print(f"{m!r}\n")
    print("eq (15) nominal configuration: inverse pose of {x y z alpha beta gamma} = {0 0 0.664 0 0 0}")
    nominal = m.inverse_pose(pose_from_xyz_euler(SAM_NOMINAL_POSE))
    config = nominal.branch(SAM_PAPER_BRANCH)
    print(f"  theta1..6 (deg)        paper {SAM_NOMINAL_ACTUATED_DEG}")
    print(f"                         ours  {np.rad2deg(config.actuated)}")
    passive = config.passive.copy()
    passive[[1, 2, 4, 5]] = np.rad2deg(passive[[1, 2, 4, 5]])
    print(f"  L2 phi2 phi3 L3 phi5 phi6 paper {SAM_NOMINAL_PASSIVE}")
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
    poses = sam_trajectory_poses()
    previous = config
    for k, pose in enumerate(poses):
        branch = nearest_branch(m.inverse_pose(pose), previous.actuated)
        try:
            forward = m.forward_pose(branch.actuated, guess=previous)
            error = np.abs(forward.pose - pose).max()
            fk = f"FK iterations {int(forward.iterations)} |pose error| {error:.1e}"
            previous = forward
        except SingularConfigurationError as singular:
            fk = f"FK: {type(singular).__name__} (type II, as the nominal pose is)"
            previous = branch
        print(f"  step {k:2d} theta (deg) {np.rad2deg(branch.actuated)}  {fk}")

    modes = m.forward_pose_all(previous.actuated)
    print(
        f"\nforward_pose_all at step 10 (closed form, degree {m.metadata['forward']['degree']} polynomial): {int(modes.count)} modes"
    )
    for mode in np.nonzero(modes.valid)[0]:
        print(
            f"  mode {mode}: {{x y z alpha beta gamma}} = {xyz_euler_from_pose(modes.poses[mode])}  residual {modes.residual[mode]:.1e}"
        )

    print(f"\nsection 4.2 inverse rate at the nominal pose, twist {SAM_RATE_TWIST} (m/s, rad/s):")
    rates = m.inverse_rate(config, SAM_RATE_TWIST)
    print(f"  theta_dot (rad/s) {rates.actuated}")
    print(f"  passive rates     {rates.passive}")


#: section 3.2.3 of the SPM report: inputs (deg)
SPM_EXAMPLE_DEG = [105.0, 60.0, 105.0]


def spm() -> None:
    m = parakin.load("spm")
    np.set_printoptions(precision=5, suppress=True, linewidth=120)
    degree = m.metadata["forward"]["degree"]
    print(f"\n{m!r}")
    print("section 3.2.3 example, read as proximal alpha1 = 45 deg, distal alpha2 = 90 deg (the printed")
    print(f"labels swap them), beta = 60, gamma = 45 deg; theta = {SPM_EXAMPLE_DEG} deg")
    theta = np.deg2rad(SPM_EXAMPLE_DEG)
    modes = m.forward_pose_all(theta)
    print(f"  forward polynomial degree {degree}: {int(modes.count)} real assembly modes (report: 8)")
    for number, k in enumerate(np.nonzero(modes.valid)[0]):
        rotation = modes.poses[k, :3, :3]
        angle = np.rad2deg(np.arccos(np.clip((np.trace(rotation) - 1) / 2, -1, 1)))
        axis = np.array(
            [rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0], rotation[1, 0] - rotation[0, 1]]
        )
        axis = axis / max(np.linalg.norm(axis), 1e-300)
        print(
            f"  mode {number + 1}: x = tan(phi1/2) = {modes.root[k]: .5f}  rotation {angle:7.3f} deg about {axis}"
            f"  passive (deg) {np.rad2deg(modes.passive[k])}  residual {modes.residual[k]:.1e}"
        )
    printed = parakin.load("spm", alpha1=np.pi / 2, alpha2=np.pi / 4)
    print(
        f"  with the labels as printed (alpha1 = 90, alpha2 = 45 deg): {int(printed.forward_pose_all(theta).count)} modes"
    )
    eye = parakin.load(
        "spm", alpha1=np.pi / 2, alpha2=np.pi / 2, beta=np.arctan(np.sqrt(2)), gamma=np.arctan(np.sqrt(2))
    )
    agile = eye.forward_pose_all(np.deg2rad([10.0, 20.0, -15.0]))
    print(
        f"  Agile Eye at theta = (10, 20, -15) deg: {int(agile.count)} genuine modes, "
        f"{int(agile.input_independent.sum())} input-independent (folded) solutions flagged"
    )


def sphere2r() -> None:
    m = parakin.load("sphere2r")
    np.set_printoptions(precision=5, suppress=True, linewidth=120)
    print(f"\n{m!r}")
    theta = np.deg2rad([30.0, 50.0])
    w = m.forward_pose(theta).rotation[:, 2]
    print(f"2R spherical chain (section 2): theta = (30, 50) deg -> w = {w}")
    branches = m.inverse_pose(m.forward_pose(theta).pose)
    for k in range(branches.actuated.shape[0]):
        reached = m.forward_pose(branches.actuated[k]).rotation[:, 2]
        print(
            f"  inverse branch {k}: theta (deg) {np.rad2deg(branches.actuated[k])}  |w error| {np.abs(reached - w).max():.1e}"
        )


DEMOS: dict[str, Callable[[], None]] = {
    "sphere2r": sphere2r,
    "sam": sam,
    "spm": spm,
    "sps": demos_sps.demo,
    "gough": demos_gough.demo,
}
