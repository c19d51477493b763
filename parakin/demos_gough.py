"""Kong & Gosselin section 5.4, printed by ``demo()`` (to be listed as ``parakin demo gough``)."""

from __future__ import annotations

import warnings

import numpy as np

import parakin
from parakin import architecture
from parakin.errors import SingularConfigurationError
from parakin.pose import xyz_euler_from_pose

#: section 5.4: the locked inputs l1..l6 as printed (two decimals)
PRINTED_LENGTHS = [33.17, 32.02, 35.12, 37.57, 39.01, 38.32]


def demo() -> None:
    np.set_printoptions(precision=5, suppress=True, linewidth=120)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", architecture.ArchitectureSingularityWarning)
        m = parakin.load("gough", backend="numpy")
    print(f"{m!r}\n")
    print("section 5.4: base A2..A6 = (5,-5) (9,-3) (10,0) (9,3) (5,5), t11 = t12 = t22 = 1")
    fit = architecture.conic_fit(m)
    print(f"  architecture (eq 14-15): {fit.describe()}")
    print("  paper: on (x - 5)^2 + y^2 - 25 = 0, i.e. x - 0.1 x^2 - 0.1 y^2 = 0")
    lengths = np.array(PRINTED_LENGTHS)
    try:
        m.forward_pose_all(lengths)
    except SingularConfigurationError as error:
        print(f"  forward_pose_all: {type(error).__name__}: {error}")

    check = architecture.compatibility(m, lengths)
    print(f"\nprinted inputs l1..l6 = {PRINTED_LENGTHS}")
    scale = check.null_vector[0]
    print(f"  compatibility lambda . L(l) = {check.value / scale:.5f} (lambda = {check.null_vector / scale})")
    bound = 0.005 * np.abs(check.gradient / scale).sum()
    print(f"  rounding to 0.005 can move it by up to {bound:.3f}: consistent with rounding")
    print(f"  each leg implied by the other five: {check.implied}")
    print(f"  nearest compatible lengths {check.nearest}, 2-norm change {check.distance:.5f}")

    motion = architecture.self_motion(m, lengths, samples=300)
    low, high = motion.intervals[0]
    print(f"\nself-motion (section 5, legs 1-5 imposed, leg {motion.dependent} dependent):")
    print(f"  {motion.modes_per_ix[0]} assembly modes for every i_x in ({low:.5f}, {high:.5f}), none outside")
    print(f"  {len(motion.circuits)} circuits, each joined from {[len(c) for c in motion.circuits]} i_x-branches")
    print(f"  max leg residual along the motion (l_i(pose) - l_i): {motion.residual}")
    print("  (leg 6 keeps the constant length the other five imply: the printed l6 is 0.0338 short)")
    modes = architecture.self_motion_modes(m, lengths, 0.044)
    print(f"\nthe {modes.poses.shape[0]} assembly modes at i_x = 0.044 ({{x y z alpha beta gamma}}, leg residuals):")
    for pose, residual in zip(modes.poses, modes.residual, strict=True):
        print(f"  {xyz_euler_from_pose(pose)}  {np.abs(residual[:5]).max():.1e} / leg 6 {residual[5]:+.6f}")

    compatible = architecture.self_motion(m, check.nearest, samples=300)
    print(
        f"\nwith the nearest compatible lengths: {compatible.modes_per_ix[0]} modes per i_x on "
        f"({compatible.intervals[0][0]:.5f}, {compatible.intervals[0][1]:.5f}), {len(compatible.circuits)} circuits, "
        f"all six legs within {compatible.residual.max():.1e}"
    )
    fit_ls = architecture.least_squares_pose(m, lengths, modes.poses[0])
    print(
        f"least-squares pose for the printed (incompatible) lengths: residuals {fit_ls.residual}, "
        f"2-norm {fit_ls.norm:.5f} (= the distance to compatible lengths)"
    )


if __name__ == "__main__":
    demo()
