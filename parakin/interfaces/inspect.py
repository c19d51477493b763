"""``parakin inspect NAME``: the symbolic model of a generated package, readable.

Needs SymPy (the ``generator`` extra). Three formats of one report:

* ``text`` (the default): the header gives the parameters one per line (value, unit and meaning),
  the variables with their home values (the home configuration: SI units, a revolute one also
  in degrees; a value below ``NOISE`` = 1e-12 times its unit's scale, the largest magnitude
  among the parameters and home values in that unit and at least 1, is rounding noise and
  prints as 0, a note naming it) and the platform's
  motion (the generator's screw analysis, ``manifest.joints.motion.text``: for a lower-mobility
  mechanism the coordinates the actuators control and the parasitic ones that follow); then each
  object as the generator named it; a matrix as a grid with its rows
  and columns labelled (the equation, the variable), or entry by entry with (row, column) labels
  where an entry is too long for a grid; large expressions with their repeated subexpressions
  named (``shared_k``, defined below them); lines wrapped to ``width`` and cut after ``lines``
  lines, with a pointer to the full expressions (``--format latex`` or ``--format json``). Every
  symbol that is not a variable or a parameter is defined: by a step printed in the report
  (inverse steps, forward auxiliaries) or in the "other symbols" list (pose inputs, branch signs,
  the unknowns of the forward methods).
* ``latex``: one complete document (``pdflatex`` compiles it: amsmath and geometry only); the
  repeated subexpressions of the whole report are named once (``s_k``), each where it is first
  needed; long expressions are inline math, which breaks after + and -.
* ``json``: one object, described by this schema (schema ``"parakin.interfaces.inspect/1"``)::

    {
      "schema": "parakin.interfaces.inspect/1",
      "manifest": NAME, "title": TEXT, "citation": TEXT,
      "motion": TEXT | null (the platform's motion, the manifest's joints.motion.text),
      "symbols": {DISPLAY: {
          "name": SYMPY_NAME, "assumptions": {"real": true, ...},
          "kind": "actuated" | "passive" | "parameter" | "defined" | "input" | "branch"
                  | "unknown" | "family" | "other",
          "description": TEXT, "unit": TEXT (variables, parameters), "value": NUMBER (parameters),
          "home": NUMBER (variables: the home configuration, SI)}},
      "shared": [[DISPLAY, VALUE], ...],
      "objects": {KEY: OBJECT},
      "sections": [{"title": TEXT, "object": KEY}, ...]
    }

  where OBJECT is one of ``{"kind": "expression", "value": VALUE}``, ``{"kind": "matrix",
  "shape": [r, c], "rows": [LABEL] * r, "columns": [LABEL] * c, "entries": [[VALUE] * c] * r}``
  or ``{"kind": "definitions", "steps": [[DISPLAY, VALUE], ...]}`` (assignments in order: the
  inverse steps, the forward auxiliaries). A VALUE is ``str`` of a SymPy expression written with
  the display names of ``symbols`` and the names of ``shared`` (plain symbols ``shared_k``), in
  order, each using only earlier ones. Read back exactly (``==`` the objects of
  ``parakin.symbolic(NAME)``)::

    names = {d: sympy.Symbol(s["name"], **s["assumptions"]) for d, s in data["symbols"].items()}
    shared = {}
    for display, value in data["shared"]:
        shared[sympy.Symbol(display)] = sympy.parse_expr(value, local_dict=names).xreplace(shared)
    expression = sympy.parse_expr(VALUE, local_dict=names).xreplace(shared)

  (``xreplace``, not the full expressions in ``local_dict``: ``-shared_0*z`` must stay
  ``Mul(-1, shared_0, z)``, where ``-(a + b)*z`` would distribute the sign.)

  A display name is the SymPy name, except where two different symbols share a name (e.g. a
  parameter ``b12`` and a forward auxiliary ``b12``): the one that is not a variable or a
  parameter gets a suffix (``b12_fwd``) in every format.
"""

from __future__ import annotations

import json
import math
import os
import re
import textwrap
from dataclasses import dataclass, field
from typing import Any

from parakin.errors import UnsupportedOperationError
from parakin.packages.subtrees import shared_subtrees

#: expressions of more nodes than this print with their repeated subexpressions named
SHARE_ABOVE = 400
#: the pose entries an inverse program reads (the generator's ``POSE_SYMBOLS``)
POSE_INPUTS = ("r11", "r12", "r13", "r21", "r22", "r23", "r31", "r32", "r33", "px", "py", "pz")
#: objects whose symbols lose a name clash (not variables or parameters), with their suffix
_TAGS = {
    "automatic_equations": "auto",
    "homotopy_equations": "hom",
    "forward_polynomial": "fwd",
    "forward_auxiliary": "fwd",
    "inverse_steps": "inv",
}
_MORE = "full: parakin inspect {name} --format latex|json"


