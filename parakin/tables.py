"""Tables for people, as text (``print``) and HTML (notebooks): what the reprs of a mechanism and
of its results are made of.

Every angle shown names its convention: poses as position (x, y, z) in metres and Z-Y-X Euler
angles (alpha about z, beta about y', gamma about x'', in degrees) of ^B_P R; revolute joint
values in degrees with the unit written. Modes are numbered 0 .. count - 1, as ``mode(k)``.
"""

from __future__ import annotations

import html
from collections.abc import Sequence

Rows = list[list[str]]
#: the convention of every pose column
POSE_HEADERS = ["x [m]", "y [m]", "z [m]", "alpha [deg]", "beta [deg]", "gamma [deg]"]
POSE_CONVENTION = "pose: position of the origin of {P} in {B}, Z-Y-X Euler angles (alpha, beta, gamma) of ^B_P R"
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


__all__ = ["POSE_CONVENTION", "POSE_HEADERS", "ROWS_SHOWN", "Rows", "html_table", "text_table"]
