"""Accelerator of ``prs3.py`` (optional): the inverse's reading of a pose onto the 3-PRS's reachable
set by hand, the tilt R0 about a horizontal axis with the parasitic centre (x0, y0) it forces, or
its half-turn about the vertical. Derivation: ``docs/derivations/prs3.md``.
"""

from __future__ import annotations

from dataclasses import replace

import sympy as sp
from parakin.generator import joints
from parakin.generator.frames import sign_or_plus
from parakin.generator.model import POSE_POSITION, POSE_ROTATION

K = sp.Matrix([0, 0, 1])


def tilt(r_p: sp.Expr, n: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """For a unit n = R^T k: the tilt R0 about a horizontal axis with R0^T k = n, its unit
    quaternion (q0 > 0) and the platform centre (x0, y0, 0) that the plane constraints give it
    (platform joints on the circle of radius ``r_p``). R0 = I + [v]x + [v]x^2 / (1 + n_z),
    v = n x k; q = (1 + n_z, n x k) / sqrt(2 (1 + n_z))."""
    v = n.cross(K)
    skew = sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    rotation = sp.eye(3) + skew + (v * v.T - v.dot(v) * sp.eye(3)) / (1 + n[2])
    root = sp.sqrt(2 * (1 + n[2]))
    q = sp.Matrix([(1 + n[2]) / root, v[0] / root, v[1] / root, 0])
    centre = sp.Matrix([-r_p * (n[0] ** 2 - n[1] ** 2) / (2 * (1 + n[2])), r_p * n[0] * n[1] / (1 + n[2]), 0])
    return rotation, q, centre


def motion(r_p: sp.Expr) -> joints.Platform:
    """A spatial platform (x, y, z, unit quaternion) whose inverse reads the reachable pose with
    the pose's height and tilt, not the pose's own x, y and turn."""
    base = joints.platform("transform")
    x, y, z, *quaternion = base.coordinates
    n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    r0 = sp.Matrix(3, 3, sp.symbols("tilt11 tilt12 tilt13 tilt21 tilt22 tilt23 tilt31 tilt32 tilt33", real=True))
    centre = sp.Matrix(sp.symbols("x0 y0", real=True))
    turn = sp.Symbol("turn", real=True)  # +1: R0, -1: its half-turn Rot_z(pi) R0
    rotation, q, centre_expr = tilt(r_p, n)
    read = [*zip(n, POSE_ROTATION[2, :], strict=True), *zip(r0, rotation, strict=True)]
    read += [*zip(centre, centre_expr[:2], strict=True), (turn, sign_or_plus(POSE_ROTATION[0, :].dot(r0[0, :])))]
    half = [(1 + turn) / 2, (1 - turn) / 2]  # Rot_z(pi) q = (0, 0, 0, 1) q = (0, -q2, q1, q0)
    turned = [half[0] * q[0], half[0] * q[1] - half[1] * q[2], half[0] * q[2] + half[1] * q[1], half[1] * q[0]]
    read += [(x, turn * centre[0]), (y, turn * centre[1]), (z, POSE_POSITION[2]), *zip(quaternion, turned, strict=True)]
    pose = (sp.diag(turn, turn, 1) * r0, sp.Matrix([x, y, z]))
    return replace(base, read=tuple(read), pose=pose)