def _sympy() -> Any:
    try:
        import sympy
    except ImportError as error:
        raise UnsupportedOperationError("parakin inspect needs SymPy: pip install 'parakin[generator]'") from error
    return sympy


@dataclass
class _Section:
    """One printed object: an expression, a matrix (rows and columns labelled) or steps."""

    title: str
    key: str
    rows: list[str] = field(default_factory=list)
    columns: list[str] = field(default_factory=list)


@dataclass
class _Entry:
    """A symbol of the report: what it is, by display name."""

    symbol: Any
    kind: str
    description: str
    unit: str | None = None
    value: float | None = None
    #: a variable's home value (SI: m, rad; a quaternion component has no unit), None if none
    home: float | None = None
    #: the symbol of ``parakin.symbolic`` (``symbol`` under another name where two share one)
    original: Any = None


@dataclass
class _Report:
    manifest: Any
    objects: dict[str, Any]
    sections: list[_Section]
    symbols: dict[str, _Entry]


def _indices(count: int) -> list[str]:
    return [str(k) for k in range(count)]


def _sections(manifest: Any, objects: dict[str, Any]) -> list[_Section]:
    """The printed objects in reading order, with their titles and matrix labels."""
    caps = manifest.capabilities
    actuated = [v.name for v in manifest.actuated]
    sections = [
        _Section("Platform pose ^B_P T in the passive variables", "platform_pose", _indices(4), _indices(4)),
        _Section("Loop-closure equations (residual = 0)", "loop_closure"),
    ]
    for leg in caps.legs or ():
        twist = ["vx", "vy", "vz", "wx", "wy", "wz"]
        sections.append(
            _Section(
                f"Leg Jacobian {leg.name} (columns {', '.join(leg.joints)}; (v, w) of {{P}} in {{B}})",
                f"leg_jacobian_{leg.name}",
                twist,
                list(leg.joints),
            )
        )
    if caps.rates is not None:
        twist = list(caps.rates.twist)
        sections += [
            _Section(
                f"A of A twist = B actuated_rates (rows: equations; columns: twist {', '.join(twist)} in {{B}})",
                "rate_matrix_A",
                columns=twist,
            ),
            _Section("B (columns: the actuated rates)", "rate_matrix_B", columns=actuated),
            _Section(
                "Constraint wrenches C (C twist = 0 for every motion the platform can make)",
                "constraint_wrenches",
                columns=twist,
            ),
        ]
    sections += [_Section(f"Determinant {name}, factored", name) for name in manifest.determinants]
    if caps.architecture is not None:
        sections += [
            _Section(
                f"Architecture measure {name} (parameters only; 0: singular at every pose)", f"architecture_{name}"
            )
            for name in caps.architecture.measures
        ]
    sections += [
        _Section(f"Singularity factor {name} (= 0 at the singularity)", f"factor_{name}")
        for name in manifest.singularity_factors
    ]
    if caps.inverse is not None:
        signs = f"; branch signs {', '.join(caps.inverse.branches)} = +1 or -1" if caps.inverse.branches else ""
        sections.append(
            _Section(
                f"Inverse kinematics, in order: from the pose (r11..r33, px, py, pz of ^B_P T){signs}",
                "inverse_steps",
            )
        )
    for method, info in caps.forward_methods.items():
        if info.homotopy is not None:
            proof = info.homotopy.root_count
            proven = f", {proof.count} solutions proven by the {proof.method}" if proof else ""
            title = f"Forward homotopy '{method}': {info.degree} paths through the equations{proven}"
            sections.append(_Section(title, f"{method}_equations"))
        else:
            sections.append(
                _Section(f"Forward polynomial in {info.unknown}, degree {info.degree}", "forward_polynomial")
            )
            sections.append(
                _Section(
                    "Forward auxiliaries (the polynomial's coefficients; the pose from a root)", "forward_auxiliary"
                )
            )
    known = {s.key for s in sections}
    sections += [_Section(f"Other derived object {key}", key) for key in objects if key not in known]
    for section in sections:
        value = objects.get(section.key)
        if value is not None and _is_matrix(value):
            rows, columns = value.shape
            section.rows = section.rows if len(section.rows) == rows else _indices(rows)
            section.columns = section.columns if len(section.columns) == columns else _indices(columns)
    return [s for s in sections if s.key in objects]


