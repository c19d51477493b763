"""Poses: 4x4 homogeneous transforms ^B_P T and the papers' {x, y, z, alpha, beta, gamma}.

Euler convention: Z-Y-X (Williams & Poling eq 2): R = Rot_z(alpha) Rot_y(beta) Rot_x(gamma).
Angles are radians; the ``*_deg`` helpers say so in their names. Every function broadcasts over
leading batch axes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from parakin.errors import BadInputError, at_index, first_index
from parakin.validation import as_array

Array = NDArray[np.float64]


#: how far from rigid (``rigidity_error``) a pose may be and still be read as rigid (then made exact)
RIGID_TOLERANCE = 1e-6


def as_pose(value: ArrayLike, name: str = "pose", tolerance: float = RIGID_TOLERANCE) -> Array:
    """A (..., 4, 4) rigid transform: checked for a proper rotation block and a [0 0 0 1] row
    (to ``tolerance``); a rotation block that is off by more than rounding is replaced by the
    nearest rotation (polar factor), so that solvers see an exact pose."""
    pose = as_array(value, name, (4, 4))
    orthogonality = rigidity_error(pose)
    if (orthogonality > tolerance).any():
        worst = float(orthogonality.max())
        raise BadInputError(f"{name} is not a rigid transform (|R^T R - I| = {worst:.3g}, last row must be 0 0 0 1)")
    if (np.linalg.det(pose[..., :3, :3]) < 0).any():
        raise BadInputError(f"{name} has a reflection (det R < 0), not a rotation")
    return nearest_rigid(pose, orthogonality)


def rigidity_error(pose: Array) -> Array:
    """How far (..., 4, 4) matrices are from rigid transforms: max-norm of R^T R - I and of the
    last row minus [0 0 0 1] (NaN propagates). A reflection (det R < 0) is not measured here."""
    rotation = pose[..., :3, :3]
    gram = np.einsum("...ji,...jk->...ik", rotation, rotation)
    orthogonality = np.abs(gram - np.eye(3)).max(axis=(-2, -1))
    return np.maximum(orthogonality, np.abs(pose[..., 3, :] - [0, 0, 0, 1]).max(-1))


def nearest_rigid(pose: Array, error: Array) -> Array:
    """``pose`` with the rotation block of every entry whose ``rigidity_error`` exceeds rounding
    replaced by the nearest proper rotation (polar factor, det +1) and its last row set to
    [0 0 0 1]."""
    inexact = np.asarray(error > 4 * np.finfo(float).eps)
    if not inexact.any():
        return pose
    rotation = pose[..., :3, :3]
    u, _, vt = np.linalg.svd(np.where(np.isfinite(rotation), rotation, 0.0))
    # a proper rotation (det +1) even where the block is far from one: flip the last singular axis
    u[..., :, 2] *= np.where(np.linalg.det(u @ vt) < 0, -1.0, 1.0)[..., None]
    pose = pose.copy()
    pose[..., :3, :3] = np.where(inexact[..., None, None], u @ vt, rotation)
    pose[..., 3, :] = np.where(inexact[..., None], [0.0, 0.0, 0.0, 1.0], pose[..., 3, :])
    return pose


def rigid_or_nan(pose: Array, keep: ArrayLike = False) -> tuple[Array, NDArray[np.bool_]]:
    """``(poses, rigid)`` of a pose kernel's output (..., 4, 4): ``rigid`` marks the entries that
    are rigid transforms to the pose-input tolerance (``RIGID_TOLERANCE``) with det R > 0. Those,
    and the entries marked in ``keep`` however far off they are, get the nearest rigid transform
    (``nearest_rigid``); every other entry is NaN, never a non-rigid matrix."""
    error = rigidity_error(pose)
    with np.errstate(invalid="ignore"):
        rigid = np.asarray((error <= RIGID_TOLERANCE) & (np.linalg.det(np.nan_to_num(pose[..., :3, :3])) > 0))
    made = rigid | np.asarray(keep)
    return np.where(made[..., None, None], nearest_rigid(pose, np.where(made, error, 0.0)), np.nan), rigid


def euler_zyx_to_rotation(alpha: ArrayLike, beta: ArrayLike, gamma: ArrayLike) -> Array:
    """R = Rot_z(alpha) Rot_y(beta) Rot_x(gamma): Z-Y-X Euler angles, eq (2) of Williams & Poling.

    Parameters
    ----------
    alpha, beta, gamma : array_like, broadcastable shapes (...)
        The angles about z, then the new y, then the new x (rad).

    Returns
    -------
    numpy.ndarray, shape (..., 3, 3)
        The rotation matrix of the frame turned by the angles, in the frame it was turned from.

    Raises
    ------
    BadInputError
        An angle not finite, or shapes that do not broadcast.

    Examples
    --------
    >>> import numpy as np
    >>> from parakin import euler_zyx_to_rotation
    >>> (euler_zyx_to_rotation(np.pi / 2, 0.0, 0.0).round(12) + 0.0).tolist()  # a quarter turn about z
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    angles = [as_array(x, n, ()) for x, n in ((alpha, "alpha"), (beta, "beta"), (gamma, "gamma"))]
    try:
        a, b, g = np.broadcast_arrays(*angles)
    except ValueError as error:
        raise BadInputError(f"alpha, beta, gamma do not broadcast: shapes {[x.shape for x in angles]}") from error
    ca, sa, cb, sb, cg, sg = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(g), np.sin(g)
    return np.stack(
        [
            np.stack([ca * cb, -sa * cg + ca * sb * sg, sa * sg + ca * sb * cg], -1),
            np.stack([sa * cb, ca * cg + sa * sb * sg, -ca * sg + sa * sb * cg], -1),
            np.stack([-sb, cb * sg, cb * cg], -1),
        ],
        -2,
    )


