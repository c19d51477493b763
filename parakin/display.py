"""Tables for people: a mechanism and its results as text (``print``) and HTML (notebooks).

Every angle shown names its convention: poses as position (x, y, z) in metres and Z-Y-X Euler
angles (alpha about z, beta about y', gamma about x'', in degrees) of ^B_P R; revolute joint
values in degrees with the unit written. Modes are numbered 0 .. count - 1, as ``mode(k)``.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from parakin.pose import xyz_euler_deg_from_pose

if TYPE_CHECKING:
    from parakin.mechanism import Mechanism
    from parakin.results import AssemblyModes

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


def _number(value: float) -> str:
    return "inf" if np.isinf(value) and value > 0 else "-inf" if np.isinf(value) else f"{value:.6g}"


def _limits(low: float, high: float) -> str:
    return f"[{_number(low)}, {_number(high)}]"


def mechanism_sections(m: Mechanism) -> tuple[list[str], list[tuple[str, list[str], Rows]]]:
    """(heading lines, [(section title, headers, rows)]) describing ``m``."""
    manifest = m.manifest
    heading = [f"{manifest.name}: {manifest.title}", str(manifest.citation)]
    heading.append(f"pose kind {manifest.pose_kind}; backend {m.backend.name}")
    parameters = [[p.name, f"{m.parameters[p.name]:.6g}", p.unit, p.description] for p in manifest.parameters]
    sections = [("parameters", ["name", "value", "unit", "meaning"], parameters)]
    for title, variables in (("actuated", manifest.actuated), ("passive", manifest.passive)):
        rows = []
        for v in variables:
            home = "" if v.home is None else f"{v.home:.6g}"
            if v.kind == "revolute" and v.home is not None:
                home += f" ({np.degrees(v.home):.4g} deg)"
            rows.append([v.name, v.kind, v.unit or "1", home, _limits(*v.limits)])
        if rows:
            sections.append((f"{title} variables", ["name", "kind", "unit", "home", "limits"], rows))
    sections.append(("capabilities", ["capability", "what"], capability_rows(m)))
    examples = [[e.name, e.description if len(e.description) <= 90 else e.description[:87] + "..."]
                for e in manifest.examples]  # fmt: skip
    if examples:
        sections.append(("named examples (parakin demo)", ["name", "description"], examples))
    return heading, sections


def capability_rows(m: Mechanism) -> Rows:
    caps = m.capabilities
    rows = []
    if caps.inverse is not None:
        count = len(caps.inverse.combinations)
        rows.append(["inverse_pose", f"closed form, {count} branch{'es' if count != 1 else ''}"])
    for name, forward in caps.forward_methods.items():
        default = " (default)" if caps.forward is not None and forward is caps.forward else ""
        rows.append(
            [f"forward_pose_all method={name!r}{default}", f"{forward.degree * len(forward.combinations)} slots"]
        )
    if caps.rates is not None:
        constrained = f", {caps.rates.constraints} constraint wrenches" if caps.rates.constraints else ""
        rows.append(["rates and statics", f"A/B rate model over ({', '.join(caps.rates.twist)}){constrained}"])
    elif caps.legs is not None:
        rows.append(["rates and statics", f"{len(caps.legs)} serial leg Jacobians"])
    rows.append(["singularities", ", ".join(m.manifest.singularity_factors) or "none"])
    if caps.drawing is not None:
        rows.append(["plot", f"drawing of {len(caps.drawing.polylines)} polylines"])
    return rows


def mechanism_text(m: Mechanism) -> str:
    heading, sections = mechanism_sections(m)
    parts = list(heading)
    for title, headers, rows in sections:
        parts += ["", f"{title}:", text_table(headers, rows)]
    return "\n".join(parts)


def mechanism_html(m: Mechanism) -> str:
    heading, sections = mechanism_sections(m)
    out = [f"<h4>{html.escape(heading[0])}</h4>"] + [f"<p>{html.escape(line)}</p>" for line in heading[1:]]
    for title, headers, rows in sections:
        out += [f"<b>{html.escape(title)}</b>", html_table(headers, rows)]
    return "<div class='parakin'>" + "".join(out) + "</div>"


def modes_summary(modes: AssemblyModes) -> str:
    """One line: input batch, modes found, method, certificate."""
    count = np.asarray(modes.count)
    method = f" by {modes.method}" if modes.method else ""
    if count.ndim == 0:
        found = f"{int(count)} assembly mode{'s' if int(count) != 1 else ''}"
    else:
        found = f"a batch of {count.size} inputs, shape {count.shape}: {int(count.min())} to {int(count.max())} modes"
    certificate = ""
    if modes.certified_roots is not None and modes.root_count is not None:
        complete = (np.asarray(modes.certified_roots) == modes.root_count) & modes.root_count_proven
        if complete.all():
            certificate = "; certified complete"
        elif count.ndim == 0:  # one input: say how far the certificate got
            missing = int(modes.root_count) - int(modes.certified_roots)  # type: ignore[call-overload]
            certificate = (
                f"; not certified complete: {int(modes.certified_roots)} of {modes.root_count} roots "  # type: ignore[call-overload]
                f"certified, {missing} not (path_certified: which paths)"
                if modes.root_count_proven
                else "; not certified complete: the root count is not proven"
            )
        else:
            certificate = f"; certified complete for {int(complete.sum())} of {complete.size} inputs"
    return f"AssemblyModes: {found}{method}{certificate}"


def modes_rows(modes: AssemblyModes, residual: bool = False) -> Rows:
    """One row per mode of a single input: mode k (as ``modes.mode(k)``), pose, the closure
    residual (with ``residual``) and the conditioning."""
    valid = np.flatnonzero(np.asarray(modes.valid))
    poses = xyz_euler_deg_from_pose(modes.poses[valid]) if valid.size else np.zeros((0, 6))
    conditioning = np.asarray(modes.conditioning)[valid]
    residuals = np.asarray(modes.residual)[valid]
    return [
        [str(k), *(f"{v:.6g}" for v in pose), *([f"{r:.1e}"] if residual else []), f"{c:.3g}"]
        for k, (pose, r, c) in enumerate(zip(poses, residuals, conditioning, strict=True))
    ]


MODE_HEADERS = ["mode", *POSE_HEADERS, "conditioning"]
MODES_CONVENTION = f"{POSE_CONVENTION}; conditioning: 1 well conditioned, 0 singular"


def modes_table(modes: AssemblyModes, residual: bool = False, rows_shown: int = ROWS_SHOWN) -> str:
    """The convention line and the table of the modes of a single input (``modes_rows``)."""
    headers = MODE_HEADERS[:-1] + (["residual"] if residual else []) + MODE_HEADERS[-1:]
    return f"  {MODES_CONVENTION}\n" + text_table(headers, modes_rows(modes, residual), rows_shown=rows_shown)


def modes_text(modes: AssemblyModes) -> str:
    lines = [modes_summary(modes)]
    if np.ndim(modes.count) == 0 and int(modes.count):
        lines.append(modes_table(modes))
    elif np.ndim(modes.count):
        lines.append("  modes per input (count): " + np.array2string(np.asarray(modes.count), threshold=20))
    return "\n".join(lines)


def modes_html(modes: AssemblyModes) -> str:
    out = [f"<p><b>{html.escape(modes_summary(modes))}</b></p>"]
    if np.ndim(modes.count) == 0 and int(modes.count):
        out += [f"<p>{html.escape(POSE_CONVENTION)}</p>", html_table(MODE_HEADERS, modes_rows(modes))]
    return "<div class='parakin'>" + "".join(out) + "</div>"


__all__ = ["html_table", "mechanism_html", "mechanism_text", "modes_html", "modes_table", "modes_text", "text_table"]