def _is_matrix(value: Any) -> bool:
    return hasattr(value, "shape") and hasattr(value, "tolist")


def _is_steps(value: Any) -> bool:
    return isinstance(value, tuple) or type(value).__name__ == "Tuple"


def _expressions(value: Any) -> list[Any]:
    """Every expression an object prints: matrix entries, step values (and targets), itself."""
    if _is_matrix(value):
        return list(value)
    if _is_steps(value):
        return [part for step in value for part in step]
    return [value]


def _display_names(sympy: Any, manifest: Any, objects: dict[str, Any], sections: list[_Section]) -> dict[Any, str]:
    """A unique display name per symbol: its own, except where another symbol of that name came
    first (variables and parameters first, then the model, forward, and inverse objects)."""
    reserved = {v.name for v in (*manifest.actuated, *manifest.passive)} | {p.name for p in manifest.parameters}
    order = [s.key for s in sections if s.key not in _TAGS] + [k for k in _TAGS if k in objects]
    symbols: list[tuple[Any, str]] = []
    for key in order:
        for expression in _expressions(objects[key]):
            symbols += [(s, key) for s in sorted(expression.free_symbols, key=str)]
    names: dict[Any, str] = {}
    taken: set[str] = set()
    for symbol, _key in symbols:  # variables and parameters keep their names
        if symbol.name in reserved and symbol.name not in taken:
            names[symbol] = symbol.name
            taken.add(symbol.name)
    for symbol, key in symbols:
        if symbol in names:
            continue
        name, k = symbol.name, 1
        while name in taken or name in reserved:
            name = f"{symbol.name}_{_TAGS.get(key, 'other')}" + (str(k) if k > 1 else "")
            k += 1
        names[symbol] = name
        taken.add(name)
    return names


def _notes(name: str | os.PathLike[str]) -> dict[str, list[str]]:
    """The generator's notes on each forward method's unknowns and family parameters."""
    from parakin.packages.package import GeneratedPackage

    try:
        data = json.loads((GeneratedPackage.find(name).path / "manifest.json").read_text())
        methods = data["capabilities"]["forward"]["methods"]
        return {method: list(info.get("notes", [])) for method, info in methods.items()}
    except (OSError, KeyError, TypeError, ValueError):
        return {}


def _glossary(manifest: Any, notes: dict[str, list[str]], objects: dict[str, Any]) -> dict[str, tuple[str, str]]:
    """(kind, description) of every name the manifest, the notes and the steps explain."""
    caps = manifest.capabilities
    out: dict[str, tuple[str, str]] = {}
    for name in POSE_INPUTS:
        out[name] = ("input", "entry of the pose ^B_P T = [[r11 r12 r13 px] [r21 r22 r23 py] [r31 r32 r33 pz]]")
    for method, info in caps.forward_methods.items():
        for branch in info.branches:
            out[branch] = ("branch", f"branch sign (+1 or -1) of the forward method '{method}'")
        if info.homotopy is None:
            out[info.unknown] = ("unknown", "the unknown of the forward polynomial (the mechanism's conventions)")
            continue
        where = f"the forward homotopy '{method}'"
        passive = {v.name for v in manifest.passive}
        for unknown in info.homotopy.unknowns:
            if unknown.startswith("z_") and unknown[2:] in passive:
                out[unknown] = ("unknown", f"z_v: the passive variable v (unknowns of {where})")
            else:
                out[unknown] = ("unknown", f"unknown of {where}")
        angles = []
        for note in notes.get(method, []):
            for kind, name, description in _from_note(note):
                if kind == "angle" and description not in angles:
                    angles.append(description)
                out[name] = (kind, f"{description} ({where})")
        for name, (kind, _) in list(out.items()):
            if kind == "angle":
                stand = "(C_u, S_u, D_u) stand for (cos, sin, 1) of an input angle, moved on C^2 + S^2 = D^2"
                out[name] = ("family", f"{stand} along the paths of {where}; u: {', '.join(angles)}")
    if caps.inverse is not None:
        for branch in caps.inverse.branches:
            out[branch] = ("branch", "branch sign of the inverse (+1 or -1)")
    for key, where in (("inverse_steps", "the inverse steps"), ("forward_auxiliary", "the forward auxiliaries")):
        for target, _ in objects.get(key, ()):
            out.setdefault(target.name, ("defined", f"defined in {where}"))
    return out


