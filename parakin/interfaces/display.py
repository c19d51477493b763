"""A mechanism as tables for people (``print(m)``, and HTML in notebooks): its parameters with
units, variables with kinds, units, home values and limits, capabilities and named examples.
Revolute home values are shown in degrees too, with the unit written (``parakin.tables``)."""

from __future__ import annotations

import html
from typing import TYPE_CHECKING

import numpy as np

from parakin.tables import Rows, html_table, text_table

if TYPE_CHECKING:
    from parakin.solvers.loaded import LoadedMechanism


def _number(value: float) -> str:
    return "inf" if np.isinf(value) and value > 0 else "-inf" if np.isinf(value) else f"{value:.6g}"


def _limits(low: float, high: float) -> str:
    return f"[{_number(low)}, {_number(high)}]"


def mechanism_sections(m: LoadedMechanism) -> tuple[list[str], list[tuple[str, list[str], Rows]]]:
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


def capability_rows(m: LoadedMechanism) -> Rows:
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


def mechanism_text(m: LoadedMechanism) -> str:
    heading, sections = mechanism_sections(m)
    parts = list(heading)
    for title, headers, rows in sections:
        parts += ["", f"{title}:", text_table(headers, rows)]
    return "\n".join(parts)


def mechanism_html(m: LoadedMechanism) -> str:
    heading, sections = mechanism_sections(m)
    out = [f"<h4>{html.escape(heading[0])}</h4>"] + [f"<p>{html.escape(line)}</p>" for line in heading[1:]]
    for title, headers, rows in sections:
        out += [f"<b>{html.escape(title)}</b>", html_table(headers, rows)]
    return "<div class='parakin'>" + "".join(out) + "</div>"


__all__ = ["mechanism_html", "mechanism_text"]
