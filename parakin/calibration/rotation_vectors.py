"""Rotation vectors for the tracker and tool frames: ``R = exp([r]x)`` (Rodrigues), its inverse,
and the analytic derivative dR/dr_i (G. Gallego and A. Yezzi, "A compact formula for the
derivative of a 3-D rotation in exponential coordinates", J. Math. Imaging Vis. 51, 2015, eq 9):

    dR/dr_i = (r_i [r]x + [r x (I - R) e_i]x) R / |r|^2,   and [e_i]x at r = 0.

A frame's six calibration parameters are (x, y, z, rx, ry, rz): its origin and its rotation
vector, in the frame it is placed in (the tracker in {B}, the tool in {P}).
"""

from __future__ import annotations

import numpy as np

from parakin.pose import axis_rotation, skew
from parakin.results import Array

#: below this |r| (rad) the derivative is taken at r = 0 ([e_i]x R, first order in |r|)
SMALL_ANGLE = 1e-9


def rotation(r: Array) -> Array:
    """exp([r]x) (3, 3) of a rotation vector r (3,) in rad (axis times angle)."""
    angle = float(np.linalg.norm(r))
    if angle < SMALL_ANGLE:
        return np.eye(3) + skew(r)
    return axis_rotation(r / angle, angle)


def rotation_vector(matrix: Array) -> Array:
    """The rotation vector r (3,) with exp([r]x) = matrix (3, 3), angle in [0, pi]."""
    cosine = np.clip((np.trace(matrix) - 1.0) / 2.0, -1.0, 1.0)
    angle = float(np.arccos(cosine))
    axis = np.array([matrix[2, 1] - matrix[1, 2], matrix[0, 2] - matrix[2, 0], matrix[1, 0] - matrix[0, 1]])
    if angle < 1e-6:
        return axis / 2.0
    if np.pi - angle < 1e-6:  # a half turn: the axis from the symmetric part
        symmetric = (matrix + np.eye(3)) / 2.0
        column = int(np.argmax(np.diag(symmetric)))
        u = symmetric[:, column] / np.sqrt(max(symmetric[column, column], 1e-300))
        return angle * u
    return angle * axis / (2.0 * np.sin(angle))


def rotation_derivatives(r: Array) -> Array:
    """dR/dr_i for i = 0, 1, 2, stacked (3, 3, 3) (first index i), at the rotation vector r."""
    matrix = rotation(r)
    squared = float(r @ r)
    basis = np.eye(3)
    if squared < SMALL_ANGLE**2:
        return np.stack([skew(basis[i]) @ matrix for i in range(3)])
    return np.stack(
        [(r[i] * skew(r) + skew(np.cross(r, (np.eye(3) - matrix) @ basis[i]))) @ matrix / squared for i in range(3)]
    )


def frame_values(transform: Array) -> Array:
    """(x, y, z, rx, ry, rz) of a rigid transform (4, 4)."""
    return np.concatenate([transform[:3, 3], rotation_vector(transform[:3, :3])])


def frame_transform(values: Array) -> Array:
    """The rigid transform (4, 4) of (x, y, z, rx, ry, rz)."""
    transform = np.eye(4)
    transform[:3, :3] = rotation(np.asarray(values[3:6], dtype=float))
    transform[:3, 3] = values[:3]
    return transform