_NOTES = (
    (re.compile(r"^(\w+): \((c_\w+), (s_\w+)\) on the circle"), "circle"),
    (re.compile(r"^cos, sin of (.+) = \(C, S\) / D on the circle, parametrised by (\w+)$"), "angle"),
    (re.compile(r"^(\w+) = (.+): a parameter of the family$"), "family"),
    (re.compile(r"^(\w+): auxiliary unknown, \w+\^2 = (.+)$"), "root"),
)


def _from_note(note: str) -> list[tuple[str, str, str]]:
    """(kind, name, description) of the symbols one generator note explains."""
    for pattern, form in _NOTES:
        match = pattern.match(note)
        if match is None:
            continue
        a, b = match.group(1), match.group(2)
        if form == "circle":
            described = "c_v, s_v: cos and sin of the passive variable v, unknowns"
            return [("unknown", b, described), ("unknown", match.group(3), described)]
        if form == "angle":
            return [("angle", f"{c}_{b}", f"{b} {a}") for c in "CSD"]
        if form == "family":
            return [("family", a, f"= {b}, computed from the inputs")]
        return [("unknown", a, f"auxiliary unknown, {a}^2 = {b}")]
    return []


def _report(name: str | os.PathLike[str]) -> _Report:
    """The manifest, the objects (symbols under their display names), sections and symbols."""
    import parakin

    sympy = _sympy()
    manifest = parakin.metadata(name)
    objects = parakin.symbolic(name)
    sections = _sections(manifest, objects)
    names = _display_names(sympy, manifest, objects, sections)
    renamed = {s: sympy.Symbol(n, **_assumptions(s)) for s, n in names.items() if n != s.name}
    if renamed:
        objects = {k: _rename(sympy, v, renamed) for k, v in objects.items()}
    glossary = _glossary(manifest, _notes(name), objects)
    variables = {v.name: v for v in (*manifest.actuated, *manifest.passive)}
    kinds = {v.name: "actuated" for v in manifest.actuated} | {v.name: "passive" for v in manifest.passive}
    parameters = {p.name: p for p in manifest.parameters}
    symbols: dict[str, _Entry] = {}
    for original, display in names.items():
        symbol = renamed.get(original, original)
        if display in variables and display == original.name:
            v = variables[display]
            symbols[display] = _Entry(symbol, kinds[display], f"{kinds[display]} variable", v.unit, home=v.home)
        elif display in parameters and display == original.name:
            p = parameters[display]
            symbols[display] = _Entry(symbol, "parameter", p.description or "parameter", p.unit, p.default)
        elif display in glossary:
            symbols[display] = _Entry(symbol, *glossary[display])
        elif original.name in glossary and display != original.name:
            kind, description = glossary[original.name]
            symbols[display] = _Entry(symbol, kind, f"{description} (written {display}: {original.name} is taken)")
        else:
            symbols[display] = _Entry(
                symbol, "other", "defined by the mechanism file (its conventions: parakin.metadata(NAME).conventions)"
            )
        symbols[display].original = original
    return _Report(manifest, objects, sections, symbols)


def _assumptions(symbol: Any) -> dict[str, bool]:
    """The fewest assumptions that rebuild ``symbol`` (Symbol(name, **them) == symbol)."""
    every = dict(symbol.assumptions0)
    if every.get("commutative"):
        every.pop("commutative")
    for keys in (("positive",), ("negative",), ("nonnegative",), ("nonzero", "real"), ("real",), ()):
        few = {k: every[k] for k in keys if every.get(k) is True}
        if len(few) == len(keys) and type(symbol)(symbol.name, **few) == symbol:
            return few
    return every


def _rename(sympy: Any, value: Any, renamed: dict[Any, Any]) -> Any:
    if _is_steps(value):
        return sympy.Tuple(*(sympy.Tuple(*(part.xreplace(renamed) for part in step)) for step in value))
    return value.xreplace(renamed)


def _size(expression: Any, memo: dict[Any, int] | None = None) -> int:
    """Nodes of an expression tree, counted with repetition (each distinct subtree visited once)."""
    memo = {} if memo is None else memo
    found = memo.get(expression)
    if found is None:
        found = 1 + sum(_size(a, memo) for a in getattr(expression, "args", ()))
        memo[expression] = found
    return found


# ---------------------------------------------------------------------------------------- text


