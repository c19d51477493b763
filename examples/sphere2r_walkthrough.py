"""ED5314 report, section 2: the 2R spherical serial chain, forward and both inverse branches, on
parakin's public API.

    python examples/sphere2r_walkthrough.py

The end-effector direction is w, the third column of ^B_P R (the chain's last joint axis).
"""

from __future__ import annotations

import numpy as np

import parakin

#: the joint angles of the walkthrough (deg)
EXAMPLE_DEG = [30.0, 50.0]


def demo() -> None:
    m = parakin.load("sphere2r")
    np.set_printoptions(precision=5, suppress=True, linewidth=120)
    print(f"{m!r}")
    theta = np.deg2rad(EXAMPLE_DEG)
    reached = m.forward_pose(theta)
    w = reached.rotation[:, 2]
    print(f"2R spherical chain (section 2): theta = {tuple(EXAMPLE_DEG)} deg -> w = {w}")
    branches = m.inverse_pose(reached.pose)
    for k in range(branches.actuated.shape[0]):
        back = m.forward_pose(branches.actuated[k]).rotation[:, 2]
        print(
            f"  inverse branch {k}: theta (deg) {np.rad2deg(branches.actuated[k])}  |w error| {np.abs(back - w).max():.1e}"
        )


if __name__ == "__main__":
    demo()