def pose_from_xyz_euler(xyz_euler: ArrayLike) -> Array:
    """^B_P T from positions and Z-Y-X Euler angles (eq 2).

    Parameters
    ----------
    xyz_euler : array_like, shape (..., 6)
        x, y, z of the origin of {P} in {B} (m), then alpha, beta, gamma (rad, Z-Y-X).

    Returns
    -------
    numpy.ndarray, shape (..., 4, 4)
        The homogeneous transform ^B_P T.

    Raises
    ------
    BadInputError
        Not six values per pose, or a value not finite.

    Examples
    --------
    >>> import numpy as np
    >>> from parakin import pose_from_xyz_euler
    >>> pose = pose_from_xyz_euler([0.1, 0.0, 0.5, np.pi / 2, 0.0, 0.0])
    >>> pose[:3, 3].tolist(), pose[:2, :2].round(12).tolist()
    ([0.1, 0.0, 0.5], [[0.0, -1.0], [1.0, 0.0]])
    """
    values = as_array(xyz_euler, "xyz_euler", (6,))
    pose = np.zeros(values.shape[:-1] + (4, 4))
    pose[..., :3, :3] = euler_zyx_to_rotation(values[..., 3], values[..., 4], values[..., 5])
    pose[..., :3, 3] = values[..., :3]
    pose[..., 3, 3] = 1.0
    return pose


def xyz_euler_from_pose(pose: ArrayLike) -> Array:
    """Positions and Z-Y-X Euler angles from ^B_P T, the inverse of ``pose_from_xyz_euler``.

    Beta lies in [-pi/2, pi/2]. At beta = +-pi/2 (gimbal lock) alpha is set to 0 and gamma
    absorbs the rest.

    Parameters
    ----------
    pose : array_like, shape (..., 4, 4)
        ^B_P T (metres), rigid.

    Returns
    -------
    numpy.ndarray, shape (..., 6)
        x, y, z (m), alpha, beta, gamma (rad).

    Raises
    ------
    BadInputError
        Not a rigid 4 x 4 transform, or a value not finite.

    Examples
    --------
    >>> from parakin import pose_from_xyz_euler, xyz_euler_from_pose
    >>> values = [0.1, -0.2, 0.5, 0.3, -0.4, 0.5]
    >>> xyz_euler_from_pose(pose_from_xyz_euler(values)).round(12).tolist()  # the round trip
    [0.1, -0.2, 0.5, 0.3, -0.4, 0.5]
    """
    transform = as_pose(pose)
    r = transform[..., :3, :3]
    beta = np.arctan2(-r[..., 2, 0], np.hypot(r[..., 0, 0], r[..., 1, 0]))
    locked = np.hypot(r[..., 0, 0], r[..., 1, 0]) < 1e-12
    alpha = np.where(locked, 0.0, np.arctan2(r[..., 1, 0], r[..., 0, 0]))
    gamma = np.where(
        locked,
        np.arctan2(-np.sign(r[..., 2, 0]) * r[..., 0, 1], r[..., 1, 1]),
        np.arctan2(r[..., 2, 1], r[..., 2, 2]),
    )
    return np.concatenate([transform[..., :3, 3], np.stack([alpha, beta, gamma], -1)], axis=-1)