def _text(
    sympy: Any,
    expr: Any,
    width: int,
    lines: int,
    name: str,
    rows: list[str] | None = None,
    columns: list[str] | None = None,
) -> str:
    """One object as text: a scalar, a matrix (grid, or per entry with labels) or steps."""
    steps = _is_steps(expr)
    values = [v for _, v in expr] if steps else list(expr) if _is_matrix(expr) else [expr]
    memo: dict[Any, int] = {}
    size = sum(_size(v, memo) for v in values)
    if not steps and not _is_matrix(expr) and size < 40:
        return str(sympy.pretty(expr, num_columns=width))
    shared: list[tuple[Any, Any]] = []
    if size > SHARE_ABOVE:
        # a repeated subtree printed once, by name (shared_k, defined below): a 6 x 6 determinant
        # written by Laplace expansion repeats its minors; printing it whole took seconds
        shared, values = shared_subtrees(sympy, values)
    if steps:
        out = _wrapped(
            [(f"{target} = ", value) for (target, _), value in zip(expr, values, strict=True)], width, lines, name
        )
    elif _is_matrix(expr):
        out = _matrix(expr.shape, values, rows, columns, width, lines, name)
    else:
        out = _wrapped([("", values[0])], width, lines, name)
    if shared:
        shown = shared[: 2 * lines]
        out += ["  where"] + _wrapped([(f"  {symbol} = ", value) for symbol, value in shown], width, lines, name)
        if len(shared) > len(shown):
            out.append(f"  ... {len(shared) - len(shown)} more ({_MORE.format(name=name)})")
    return "\n".join(out)


def _matrix(
    shape: tuple[int, int],
    values: list[Any],
    rows: list[str] | None,
    columns: list[str] | None,
    width: int,
    lines: int,
    name: str,
) -> list[str]:
    """A matrix as a grid with labelled rows and columns when every entry fits, else entry by
    entry labelled [row, column]; a column vector as one labelled line per row."""
    r, c = shape
    rows = rows or _indices(r)
    columns = columns or _indices(c)
    cells = [str(v) for v in values]
    if c == 1:
        return _wrapped([(f"[{rows[i]}] ", cells[i]) for i in range(r)], width, lines, name)
    label = max(len(x) for x in rows) + 2
    widths = [max(len(columns[j]), *(len(cells[i * c + j]) for i in range(r))) for j in range(c)]
    if label + sum(w + 2 for w in widths) <= width:
        out = [" " * label + "".join(f"  {columns[j]:>{widths[j]}}" for j in range(c))]
        for i in range(r):
            out.append(f"[{rows[i]}]".ljust(label) + "".join(f"  {cells[i * c + j]:>{widths[j]}}" for j in range(c)))
        return out
    listed = [(f"[{rows[i]}, {columns[j]}] ", cells[i * c + j]) for i in range(r) for j in range(c)]
    nonzero = [(label_, cell) for label_, cell in listed if cell != "0"]
    zeros = len(listed) - len(nonzero)
    return _wrapped(nonzero, width, lines, name) + ([f"  (the other {zeros} entries are 0)"] if zeros else [])


def _wrapped(rows: list[tuple[str, Any]], width: int, lines: int, name: str) -> list[str]:
    out: list[str] = []
    for label, row in rows:
        wrapped = textwrap.wrap(label + str(row), width=width, break_long_words=True, subsequent_indent="    ")
        if len(wrapped) > lines:
            hidden = len(wrapped) - lines
            wrapped = wrapped[:lines] + [f"    ... {hidden} more lines ({_MORE.format(name=name)})"]
        out.extend(wrapped)
    return out


def _motion(manifest: Any) -> str | None:
    """The platform's motion as the generator's screw analysis states it (mobility, nTmR; for a
    lower-mobility mechanism the controlled and the parasitic coordinates); None without one."""
    graph = manifest.joints
    return None if graph is None or graph.motion is None else str(graph.motion.text)


def _as_text(sympy: Any, report: _Report, width: int, lines: int, name: str) -> str:
    manifest = report.manifest
    header = [
        manifest.title,
        *textwrap.wrap(f"citation: {manifest.citation}", width=width, subsequent_indent="    "),
        "",
    ]
    scales = _scales(manifest)
    noise: list[str] = []  # the values shown as 0 (rounding noise)
    header.append("parameters:" if manifest.parameters else "parameters: none")
    for p in manifest.parameters:
        value = _denoised(p.default, scales, p.unit, p.name, noise)
        shown = f"{p.name} = {value:g} {p.unit}".rstrip() + (f": {p.description}" if p.description else "")
        header += textwrap.wrap(shown, width=width, initial_indent="  ", subsequent_indent="      ")
    for title, variables in (("actuated", manifest.actuated), ("passive", manifest.passive)):
        header += _wrapped_parts(f"{title} (at home): ", _home_values(variables, scales, noise), width)
    if noise:
        header += textwrap.wrap(
            f"({', '.join(noise)}: below {NOISE:g} times the scale of {'its' if len(noise) == 1 else 'their'} "
            "unit (the largest magnitude among the parameters and home values of that unit, at least 1), "
            "rounding noise, shown as 0)",
            width=width,
            subsequent_indent="    ",
        )
    motion = _motion(manifest)
    if motion is not None:
        header += textwrap.wrap(f"motion: {motion}", width=width, subsequent_indent="    ")
    others = _others(report)
    if others:
        header.append("other symbols:")
        for names, description in others:
            header += textwrap.wrap(
                f"{', '.join(names)}: {description}", width=width, initial_indent="  ", subsequent_indent="    "
            )
    body = []
    for section in report.sections:
        shown = _text(sympy, report.objects[section.key], width, lines, name, section.rows, section.columns)
        title = "\n".join(textwrap.wrap(f"== {section.title}", width=width, subsequent_indent="   "))
        body.append(f"{title}\n{shown}\n")
    return "\n".join([*header, "", *body])


