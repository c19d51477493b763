"""``parakin inspect NAME``: the symbolic model of a generated package, readable.

Needs SymPy (the ``generator`` extra). Text output prints each expression factored as the
generator named it, wrapped to a line width and cut after a number of lines, with a pointer to
the full expressions (``--format latex`` or ``--format json``).
"""

from __future__ import annotations

import json
import os
import textwrap
from typing import Any

from parakin.errors import UnsupportedOperationError
from parakin.subtrees import shared_subtrees


def _sympy() -> Any:
    try:
        import sympy
    except ImportError as error:
        raise UnsupportedOperationError("parakin inspect needs SymPy: pip install 'parakin[generator]'") from error
    return sympy


def _sections(manifest: Any, objects: dict[str, Any]) -> list[tuple[str, str]]:
    caps = manifest.capabilities
    sections = [("Loop-closure equations (residual = 0)", "loop_closure")]
    for leg in caps.legs or ():
        sections.append(
            (
                f"Leg Jacobian {leg.name} (columns {', '.join(leg.joints)}; (v, w) of {{P}} in {{B}})",
                f"leg_jacobian_{leg.name}",
            )
        )
    if caps.rates is not None:
        twist = ", ".join(caps.rates.twist)
        sections += [
            (f"A of A twist = B actuated_rates (twist {twist} in {{B}})", "rate_matrix_A"),
            ("B", "rate_matrix_B"),
        ]
    sections += [(f"Determinant {name}, factored", name) for name in manifest.determinants]
    if caps.architecture is not None:
        sections += [
            (f"Architecture measure {name} (parameters only; 0: singular at every pose)", f"architecture_{name}")
            for name in caps.architecture.measures
        ]
    sections += [
        (f"Singularity factor {name} (= 0 at the singularity)", f"factor_{name}")
        for name in manifest.singularity_factors
    ]
    for method, info in caps.forward_methods.items():
        if info.homotopy is not None:
            proof = info.homotopy.root_count
            proven = f", {proof.count} solutions proven by the {proof.method}" if proof else ""
            sections.append(
                (
                    f"Forward homotopy '{method}': {info.degree} paths through the equations{proven}",
                    f"{method}_equations",
                )
            )
        else:
            sections.append((f"Forward polynomial in {info.unknown}, degree {info.degree}", "forward_polynomial"))
    return [(title, key) for title, key in sections if key in objects]


#: expressions of more operations than this print with their repeated subexpressions named
SHARE_ABOVE = 400


def _text(sympy: Any, expr: Any, width: int, lines: int, name: str) -> str:
    operations = sympy.count_ops(expr)
    if operations < 40:
        return str(sympy.pretty(expr, num_columns=width))
    rows = [expr] if not isinstance(expr, sympy.MatrixBase) else list(expr)
    shared: list[tuple[Any, Any]] = []
    if operations > SHARE_ABOVE:
        # a repeated subtree printed once, by name (shared_k, defined below): a 6 x 6 determinant
        # written by Laplace expansion repeats its minors; printing it whole took seconds
        shared, rows = shared_subtrees(sympy, rows)
    out = _wrapped([(f"[{k}] " if len(rows) > 1 else "", row) for k, row in enumerate(rows)], width, lines, name)
    if shared:
        shown = shared[: 2 * lines]
        out += ["  where"] + _wrapped([(f"  {symbol} = ", value) for symbol, value in shown], width, lines, name)
        if len(shared) > len(shown):
            out.append(f"  ... {len(shared) - len(shown)} more (full: parakin inspect {name} --format latex|json)")
    return "\n".join(out)


def _wrapped(rows: list[tuple[str, Any]], width: int, lines: int, name: str) -> list[str]:
    out: list[str] = []
    for label, row in rows:
        wrapped = textwrap.wrap(label + str(row), width=width, break_long_words=True, subsequent_indent="    ")
        if len(wrapped) > lines:
            hidden = len(wrapped) - lines
            wrapped = wrapped[:lines] + [
                f"    ... {hidden} more lines (full: parakin inspect {name} --format latex|json)"
            ]
        out.extend(wrapped)
    return out


def inspect(name: str | os.PathLike[str], fmt: str = "text", width: int = 100, lines: int = 12) -> str:
    """The inspect report of a mechanism as text, LaTeX or JSON."""
    import parakin

    sympy = _sympy()
    manifest = parakin.metadata(name)
    objects = parakin.symbolic(name)
    if fmt == "json":
        return json.dumps({"manifest": manifest.name, "objects": {k: str(v) for k, v in objects.items()}}, indent=1)
    header = [
        manifest.title,
        f"citation: {manifest.citation}",
        "",
        "parameters: " + ", ".join(f"{p.name} = {p.default:g} {p.unit}".rstrip() for p in manifest.parameters),
        "actuated: " + ", ".join(f"{v.name} [{v.unit}]" for v in manifest.actuated),
        "passive: " + ", ".join(f"{v.name} [{v.unit}]" for v in manifest.passive),
        "",
    ]
    body = []
    for title, key in _sections(manifest, objects):
        shown = sympy.latex(objects[key]) if fmt == "latex" else _text(sympy, objects[key], width, lines, str(name))
        body.append(f"== {title}\n{shown}\n")
    return "\n".join(header + body)


__all__ = ["inspect"]
