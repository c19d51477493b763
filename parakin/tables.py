"""Tables for people, as text (``print``) and HTML (notebooks): what the reprs of a mechanism and
of its results are made of.

Every angle shown names its convention: poses as position (x, y, z) in metres and Z-Y-X Euler
angles (alpha about z, beta about y', gamma about x'', in degrees) of ^B_P R; revolute joint
values in degrees with the unit written. Modes are numbered 0 .. count - 1, as ``mode(k)``.
"""

from __future__ import annotations

import html
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from parakin.pose import POSE_KINDS, xyz_euler_from_pose

Rows = list[list[str]]
#: the convention of every pose column
POSE_HEADERS = ["x [m]", "y [m]", "z [m]", "alpha [deg]", "beta [deg]", "gamma [deg]"]
POSE_CONVENTION = "pose: position of the origin of {P} in {B}, Z-Y-X Euler angles (alpha, beta, gamma) of ^B_P R"
#: the unit of each pose coordinate (``parakin.pose.POSE_KINDS``): lengths in metres, angles in radians
_LENGTHS = ("x", "y", "z")


def pose_headers(kind: str, degrees: bool = True) -> list[str]:
    """The column headers of a pose of kind ``kind`` (``parakin.pose.POSE_KINDS``): only the
    coordinates the kind has (no z for a planar pose, no x, y, z for a rotation), each with its
    unit; angles in degrees with ``degrees``, else radians. An unknown kind (``""``) shows all
    six coordinates of a transform."""
    unit = "deg" if degrees else "rad"
    return [f"{c} [{'m' if c in _LENGTHS else unit}]" for c in pose_coordinates(kind)]


def pose_coordinates(kind: str) -> tuple[str, ...]:
    """The coordinate names of pose kind ``kind``; all six of a transform for an unknown kind."""
    return POSE_KINDS[kind].coordinates if kind in POSE_KINDS else POSE_KINDS["transform"].coordinates


def pose_values(kind: str, poses: ArrayLike, degrees: bool = True) -> NDArray[np.float64]:
    """The coordinates of ``poses`` ^B_P T (..., 4, 4) that pose kind ``kind`` has, as the columns
    ``pose_headers`` names: (..., n) with positions in metres and Z-Y-X Euler angles (phi, the
    planar turn about z, is alpha) in degrees with ``degrees``, else radians."""
    xyz_euler = xyz_euler_from_pose(poses)
    position = dict(zip(_LENGTHS, np.moveaxis(xyz_euler[..., :3], -1, 0), strict=True))
    angles = np.rad2deg(xyz_euler[..., 3:]) if degrees else xyz_euler[..., 3:]
    angle = dict(zip(("alpha", "beta", "gamma"), np.moveaxis(angles, -1, 0), strict=True)) | {"phi": angles[..., 0]}
    columns = [position[c] if c in _LENGTHS else angle[c] for c in pose_coordinates(kind)]
    return np.stack(columns, axis=-1) + 0.0  # + 0.0: no negative zero printed


def pose_convention(kind: str) -> str:
    """The convention line of a table of poses of kind ``kind``."""
    coordinates = pose_coordinates(kind)
    position = [c for c in coordinates if c in _LENGTHS]
    words = []
    if position:
        words.append(f"position ({', '.join(position)}) of the origin of {{P}} in {{B}}")
    if "phi" in coordinates:
        words.append("phi the turn of {P} about z")
    elif "alpha" in coordinates:
        words.append("Z-Y-X Euler angles (alpha, beta, gamma) of ^B_P R")
    if not position and "alpha" not in coordinates and "phi" not in coordinates:
        words.append("no rotation")
    elif "alpha" not in coordinates and "phi" not in coordinates:
        words.append("^B_P R = I")
    return "pose: " + ", ".join(words)


#: at most this many rows of a table are shown (the rest counted)
ROWS_SHOWN = 40


def text_table(headers: Sequence[str], rows: Rows, indent: str = "  ", rows_shown: int = ROWS_SHOWN) -> str:
    """Columns padded to their widest cell, a rule under the headers; rows past ``rows_shown`` are
    counted, not shown."""
    shown = rows[:rows_shown]
    widths = [max(len(str(c)) for c in column) for column in zip(headers, *shown, strict=True)]
    lines = ["  ".join(str(h).ljust(w) for h, w in zip(headers, widths, strict=True)).rstrip()]
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(str(c).ljust(w) for c, w in zip(row, widths, strict=True)).rstrip() for row in shown]
    if len(rows) > len(shown):
        lines.append(f"... {len(rows) - len(shown)} more rows")
    return "\n".join(indent + line for line in lines)


def html_table(headers: Sequence[str], rows: Rows) -> str:
    head = "".join(f"<th>{html.escape(str(h))}</th>" for h in headers)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in rows[:ROWS_SHOWN]
    )
    more = f"<p>... {len(rows) - ROWS_SHOWN} more rows</p>" if len(rows) > ROWS_SHOWN else ""
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>{more}"


__all__ = [
    "POSE_CONVENTION",
    "POSE_HEADERS",
    "ROWS_SHOWN",
    "Rows",
    "html_table",
    "pose_convention",
    "pose_coordinates",
    "pose_headers",
    "pose_values",
    "text_table",
]
