"""Homogeneous transforms, Craig's modified Denavit-Hartenberg links and Z-Y-X Euler angles.

Conventions (Craig, *Introduction to Robotics*, 1989, the convention of all four papers' tables):
a modified-DH row (alpha_{i-1}, a_{i-1}, d_i, theta_i) gives
    ^{i-1}_i T = Rot_x(alpha_{i-1}) Trans_x(a_{i-1}) Rot_z(theta_i) Trans_z(d_i).
Z-Y-X Euler angles (alpha about Z, then beta about the new Y, then gamma about the new X) give
    R = Rot_z(alpha) Rot_y(beta) Rot_x(gamma), Williams & Poling eq (2).
"""

from __future__ import annotations

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