#: a value whose magnitude is below this times its unit's scale (``_scales``) is rounding noise
#: and prints as 0 (rus6's home theta1 = 2.88e-16 rad)
NOISE = 1e-12


def _scales(manifest: Any) -> dict[str, float]:
    """Per unit: the largest magnitude among the parameters' defaults and the variables' home
    values in that unit, at least 1 (``NOISE`` is relative to it)."""
    scales: dict[str, float] = {}
    values = [(p.unit, p.default) for p in manifest.parameters]
    values += [(v.unit, v.home) for v in (*manifest.actuated, *manifest.passive) if v.home is not None]
    for unit, value in values:
        if math.isfinite(float(value)):
            scales[unit] = max(scales.get(unit, 1.0), abs(float(value)))
    return scales


def _denoised(value: float, scales: dict[str, float], unit: str, name: str, noise: list[str]) -> float:
    """``value``, or 0.0 where it is rounding noise (``NOISE``), its name then added to ``noise``."""
    value = float(value)
    if value != 0.0 and abs(value) < NOISE * scales.get(unit, 1.0):
        noise.append(name)
        return 0.0
    return value + 0.0  # no -0


def _home_values(variables: Any, scales: dict[str, float] | None = None, noise: list[str] | None = None) -> list[str]:
    """``d1 = 0.26459 m`` per variable at the home configuration, with its unit (SI), a revolute
    one also in degrees (labelled); a variable without a home value as ``name [unit]``; a value
    below ``NOISE`` times its unit's scale (``scales``, default 1) as 0, its name added to
    ``noise``."""
    parts = []
    for v in variables:
        if v.home is None:
            parts.append(f"{v.name} [{v.unit}]" if v.unit else v.name)
            continue
        home = _denoised(v.home, scales or {}, v.unit, v.name, [] if noise is None else noise)
        shown = f"{v.name} = {home:.6g}" + (f" {v.unit}" if v.unit else "")
        if v.kind == "revolute":
            shown += f" ({math.degrees(home) + 0.0:.6g} deg)"
        parts.append(shown)
    return parts


def _wrapped_parts(lead: str, parts: list[str], width: int) -> list[str]:
    """``lead`` and the parts joined by ", ", lines broken between parts only (never inside
    ``l6 = 0.771071 m``), continuation lines indented by four spaces."""
    if not parts:
        return [lead + "none"]
    lines = [lead + parts[0]]
    for k, part in enumerate(parts[1:], 1):
        if len(lines[-1]) + 2 + len(part) + (1 if k < len(parts) - 1 else 0) > width:
            lines[-1] += ","
            lines.append("    " + part)
        else:
            lines[-1] += ", " + part
    return lines


def _others(report: _Report) -> list[tuple[list[str], str]]:
    """The symbols that are neither variables nor parameters, grouped by their description."""
    groups: dict[str, list[str]] = {}
    for display, entry in report.symbols.items():
        if entry.kind not in ("actuated", "passive", "parameter"):
            groups.setdefault(entry.description, []).append(display)
    return [(sorted(names, key=_natural), description) for description, names in groups.items()]


def _natural(name: str) -> tuple[Any, ...]:
    """Pose entries in matrix order, then names with their numbers compared as numbers."""
    if name in POSE_INPUTS:
        return (0, POSE_INPUTS.index(name))
    return (1, *((int(part), "") if part.isdigit() else (-1, part) for part in re.split(r"(\d+)", name)))


# --------------------------------------------------------------------------------------- LaTeX


_LATEX_SPECIAL = {
    "\\": r"\textbackslash{}",
    "{": r"\{",
    "}": r"\}",
    "_": r"\_",
    "^": r"\^{}",
    "&": r"\&",
    "%": r"\%",
    "$": r"\$",
    "#": r"\#",
    "~": r"\textasciitilde{}",
}


