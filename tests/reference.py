"""An independent plain-NumPy model of SAM for the tests: Table I with Craig's modified DH and
eq (3), written directly from the paper, sharing no code with the generator or runtime."""

from __future__ import annotations

import numpy as np

L1, L4 = 0.5334, 0.3556


def mdh(alpha: float, a: float, d: float, theta: float) -> np.ndarray:
    ca, sa, ct, st = np.cos(alpha), np.sin(alpha), np.cos(theta), np.sin(theta)
    return np.array([[ct, -st, 0, a], [st * ca, ct * ca, -sa, -sa * d], [st * sa, ct * sa, ca, ca * d], [0, 0, 0, 1.0]])


def leg_pose(joints, base_offset: float = L1, platform_offset: float = L4) -> np.ndarray:
    """^B_P T of one SPU leg from (theta_a, theta_b, theta_c, L, phi_a, phi_b)."""
    t1, t2, t3, length, p2, p3 = joints
    h = np.pi / 2
    transform = np.eye(4)
    transform[1, 3] = -base_offset
    for row in [
        (0, 0, 0, t1 + h),
        (h, 0, 0, t2 + h),
        (h, 0, 0, t3),
        (-h, length, 0, 0),
        (0, 0, 0, p2 + h),
        (h, 0, 0, p3),
    ]:
        transform = transform @ mdh(*row)
    tool = np.array([[0, -1, 0, -platform_offset], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
    return transform @ tool


def sam_poses(actuated, passive, l1: float = L1, l4: float = L4) -> tuple[np.ndarray, np.ndarray]:
    """(left, right) platform poses; the right leg has the signs of L1 and L4 reversed."""
    left = leg_pose([*actuated[:3], *passive[:3]], l1, l4)
    right = leg_pose([*actuated[3:], *passive[3:]], -l1, -l4)
    return left, right


def twist_jacobian(joints, base_offset: float = L1, platform_offset: float = L4, h: float = 1e-6) -> np.ndarray:
    """Central finite differences of the leg pose: columns (v of the origin of {P}, w) in {B}."""
    joints = np.asarray(joints, dtype=float)
    columns = []
    for k in range(6):
        step = np.zeros(6)
        step[k] = h
        plus, minus = (
            leg_pose(joints + step, base_offset, platform_offset),
            leg_pose(joints - step, base_offset, platform_offset),
        )
        v = (plus[:3, 3] - minus[:3, 3]) / (2 * h)
        dr = (plus[:3, :3] - minus[:3, :3]) / (2 * h) @ leg_pose(joints, base_offset, platform_offset)[:3, :3].T
        w = np.array([dr[2, 1] - dr[1, 2], dr[0, 2] - dr[2, 0], dr[1, 0] - dr[0, 1]]) / 2
        columns.append(np.concatenate([v, w]))
    return np.array(columns).T
