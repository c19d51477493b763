"""Homogeneous transforms, Craig's modified Denavit-Hartenberg links and Z-Y-X Euler angles.

Conventions (Craig, *Introduction to Robotics*, 1989, the convention of all four papers' tables):
a modified-DH row (alpha_{i-1}, a_{i-1}, d_i, theta_i) gives
    ^{i-1}_i T = Rot_x(alpha_{i-1}) Trans_x(a_{i-1}) Rot_z(theta_i) Trans_z(d_i).
Z-Y-X Euler angles (alpha about Z, then beta about the new Y, then gamma about the new X) give
    R = Rot_z(alpha) Rot_y(beta) Rot_x(gamma), Williams & Poling eq (2).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp


def rot_x(angle: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(angle: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_z(angle: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def homogeneous(rotation: sp.Matrix, translation: sp.Matrix | list) -> sp.Matrix:
    """4x4 transform from a 3x3 rotation and a 3-vector translation."""
    transform = sp.eye(4)
    transform[:3, :3] = rotation
    transform[:3, 3] = sp.Matrix(translation)
    return transform


def translation(x: sp.Expr = 0, y: sp.Expr = 0, z: sp.Expr = 0) -> sp.Matrix:
    return homogeneous(sp.eye(3), [x, y, z])


def inverse_transform(transform: sp.Matrix) -> sp.Matrix:
    """Closed-form inverse of a rigid transform: [R^T, -R^T p]."""
    rotation_t = transform[:3, :3].T
    return homogeneous(rotation_t, -rotation_t * transform[:3, 3])


def euler_zyx_rotation(alpha: sp.Expr, beta: sp.Expr, gamma: sp.Expr) -> sp.Matrix:
    """R = Rot_z(alpha) Rot_y(beta) Rot_x(gamma): Williams & Poling eq (2)."""
    return rot_z(alpha) * rot_y(beta) * rot_x(gamma)


def vee(skew: sp.Matrix) -> sp.Matrix:
    """The axial vector of the skew-symmetric part of a 3x3 matrix: (M - M^T)/2 -> w."""
    return sp.Matrix(
        [
            (skew[2, 1] - skew[1, 2]) / 2,
            (skew[0, 2] - skew[2, 0]) / 2,
            (skew[1, 0] - skew[0, 1]) / 2,
        ]
    )


# ------------------------------------------------------------------ quaternions
# q = (q0, q1, q2, q3) = q0 + q1 i + q2 j + q3 k, scalar first (Hamilton); a vector v is the pure
# quaternion (0, v); R(q) v = q v q* / |q|^2, so q and any non-zero multiple of it (-q included)
# give the same rotation.
def quaternion_product(a: sp.Matrix | list, b: sp.Matrix | list) -> sp.Matrix:
    """The Hamilton product a b of two quaternions (4-vectors, scalar first)."""
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return sp.Matrix(
        [
            a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
            a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
            a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
        ]
    )


def quaternion_conjugate(q: sp.Matrix | list) -> sp.Matrix:
    """q* = (q0, -q1, -q2, -q3)."""
    return sp.Matrix([q[0], -q[1], -q[2], -q[3]])


def pure_quaternion(v: sp.Matrix | list) -> sp.Matrix:
    """The vector v as the quaternion (0, v)."""
    return sp.Matrix([0, v[0], v[1], v[2]])


def quaternion_rotation_unnormalised(q: sp.Matrix | list) -> sp.Matrix:
    """|q|^2 R(q): the columns are q e_k q* (a quadratic form in q, exact for any scale)."""
    columns = [
        quaternion_product(quaternion_product(q, pure_quaternion(axis)), quaternion_conjugate(q))[1:, 0]
        for axis in sp.eye(3).columnspace()
    ]
    return sp.Matrix.hstack(*columns)


def quaternion_rotation(q: sp.Matrix | list) -> sp.Matrix:
    """R(q) = (q v q*) / |q|^2: a rotation for every non-zero q, singular nowhere else."""
    norm = sum(c**2 for c in q)
    return quaternion_rotation_unnormalised(q) / norm


def sign_or_plus(value: sp.Expr) -> sp.Expr:
    """sign(value) with sign(0) = +1."""
    return sp.sign(value) + 1 - sp.Abs(sp.sign(value))


def quaternion_from_rotation(rotation: sp.Matrix) -> sp.Matrix:
    """The unit quaternion of R with q0 >= 0 (q0 = 0: the half-turns, either sign), without
    branches: the columns of K = 4 q q^T (entries linear in R) are 4 q_k q; they are added with
    the sign that makes each agree with the sum so far (a sign error only ever affects a column of
    vanishing length), so the sum is 4 (|q0| + |q1| + |q2| + |q3|) q, of length >= 2. One
    expression: ``quaternion_steps`` substituted into one another."""
    quaternion = sp.symbols("q0:4", real=True)
    values: dict[sp.Symbol, sp.Expr] = {}
    for target, expression in quaternion_steps(rotation, quaternion):
        values[target] = expression.xreplace(values)
    return sp.Matrix([values[q] for q in quaternion])


@dataclass(frozen=True)
class ModifiedDHLink:
    """One row of a modified-DH table (Craig): alpha_{i-1}, a_{i-1}, d_i, theta_i.

    ``joint`` is the joint variable this row moves (a revolute variable inside ``theta`` or a
    prismatic one inside ``a``/``d``), or None for a fixed row.
    """

    alpha: sp.Expr
    a: sp.Expr
    d: sp.Expr
    theta: sp.Expr
    joint: sp.Symbol | None = None

    def __post_init__(self) -> None:
        for name in ("alpha", "a", "d", "theta"):
            object.__setattr__(self, name, sp.sympify(getattr(self, name)))

    def transform(self) -> sp.Matrix:
        """^{i-1}_i T = Rot_x(alpha) Trans_x(a) Rot_z(theta) Trans_z(d)."""
        return homogeneous(rot_x(self.alpha), [self.a, 0, 0]) * homogeneous(rot_z(self.theta), [0, 0, self.d])

    def kind(self) -> str:
        """'R' when the joint variable sits in theta, 'P' when it sits in a or d."""
        if self.joint is None:
            return "fixed"
        return "R" if self.theta.has(self.joint) else "P"

    def prismatic_axis(self) -> str:
        """Which frame axis a prismatic joint slides along: x_{i-1} (in a) or z_i (in d)."""
        return "x_prev" if self.a.has(self.joint) else "z"


def quaternion_steps(rotation: sp.Matrix, quaternion: Sequence[sp.Symbol]) -> list[tuple[sp.Symbol, sp.Expr]]:
    """``quaternion`` (q0..q3) of R (q0 >= 0, branch-free; ``quaternion_from_rotation``: the
    columns k_c of K = 4 q q^T, each added to the running sum with the sign that makes it agree,
    then normalised), written as steps with the running sums as intermediate symbols: as one
    expression each sum repeats inside every later sign (2.7 MB of SymPy, 0.1 s per evaluation
    in the generator's checks)."""
    r = rotation
    k = sp.Matrix(
        [
            [1 + r[0, 0] + r[1, 1] + r[2, 2], r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]],
            [r[2, 1] - r[1, 2], 1 + r[0, 0] - r[1, 1] - r[2, 2], r[0, 1] + r[1, 0], r[0, 2] + r[2, 0]],
            [r[0, 2] - r[2, 0], r[0, 1] + r[1, 0], 1 - r[0, 0] + r[1, 1] - r[2, 2], r[1, 2] + r[2, 1]],
            [r[1, 0] - r[0, 1], r[0, 2] + r[2, 0], r[1, 2] + r[2, 1], 1 - r[0, 0] - r[1, 1] + r[2, 2]],
        ]
    )
    steps: list[tuple[sp.Symbol, sp.Expr]] = []
    total = k[:, 0]
    for column in range(1, 4):
        sign = sign_or_plus(total.dot(k[:, column]))
        running = sp.Matrix(sp.symbols(f"quaternion_sum{column}_0:4", real=True))
        steps += list(zip(running, total + sign * k[:, column], strict=True))
        total = running
    norm = sp.Symbol("quaternion_sum_norm", positive=True)
    steps.append((norm, sp.sqrt(total.dot(total))))
    return steps + [(q, total[j] / norm) for j, q in enumerate(quaternion)]