def _escape(text: str) -> str:
    """Plain text for LaTeX."""
    return "".join(_LATEX_SPECIAL.get(ch, ch) for ch in text)


def _as_latex(sympy: Any, report: _Report) -> str:
    """One complete document: the symbols, then each section; the repeated subexpressions of the
    whole report named once (s_k), each defined in the first section that needs it."""
    manifest = report.manifest
    parts: list[tuple[_Section, list[Any]]] = [(s, _expressions(report.objects[s.key])) for s in report.sections]
    flat = [e for _, values in parts for e in values]
    shared, rows = shared_subtrees(sympy, flat)
    names = {symbol: rf"\mathsf{{s}}_{{{k}}}" for k, (symbol, _) in enumerate(shared)}
    definitions = dict(shared)

    def tex(expression: Any) -> str:
        text = sympy.latex(expression, symbol_names=names, mul_symbol=None)
        # plain parentheses: TeX may then break inside them, after + and -
        return text.replace(r"\left(", "(").replace(r"\right)", ")")

    out = [
        r"\documentclass[10pt]{article}",
        r"\usepackage[margin=2cm]{geometry}",
        r"\usepackage{amsmath}",
        r"\newcommand{\eqn}[2]{\par\noindent\hangindent=3em\hangafter=1 $#1 = #2$\par}",
        r"\raggedright",
        r"\setlength{\parskip}{2pt}",
        rf"\title{{{_escape(manifest.title)}}}",
        rf"\author{{{_escape(str(manifest.citation))}}}",
        r"\date{\texttt{parakin inspect " + _escape(manifest.name) + r" --format latex}}",
        r"\begin{document}",
        r"\maketitle",
    ]
    motion = _motion(manifest)
    if motion is not None:
        out.append(r"\noindent\textbf{Motion:} " + _escape(motion) + r"\par")
    out += [
        r"\section*{Symbols}",
        r"\begin{description}",
    ]
    order = [v.name for v in (*manifest.actuated, *manifest.passive)] + [p.name for p in manifest.parameters]
    for display in order:
        entry = report.symbols.get(display)
        if entry is not None:
            what = entry.description + (f" [{entry.unit}]" if entry.unit else "")
            what += f", default {entry.value:g}" if entry.value is not None else ""
            what += f", home {entry.home:.6g}" if entry.home is not None else ""
            out.append(rf"\item[${tex(entry.symbol)}$] {_escape(what)}")
    for group, description in _others(report):
        shown = ", ".join(tex(report.symbols[n].symbol) for n in group)
        out.append(rf"\item[${shown}$] {_escape(description)}")
    out += [r"\end{description}"]
    defined: set[Any] = set()
    position = 0
    for section, values in parts:
        written = rows[position : position + len(values)]
        position += len(values)
        out.append(rf"\section{{{_escape(section.title)}}}")
        value = report.objects[section.key]
        if _is_matrix(value):
            out += _latex_matrix(tex, value.shape, written, section)
        elif _is_steps(value):
            out += [rf"\eqn{{{tex(written[k])}}}{{{tex(written[k + 1])}}}" for k in range(0, len(written), 2)]
        else:
            out.append(rf"\eqn{{{_escape_name(section.key)}}}{{{tex(written[0])}}}")
        needed = _needed(written, definitions, defined)
        if needed:
            out.append(r"\noindent where")
            out += [rf"\eqn{{{names[symbol]}}}{{{tex(definitions[symbol])}}}" for symbol in needed]
    out.append(r"\end{document}")
    return "\n".join(out) + "\n"


def _escape_name(key: str) -> str:
    return r"\text{" + _escape(key) + "}"


def _needed(values: list[Any], definitions: dict[Any, Any], defined: set[Any]) -> list[Any]:
    """The shared symbols the values use, not yet defined, with the ones they use, in order."""
    found: list[Any] = []
    stack = [s for v in values for s in getattr(v, "free_symbols", ()) if s in definitions]
    while stack:
        symbol = stack.pop()
        if symbol in defined:
            continue
        defined.add(symbol)
        found.append(symbol)
        stack += [s for s in definitions[symbol].free_symbols if s in definitions and s not in defined]
    order = {symbol: k for k, symbol in enumerate(definitions)}
    return sorted(found, key=order.__getitem__)


