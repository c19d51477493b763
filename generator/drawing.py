"""What a drawing's parts are, for the manifest: the runtime draws from these and infers nothing.

A drawing (``model.Drawing``) names point sets and polylines through them. Each polyline is one of
``PARTS``: the mechanism declares it (``Drawing.parts``), or its name says it (``PART_WORDS``:
base words first, so "base_platform" is the base), or it is the base when all its vertices are
fixed and a leg otherwise. A point set is fixed when its expressions hold no state variable
(actuated, passive or pose): a symbolic fact, not a sampled one.
"""

from __future__ import annotations

import re

import sympy as sp

from parakin.packages.manifest import DRAWING_PARTS as PARTS

from .errors import GenerationError
from .model import Drawing

#: words in a polyline's name that say its part, when the mechanism does not declare it
PART_WORDS = {
    "base": ("base", "ground", "fixed", "frame", "reference"),
    "platform": ("platform", "tool", "effector", "end", "moving"),
    "leg": ("leg", "link", "arm", "rail", "crank", "chain", "rod", "elbow", "strut"),
}


def part_of_name(name: str) -> str | None:
    """The part a name says, or None for a name that says none."""
    words = [w for w in re.split(r"[^a-z]+", name.lower()) if w]
    for part in ("base", "platform", "leg"):
        if any(word in PART_WORDS[part] for word in words):
            return part
    return None


def drawing_metadata(drawing: Drawing, state: set[sp.Symbol]) -> dict[str, object]:
    """The manifest's drawing: point sets (name -> columns), polylines, each polyline's part and
    the fixed point sets. Raises GenerationError for a declared part that is not one of PARTS or
    names no polyline."""
    unknown = {name: part for name, part in drawing.parts.items() if part not in PARTS or name not in drawing.polylines}
    if unknown:
        raise GenerationError(
            f"drawing parts {unknown}: each key must be a polyline ({', '.join(drawing.polylines)}) "
            f"and each value one of {', '.join(PARTS)}"
        )
    fixed = [name for name, matrix in drawing.points.items() if not (matrix.free_symbols & state)]
    parts = {}
    for name, line in drawing.polylines.items():
        declared = drawing.parts.get(name) or part_of_name(name)
        parts[name] = declared or ("base" if all(s in fixed for s, _ in line) else "leg")
    return {
        "points": {name: matrix.cols for name, matrix in drawing.points.items()},
        "polylines": {name: [[s, int(c)] for s, c in line] for name, line in drawing.polylines.items()},
        "parts": parts,
        "fixed": fixed,
    }
