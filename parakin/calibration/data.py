"""Measurements for calibration (``CalibrationData``) and how each kind is predicted from the
model: the frames a tracker and a tool add, the residual of one measurement and its derivatives.

Frames (SI, radians): {B} and {P} are the mechanism's base and platform frames
(``m.manifest.conventions``). The instrument measures in its own frame {W} (a laser tracker, a
coordinate-measuring arm, a printer's bed), placed in {B} by ^B_W T (``tracker``); it sees a
target or probe {T} fixed on the platform, placed in {P} by ^P_T T (``tool``). Either may be
known (held at the value given) or unknown (six more parameters, ``tracker_x`` .. ``tracker_rz``,
``tool_x`` .. ``tool_rz``: origin and rotation vector, ``parakin.calibration.rotation_vectors``).

Kinds, their measurement per pose and their residual (prediction minus measurement, over sigma):

* ``"pose"``: ^W_T T (4, 4). Residual: the position error (3, m) over ``sigma[0]`` and the
  rotation error (3, rad) over ``sigma[1]``: vee of the skew part of R_meas^T R_pred (the
  rotation vector of the error, in {T}, to second order).
* ``"position"``: the origin of {T} in {W} (3,), m. Residual (3,) over sigma.
* ``"z"``: the height of the origin of {T} along the z axis of {W} (scalar, m): a probe touching a
  bed, whose height and tilt are ``tracker_z``, ``tracker_rx``, ``tracker_ry``.
* ``"distance"``: the distance (m) from the origin of {W} (a ball bar's or a string
  potentiometer's fixed pivot) to the origin of {T}.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from parakin.calibration.rotation_vectors import frame_values, rotation_derivatives
from parakin.errors import BadInputError, CalibrationDataError
from parakin.pose import as_pose, skew
from parakin.results import Array
from parakin.validation import as_array

KINDS = ("pose", "position", "z", "distance")
#: residual components per measurement of each kind
SIZES = {"pose": 6, "position": 3, "z": 1, "distance": 1}
#: the measurement's trailing shape per kind
SHAPES: dict[str, tuple[int, ...]] = {"pose": (4, 4), "position": (3,), "z": (), "distance": ()}
FRAME_COORDINATES = ("x", "y", "z", "rx", "ry", "rz")
#: the frame parameters an unknown frame frees by default, per kind (the others cannot change
#: that kind's measurement, or change it only together with these)
UNKNOWN_FRAME: dict[str, dict[str, tuple[str, ...]]] = {
    "pose": {"tracker": FRAME_COORDINATES, "tool": FRAME_COORDINATES},
    "position": {"tracker": FRAME_COORDINATES, "tool": ("x", "y", "z")},
    "z": {"tracker": ("z", "rx", "ry"), "tool": ("x", "y", "z")},
    "distance": {"tracker": ("x", "y", "z"), "tool": ("x", "y", "z")},
}


def frame_names(frame: str) -> list[str]:
    """The six parameter names of ``frame`` ('tracker' or 'tool')."""
    return [f"{frame}_{c}" for c in FRAME_COORDINATES]


@dataclass(frozen=True)
class CalibrationData:
    """Measurements of a calibration campaign: N poses, each the actuated joints as read and
    what the instrument measured there.

    Parameters
    ----------
    actuated : array_like, (N, n_a)
        The actuated joint values as read by the encoders (m or rad), in ``m.actuated_names``
        order. The model's joint is ``scale * reading + offset`` (parameters ``<name>_offset``,
        default 0, and ``<name>_scale``, default 1).
    measured : array_like
        Per pose: (N, 4, 4) for ``kind="pose"``, (N, 3) for ``"position"``, (N,) for ``"z"`` and
        ``"distance"`` (module docstring: frames and meaning).
    kind : str
        ``"pose"``, ``"position"``, ``"z"`` or ``"distance"``.
    sigma : float or (float, float)
        Standard deviation of the measurement noise: metres; for ``"pose"`` a pair (position m,
        rotation rad) or one number for both.
    tracker, tool : array_like (4, 4), optional
        ^B_W T and ^P_T T: known values, or the starting values of unknown frames (default
        identity).
    unknown : sequence of str
        Which frames are unknown: any of ``"tracker"``, ``"tool"``.
    passive : array_like (N, n_p), optional
        Starting passive values (default: the forward pose of the nominal model, seeded by the
        measured pose where it is complete).

    Raises
    ------
    CalibrationDataError
        A shape that does not match the kind, a non-positive sigma, an unknown kind or frame name.

    Examples
    --------
    Positions of a delta's platform seen by a laser tracker placed at an unknown pose: the
    readings are the encoders' values there (here the drawing's own inverse, branch 0).

    >>> import parakin
    >>> from parakin.calibration import CalibrationData
    >>> m = parakin.load("delta", backend="numpy")
    >>> points = m.home_passive + [[0.0, 0.0, 0.0], [0.05, 0.0, 0.0], [0.0, 0.05, 0.0], [0.0, 0.0, -0.05]]
    >>> readings = m.inverse_pose(points).actuated[:, 0]
    >>> data = CalibrationData(readings, points, kind="position", sigma=20e-6, unknown=["tracker"])
    >>> len(data), data.size, data.sigma
    (4, 3, (2e-05, 2e-05))
    >>> CalibrationData(readings, points[:3], kind="position")
    Traceback (most recent call last):
    ...
    parakin.errors.CalibrationDataError: measured must have shape (4, 3) for kind 'position' and 4 poses, got (3, 3)
    """

    actuated: Array
    measured: Array
    kind: str = "pose"
    sigma: tuple[float, float] = (1e-5, 1e-5)
    tracker: Array = field(default_factory=lambda: np.eye(4))
    tool: Array = field(default_factory=lambda: np.eye(4))
    unknown: tuple[str, ...] = ()
    passive: Array | None = None

    def __init__(
        self,
        actuated: ArrayLike,
        measured: ArrayLike,
        kind: str = "pose",
        sigma: float | Sequence[float] = 1e-5,
        tracker: ArrayLike | None = None,
        tool: ArrayLike | None = None,
        unknown: Sequence[str] = (),
        passive: ArrayLike | None = None,
    ) -> None:
        if kind not in KINDS:
            raise CalibrationDataError(f"kind must be one of {KINDS}, got {kind!r}")
        try:
            theta = as_array(actuated, "actuated", ())
            if theta.ndim != 2 or theta.shape[0] < 1:
                raise CalibrationDataError(f"actuated must have shape (N, n_a) with N >= 1, got {theta.shape}")
            values = as_array(measured, "measured", SHAPES[kind])
            if values.shape != (theta.shape[0], *SHAPES[kind]):
                raise CalibrationDataError(
                    f"measured must have shape {(theta.shape[0], *SHAPES[kind])} for kind {kind!r} and "
                    f"{theta.shape[0]} poses, got {values.shape}"
                )
            if kind == "pose":
                values = as_pose(values, "measured")
            frames = [
                as_pose(np.eye(4) if f is None else f, name) for f, name in ((tracker, "tracker"), (tool, "tool"))
            ]
            if frames[0].shape != (4, 4) or frames[1].shape != (4, 4):
                raise CalibrationDataError("tracker and tool must each be one (4, 4) transform")
            start = None if passive is None else as_array(passive, "passive", ())
        except CalibrationDataError:
            raise
        except BadInputError as error:
            raise CalibrationDataError(str(error)) from error
        if start is not None and (start.ndim != 2 or start.shape[0] != theta.shape[0]):
            raise CalibrationDataError(f"passive must have shape ({theta.shape[0]}, n_p), got {start.shape}")
        spread = np.atleast_1d(np.asarray(sigma, dtype=float)).ravel()
        if spread.size not in (1, 2) or (spread.size == 2 and kind != "pose"):
            raise CalibrationDataError(f"sigma must be one number (or two for kind 'pose'), got {sigma!r}")
        if not (np.isfinite(spread).all() and (spread > 0).all()):
            raise CalibrationDataError(f"sigma must be positive and finite, got {sigma!r}")
        names = tuple(unknown)
        for name in names:
            if name not in ("tracker", "tool"):
                raise CalibrationDataError(f"unknown frames are 'tracker' and 'tool', got {name!r}")
        object.__setattr__(self, "actuated", theta)
        object.__setattr__(self, "measured", values)
        object.__setattr__(self, "kind", kind)
        object.__setattr__(self, "sigma", (float(spread[0]), float(spread[-1])))
        object.__setattr__(self, "tracker", frames[0])
        object.__setattr__(self, "tool", frames[1])
        object.__setattr__(self, "unknown", names)
        object.__setattr__(self, "passive", start)

    def __len__(self) -> int:
        return int(self.actuated.shape[0])

    @property
    def size(self) -> int:
        """Residual components per pose (6, 3 or 1)."""
        return SIZES[self.kind]

    def frame_values(self) -> dict[str, float]:
        """The starting values of the twelve frame parameters (tracker then tool).

        Returns
        -------
        dict of str to float
            ``tracker_x``, ``tracker_y``, ``tracker_z`` (m: the origin of {W} in {B}),
            ``tracker_rx``, ``tracker_ry``, ``tracker_rz`` (rad: the rotation vector of ^B_W R),
            then the same six of ``tool`` (^P_T T); the calibration's starting values for unknown
            frames, its held values for known ones.

        Examples
        --------
        >>> import numpy as np
        >>> from parakin.calibration import CalibrationData
        >>> tracker = np.eye(4)
        >>> tracker[:3, 3] = [1.5, 0.0, 0.25]  # the tracker 1.5 m along x of {B}, 0.25 m up
        >>> data = CalibrationData([[0.1, 0.2, 0.3]], [[0.0, 0.0, -1.0]], kind="position", tracker=tracker)
        >>> {name: value for name, value in data.frame_values().items() if value}
        {'tracker_x': 1.5, 'tracker_z': 0.25}
        """
        values = np.concatenate([frame_values(self.tracker), frame_values(self.tool)])
        return dict(zip(frame_names("tracker") + frame_names("tool"), (float(v) for v in values), strict=True))

    def free_frames(self) -> list[str]:
        """The frame parameters an unknown frame frees for this kind (``UNKNOWN_FRAME``): the
        ones that change this kind's measurement independently (a position does not see the
        tool's rotation; a height sees only the tracker's z and its tilt).

        Returns
        -------
        list of str
            Names as in ``frame_values``, tracker first; empty when both frames are known.

        Examples
        --------
        >>> from parakin.calibration import CalibrationData
        >>> data = CalibrationData([[0.1, 0.2, 0.3]], [-1.0], kind="z", unknown=["tracker", "tool"])
        >>> data.free_frames()
        ['tracker_z', 'tracker_rx', 'tracker_ry', 'tool_x', 'tool_y', 'tool_z']
        """
        return [f"{frame}_{c}" for frame in self.unknown for c in UNKNOWN_FRAME[self.kind][frame]]

    def subset(self, rows: ArrayLike) -> CalibrationData:
        """The measurements at ``rows`` (indices or a mask), same kind, sigma and frames: a
        campaign split into the poses that calibrate and the poses held out to check it.

        Parameters
        ----------
        rows : array_like of int, shape (k,), or of bool, shape (N,)
            Indices of the poses to keep (in this order, repeats allowed), or a mask over all N.

        Returns
        -------
        CalibrationData
            The k poses' readings, measurements and starting passive joints (if given).

        Raises
        ------
        CalibrationDataError
            ``rows`` selects no pose.
        IndexError
            An index out of range, a mask of another length than N, or a float index (NumPy's
            indexing error, with the sizes).

        Examples
        --------
        >>> import numpy as np
        >>> from parakin.calibration import CalibrationData
        >>> data = CalibrationData(np.zeros((5, 3)), np.arange(5.0), kind="distance", sigma=1e-5)
        >>> fit, held_out = data.subset([0, 1, 2]), data.subset(np.arange(5) >= 3)
        >>> len(fit), held_out.measured.tolist(), held_out.sigma
        (3, [3.0, 4.0], (1e-05, 1e-05))
        """
        index = np.asarray(rows)
        return CalibrationData(
            self.actuated[index],
            self.measured[index],
            self.kind,
            self.sigma if self.kind == "pose" else self.sigma[0],
            self.tracker,
            self.tool,
            self.unknown,
            None if self.passive is None else self.passive[index],
        )


# ---------------------------------------------------------------- prediction and its derivatives
def predict(
    platform: Array, tracker: Array, tool: Array, derivatives: bool = True
) -> tuple[Array, Array, Array, Array]:
    """The instrument's view ^W_T T = (^B_W T)^-1 ^B_P T ^P_T T of N platform poses.

    Parameters
    ----------
    platform : (N, 3, 4)
        ^B_P T, its top three rows.
    tracker, tool : (6,)
        (x, y, z, rx, ry, rz) of ^B_W T and ^P_T T.

    Returns
    -------
    y : (N, 12)
        The predicted position (3) then rotation (9, row-major) of {T} in {W}.
    d_platform : (N, 12, 12)
        dy / d(the 12 platform entries, row-major 3 x 4).
    d_tracker, d_tool : (N, 12, 6)
        dy / d(tracker values), dy / d(tool values).
    """
    from parakin.calibration.rotation_vectors import rotation

    n = platform.shape[0]
    r_x, t_x = rotation(tracker[3:]), tracker[:3]
    r_y, t_y = rotation(tool[3:]), tool[:3]
    r_p, t_p = platform[:, :, :3], platform[:, :, 3]
    point = r_p @ t_y + t_p - t_x  # the tool's origin from the tracker's, in {B}
    position = point @ r_x  # R_X^T point
    orientation = np.einsum("ia,nik,kb->nab", r_x, r_p, r_y)
    y = np.concatenate([position, orientation.reshape(n, 9)], axis=1)
    if not derivatives:
        empty = np.zeros((0,))
        return y, empty, empty, empty
    augmented = np.append(t_y, 1.0)
    d_platform = np.zeros((n, 12, 3, 4))
    d_platform[:, :3] = np.einsum("ia,k->aik", r_x, augmented)[None]
    rotation_part = np.einsum("ia,kb->abik", r_x, r_y).reshape(9, 3, 3)
    d_platform[:, 3:, :, :3] = rotation_part[None]
    d_tracker = np.zeros((n, 12, 6))
    d_tracker[:, :3, :3] = -r_x.T
    for i, d_r in enumerate(rotation_derivatives(tracker[3:])):
        d_tracker[:, :3, 3 + i] = point @ d_r
        d_tracker[:, 3:, 3 + i] = np.einsum("ia,nik,kb->nab", d_r, r_p, r_y).reshape(n, 9)
    d_tool = np.zeros((n, 12, 6))
    d_tool[:, :3, :3] = np.einsum("ia,nik->nak", r_x, r_p)
    for i, d_r in enumerate(rotation_derivatives(tool[3:])):
        d_tool[:, 3:, 3 + i] = np.einsum("ia,nik,kb->nab", r_x, r_p, d_r).reshape(n, 9)
    return y, d_platform.reshape(n, 12, 12), d_tracker, d_tool


def residual(data: CalibrationData, y: Array) -> tuple[Array, Array]:
    """Whitened residuals (N, s) of predictions y (N, 12) (``predict``) against the data, and
    their derivative (N, s, 12) with respect to y (module docstring: one formula per kind)."""
    n = y.shape[0]
    sigma_position, sigma_angle = data.sigma
    position = y[:, :3]
    if data.kind == "pose":
        measured = data.measured[:, :3, :3]
        orientation = y[:, 3:].reshape(n, 3, 3)
        product = np.einsum("nau,nav->nuv", measured, orientation)  # R_meas^T R_pred
        pairs = ((2, 1), (0, 2), (1, 0))  # vee of a skew matrix S: (S21, S02, S10)
        angle = np.stack([0.5 * (product[:, u, v] - product[:, v, u]) for u, v in pairs], axis=1)
        out = np.concatenate(
            [(position - data.measured[:, :3, 3]) / sigma_position, angle / sigma_angle],
            axis=1,
        )
        derivative = np.zeros((n, 6, 12))
        derivative[:, :3, :3] = np.eye(3) / sigma_position
        for c, (u, v) in enumerate(pairs):
            block = np.zeros((n, 3, 3))
            block[:, :, v] += 0.5 * measured[:, :, u]
            block[:, :, u] -= 0.5 * measured[:, :, v]
            derivative[:, 3 + c, 3:] = block.reshape(n, 9) / sigma_angle
        return out, derivative
    if data.kind == "position":
        derivative = np.zeros((n, 3, 12))
        derivative[:, :, :3] = np.eye(3) / sigma_position
        return (position - data.measured) / sigma_position, derivative
    if data.kind == "z":
        derivative = np.zeros((n, 1, 12))
        derivative[:, 0, 2] = 1.0 / sigma_position
        return ((position[:, 2] - data.measured) / sigma_position)[:, None], derivative
    distance = np.linalg.norm(position, axis=1)
    derivative = np.zeros((n, 1, 12))
    derivative[:, 0, :3] = position / np.maximum(distance, 1e-300)[:, None] / sigma_position
    return ((distance - data.measured) / sigma_position)[:, None], derivative


def residual_in_units(data: CalibrationData, whitened: Array) -> dict[str, Array]:
    """Whitened residuals (N, s) back in measurement units: {'position': (N, 3) m,
    'angle': (N, 3) rad} for poses, {'position': (N, 3)} for positions, {'z': (N,)} or
    {'distance': (N,)} for scalars."""
    sigma_position, sigma_angle = data.sigma
    if data.kind == "pose":
        return {"position": whitened[:, :3] * sigma_position, "angle": whitened[:, 3:] * sigma_angle}
    if data.kind == "position":
        return {"position": whitened * sigma_position}
    return {data.kind: whitened[:, 0] * sigma_position}


__all__ = ["KINDS", "CalibrationData", "frame_names", "predict", "residual", "skew"]