def _latex_matrix(tex: Any, shape: tuple[int, int], values: list[Any], section: _Section) -> list[str]:
    """A grid with labelled rows and columns when the entries are short, else one labelled
    equation per nonzero entry."""
    r, c = shape
    cells = [tex(v) for v in values]
    rows = [tex(_label_symbol(x)) for x in section.rows]
    columns = [tex(_label_symbol(x)) for x in section.columns]
    key = _escape_name(section.key)
    if max((len(x) for x in cells), default=0) <= 24 and c <= 8:
        head = " & " + " & ".join(columns) + r" \\ \hline"
        body = [rows[i] + " & " + " & ".join(cells[i * c : (i + 1) * c]) + r" \\" for i in range(r)]
        return [r"\[" + key + r" = \begin{array}{r|" + "c" * c + "}", head, *body, r"\end{array}\]"]
    out = [
        rf"\eqn{{{key}_{{{rows[i]},\,{columns[j]}}}}}{{{cells[i * c + j]}}}"
        for i in range(r)
        for j in range(c)
        if cells[i * c + j] != "0"
    ]
    return out + ([r"\noindent (the other entries are 0)"] if len(out) < r * c else [])


def _label_symbol(label: str) -> Any:
    sympy = _sympy()
    return sympy.Integer(int(label)) if label.isdigit() else sympy.Symbol(label)


# ---------------------------------------------------------------------------------------- JSON


def _as_json(sympy: Any, report: _Report) -> str:
    """The report as the JSON object of the module docstring."""
    manifest = report.manifest
    keys = list(report.objects)
    flat = [e for key in keys for e in _expressions(report.objects[key])]
    shared, rows = shared_subtrees(sympy, flat)
    objects: dict[str, Any] = {}
    labels = {s.key: s for s in report.sections}
    position = 0
    for key in keys:
        value = report.objects[key]
        count = len(_expressions(value))
        written = [str(x) for x in rows[position : position + count]]
        position += count
        if _is_matrix(value):
            r, c = value.shape
            section = labels.get(key)
            objects[key] = {
                "kind": "matrix",
                "shape": [r, c],
                "rows": section.rows if section else _indices(r),
                "columns": section.columns if section else _indices(c),
                "entries": [written[i * c : (i + 1) * c] for i in range(r)],
            }
        elif _is_steps(value):
            objects[key] = {"kind": "definitions", "steps": [written[k : k + 2] for k in range(0, count, 2)]}
        else:
            objects[key] = {"kind": "expression", "value": written[0]}
    symbols = {}
    for display, entry in report.symbols.items():
        item: dict[str, Any] = {
            "name": entry.original.name,
            "assumptions": _assumptions(entry.original),
            "kind": entry.kind,
            "description": entry.description,
        }
        if entry.unit is not None:
            item["unit"] = entry.unit
        if entry.value is not None:
            item["value"] = entry.value
        if entry.home is not None:
            item["home"] = entry.home
        symbols[display] = item
    data = {
        "schema": "parakin.interfaces.inspect/1",
        "manifest": manifest.name,
        "title": manifest.title,
        "citation": str(manifest.citation),
        "motion": _motion(manifest),
        "symbols": symbols,
        "shared": [[str(symbol), str(value)] for symbol, value in shared],
        "objects": objects,
        "sections": [{"title": s.title, "object": s.key} for s in report.sections],
    }
    return json.dumps(data, indent=1)


def inspect(name: str | os.PathLike[str], fmt: str = "text", width: int = 100, lines: int = 12) -> str:
    """The inspect report of a mechanism (the formats of the module docstring).

    Parameters
    ----------
    name : str or path
        A generated package: a shipped mechanism's name or a package folder.
    fmt : {"text", "latex", "json"}
        "text" (readable, wrapped), "latex" (one complete document) or "json" (the schema of the
        module docstring); any other value gives the text.
    width : int
        Characters per line of the text format.
    lines : int
        Lines of one expression shown in the text format before it is cut (with a pointer to the
        full forms).

    Returns
    -------
    str
        The report. Its header names the variables, the parameters and the platform's motion
        (``manifest.joints.motion.text``; the JSON's ``"motion"``).

    Raises
    ------
    parakin.errors.UnsupportedOperationError
        SymPy is not installed (the ``generator`` extra).

    Example
    -------
    >>> from parakin.interfaces.inspect import inspect
    >>> "controlled: the height p . k" in inspect("prs3", width=10_000)
    True
    """
    sympy = _sympy()
    report = _report(name)
    if fmt == "json":
        return _as_json(sympy, report)
    if fmt == "latex":
        return _as_latex(sympy, report)
    return _as_text(sympy, report, width, lines, str(name))


__all__ = ["inspect"]