def pose_from_xyz_euler_deg(xyz_euler_deg: ArrayLike) -> Array:
    """As ``pose_from_xyz_euler`` with the three angles in degrees (lengths still in metres).

    Parameters
    ----------
    xyz_euler_deg : array_like, shape (..., 6)
        x, y, z (m), then alpha, beta, gamma (degrees, Z-Y-X).

    Returns
    -------
    numpy.ndarray, shape (..., 4, 4)
        ^B_P T.

    Raises
    ------
    BadInputError
        Not six values per pose, or a value not finite.

    Examples
    --------
    >>> from parakin import pose_from_xyz_euler_deg
    >>> (pose_from_xyz_euler_deg([0, 0, 0.5, 0, 0, 90])[1:3, 1:3].round(12) + 0.0).tolist()  # 90 deg about x
    [[0.0, -1.0], [1.0, 0.0]]
    """
    values = as_array(xyz_euler_deg, "xyz_euler_deg", (6,)).copy()
    values[..., 3:] = np.deg2rad(values[..., 3:])
    return pose_from_xyz_euler(values)


def xyz_euler_deg_from_pose(pose: ArrayLike) -> Array:
    """As ``xyz_euler_from_pose`` with the three angles in degrees.

    Parameters
    ----------
    pose : array_like, shape (..., 4, 4)
        ^B_P T (metres), rigid.

    Returns
    -------
    numpy.ndarray, shape (..., 6)
        x, y, z (m), alpha, beta, gamma (degrees).

    Raises
    ------
    BadInputError
        Not a rigid 4 x 4 transform, or a value not finite.

    Examples
    --------
    >>> from parakin import pose_from_xyz_euler_deg, xyz_euler_deg_from_pose
    >>> xyz_euler_deg_from_pose(pose_from_xyz_euler_deg([0, 0, 0.5, 30, -20, 10])).round(9).tolist()
    [0.0, 0.0, 0.5, 30.0, -20.0, 10.0]
    """
    values = xyz_euler_from_pose(pose)
    values[..., 3:] = np.rad2deg(values[..., 3:])
    return values


def skew(v: Array) -> Array:
    """[v]x (3, 3) of a vector v (3,): [v]x u = v x u."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def axis_rotation(axis: Array, angle: float) -> Array:
    """The rotation (3, 3) by ``angle`` (rad) about the unit ``axis`` (3,) (Rodrigues)."""
    k = skew(axis)
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def pose_vector(pose: Array) -> Array:
    """(..., 12): r11..r33 then px, py, pz, the input layout of generated inverse kernels."""
    return np.concatenate([pose[..., :3, :3].reshape(pose.shape[:-2] + (9,)), pose[..., :3, 3]], axis=-1)


def wrap_angle(angle: ArrayLike) -> Array:
    """Angles mapped to (-pi, pi]."""
    wrapped = np.mod(np.asarray(angle, dtype=float) + np.pi, 2 * np.pi) - np.pi
    return np.where(wrapped == -np.pi, np.pi, wrapped)


#: twist components of a leg-based model (no A/B rate model): (v of the origin of {P}, w) in {B}
LEG_TWIST = ("vx", "vy", "vz", "wx", "wy", "wz")


#: pose kinds of the manifest and the short forms ``transform_from_pose`` accepts besides ^B_P T
@dataclass(frozen=True)
class PoseKind:
    """A manifest pose kind: the forms ``transform_from_pose`` accepts, and the coordinates a pose
    of the kind has (metres x y z; radians: Z-Y-X Euler alpha beta gamma, or the planar turn phi
    about z). The CLI's pose arguments and the sweep's pose axes are these coordinates."""

    forms: str
    coordinates: tuple[str, ...]

    def __str__(self) -> str:
        return self.forms


POSE_KINDS = {
    "transform": PoseKind("^B_P T (..., 4, 4)", ("x", "y", "z", "alpha", "beta", "gamma")),
    "rotation": PoseKind("^B_P T (..., 4, 4) or R (..., 3, 3)", ("alpha", "beta", "gamma")),
    "planar": PoseKind(
        "^B_P T (..., 4, 4) or (x, y, phi) (..., 3): rotation phi about z, in the plane z = 0", ("x", "y", "phi")
    ),
    "translation": PoseKind("^B_P T (..., 4, 4) or the position (x, y, z) (..., 3), with R = I", ("x", "y", "z")),
    "planar_translation": PoseKind(
        "^B_P T (..., 4, 4) or the position (x, y) (..., 2) in the plane z = 0, with R = I", ("x", "y")
    ),
}


def transform_from_pose(pose: ArrayLike, kind: str, name: str = "pose") -> Array:
    """^B_P T (..., 4, 4) from any pose form of a mechanism's pose kind (``POSE_KINDS``), checked
    to be a pose of that kind (BadInputError naming how far it is off)."""
    if kind not in POSE_KINDS:
        raise BadInputError(f"unknown pose kind {kind!r}; known: {sorted(POSE_KINDS)}")
    array = as_array_any(pose, name)
    if kind in ("rotation",) and array.shape[-2:] == (3, 3):
        full = np.zeros(array.shape[:-2] + (4, 4))
        full[..., :3, :3] = array
        full[..., 3, 3] = 1.0
        array = full
    elif kind in ("planar", "translation") and array.ndim >= 1 and array.shape[-1] == 3 and array.shape[-2:] != (3, 3):
        full = np.broadcast_to(np.eye(4), array.shape[:-1] + (4, 4)).copy()
        if kind == "planar":
            c, s = np.cos(array[..., 2]), np.sin(array[..., 2])
            full[..., 0, 0], full[..., 0, 1], full[..., 1, 0], full[..., 1, 1] = c, -s, s, c
            full[..., 0, 3], full[..., 1, 3] = array[..., 0], array[..., 1]
        else:
            full[..., :3, 3] = array
        array = full
    elif kind == "planar_translation" and array.ndim >= 1 and array.shape[-1] == 2:
        full = np.broadcast_to(np.eye(4), array.shape[:-1] + (4, 4)).copy()
        full[..., :2, 3] = array
        array = full
    if array.shape[-2:] != (4, 4):
        raise BadInputError(f"{name} must be {POSE_KINDS[kind]}, got shape {array.shape}")
    pose = as_pose(array, name)
    _check_kind(pose, kind, name)
    return pose


def _check_kind(pose: Array, kind: str, name: str, tolerance: float = 1e-6) -> None:
    """A pose a mechanism of this kind can take: an orienting platform has no translation, a
    translating one no rotation, a planar one moves in z = 0 about z, a planar translating one
    moves in z = 0 without rotation. ``measure`` in the message: max-norm of the offending part
    (metres for a translation, rotation-matrix entries for a rotation)."""
    rotation, translation = pose[..., :3, :3], pose[..., :3, 3]
    problems = {
        "rotation": (np.abs(translation).max(-1, initial=0.0), "a translation (an orienting platform has none)"),
        "translation": (
            np.abs(rotation - np.eye(3)).max(axis=(-2, -1)),
            "a rotation (a translating platform has none)",
        ),
        "planar": (
            np.maximum(np.abs(translation[..., 2]), np.abs(rotation[..., 2, :] - [0, 0, 1]).max(-1)),
            "motion out of the plane z = 0 (a planar platform translates in x, y and turns about z)",
        ),
        "planar_translation": (
            np.maximum(np.abs(translation[..., 2]), np.abs(rotation - np.eye(3)).max(axis=(-2, -1))),
            "a z offset or a rotation (a planar translating platform moves in x, y in the plane z = 0)",
        ),
        # a full rigid transform: as_pose has checked everything it can be
        "transform": (np.zeros(pose.shape[:-2]), ""),
    }
    measure, what = problems[kind]
    bad = ~(measure <= tolerance)
    if np.any(bad):
        index = first_index(bad)
        raise BadInputError(f"{name}{at_index(index)} has {what}: off by {float(np.asarray(measure)[index]):.3g}")


def as_array_any(value: ArrayLike, name: str) -> Array:
    """A finite real float array of any shape, or BadInputError."""
    return as_array(value, name, ())
