"""Rendering of lowered programs through the Jinja templates in ``generator/templates``.

Each backend has its own template; this module only prepares the values the templates print
(expressions as strings, shapes, operation counts). No code is assembled by concatenation here.
"""

from __future__ import annotations

import functools
import importlib.metadata
import tomllib
from pathlib import Path
from typing import Any

import jinja2
import numpy as np
import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from parakin.packages.package import export_name
from parakin.packages.subtrees import shared_subtrees
from parakin.solvers import path_tracking as tracking
from parakin.solvers.path_tracking import path_pairs

from .program import LoweredProgram

TEMPLATES = Path(__file__).parent / "templates"
#: the fixed C every homotopy package's driver holds (ordinary sources, tested on their own by
#: tests/test_c_runtime.py), printed into the driver where the template names them
RUNTIME = Path(__file__).parent / "runtime"
#: the step control the C tracker shares with parakin.solvers.path_tracking, printed as #defines
TRACKER_CONSTANTS = (
    "CORRECTIONS",
    "INITIAL_STEP",
    "PREDICTOR_TARGET",
    "STEP_SAFETY",
    "STEP_GROW",
    "STEP_SHRINK",
    "MIN_STEP",
    "ESCAPE",
    "MAX_STEPS",
    "REFINE",
    "END_GAP",
    "RATIONAL_GUARD",
    "ONE_STEP_BASIN",
    "ONE_STEP_ERROR",
    "OMEGA_DECAY",
    "ONE_STEP_GOAL",
    "OMEGA_FADE",
    "END_REACH",
    "REFINE_ERROR",
    "ACROSS_NOISE",
)
PYPROJECT = Path(__file__).resolve().parent.parent / "pyproject.toml"


@functools.cache
def package_version() -> str:
    """parakin's version, printed in every banner and the manifest: ``[project] version`` of the
    source tree's pyproject.toml (the one place it is written), or the installed distribution's
    when the generator runs from an installed parakin."""
    if PYPROJECT.is_file():
        project = tomllib.loads(PYPROJECT.read_text()).get("project", {})
        if project.get("name") == "parakin":
            return str(project["version"])
    return importlib.metadata.version("parakin")


_FUNCTIONS = {
    "numpy": {
        "sin": "sin",
        "cos": "cos",
        "tan": "tan",
        "atan2": "arctan2",
        "asin": "arcsin",
        "acos": "arccos",
        "atan": "arctan",
        "Abs": "abs",
        "sign": "sign",
        "exp": "exp",
        "log": "log",
        "Min": "fmin",
        "Max": "fmax",
    },
    "casadi": {
        "sin": "sin",
        "cos": "cos",
        "tan": "tan",
        "atan2": "atan2",
        "asin": "asin",
        "acos": "acos",
        "atan": "atan",
        "Abs": "fabs",
        "sign": "sign",
        "exp": "exp",
        "log": "log",
        "Min": "fmin",
        "Max": "fmax",
    },
}


class ModulePrinter(PythonCodePrinter):
    """Python expression printer whose elementary functions come from one module."""

    def __init__(self, module: str) -> None:
        functions = {name: f"{module}.{target}" for name, target in _FUNCTIONS[module].items()}
        super().__init__({"user_functions": functions, "fully_qualified_modules": True})
        self.module = module

    def _print_Pow(self, expr: sp.Pow, rational: bool = False) -> str:
        return self._hprint_Pow(expr, rational=rational, sqrt=f"{self.module}.sqrt")

    def _print_Pi(self, expr: sp.Expr) -> str:
        return f"{self.module}.pi"

    def _print_sign(self, expr: sp.Expr) -> str:
        # the base printer emits a Python conditional, which neither arrays nor CasADi accept
        return f"{self.module}.sign({self._print(expr.args[0])})"


def runtime_sources() -> dict[str, str]:
    """The C runtime's headers by name without their extension (``complex``, ``tracker``): their
    text as the driver prints it, the include guard's lines and all."""
    return {path.stem: path.read_text().rstrip() for path in sorted(RUNTIME.glob("*.h"))}


def _environment() -> jinja2.Environment:
    environment = jinja2.Environment(
        loader=jinja2.FileSystemLoader(TEMPLATES),
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        undefined=jinja2.StrictUndefined,
    )
    environment.filters["pyrepr"] = repr  # Python literals (None, tuples), not JSON
    return environment


def _printed_program(program: LoweredProgram, printer: ModulePrinter) -> dict[str, Any]:
    return {
        "name": program.name,
        "doc": program.source.doc,
        "operations": program.operations,
        "inputs": [(group, len(symbols)) for group, symbols in program.source.inputs],
        "unpack": [(str(symbol), group, position) for group, position, symbol in program.used_inputs()],
        "body": [(str(a.target), printer.doprint(a.value)) for a in program.body],
        "outputs": [
            {
                "name": output.name,
                "shape": output.shape,
                "entries": [
                    (", ".join(str(i) for i in entry.index), printer.doprint(entry.value))
                    for entry in output.entries
                    if entry.value != 0
                ],
            }
            for output in program.outputs
        ],
    }


def banner(mechanism: str, template: str, programs: list[LoweredProgram], comment: str) -> str:
    return (
        _environment()
        .get_template("banner.j2")
        .render(
            mechanism=mechanism,
            template=template,
            version=package_version(),
            programs=[(p.name, p.operations) for p in programs],
            comment=comment,
        )
    )


def render_numpy(mechanism: str, programs: list[LoweredProgram]) -> str:
    printer = ModulePrinter("numpy")
    return (
        _environment()
        .get_template("numpy_module.py.j2")
        .render(
            banner=banner(mechanism, "numpy_module.py.j2", programs, "#"),
            programs=[_printed_program(p, printer) for p in programs],
        )
    )


def render_casadi(mechanism: str, programs: list[LoweredProgram]) -> str:
    """CasADi builders; each Function is named ``<mechanism>_<kernel>`` so that the C of two
    mechanisms links into one program."""
    printer = ModulePrinter("casadi")
    return (
        _environment()
        .get_template("casadi_module.py.j2")
        .render(
            prefix=f"{mechanism}_",
            banner=banner(mechanism, "casadi_module.py.j2", programs, "#"),
            programs=[_printed_program(p, printer) for p in programs],
        )
    )


def _near_start(near: dict | None) -> dict:
    """The template's view of the start near home (generator/near_start.py); an empty
    ``near_real`` where the package has none (the template then leaves it out)."""
    if near is None:
        return {"near_real": []}
    solutions = near["solutions"]
    return {
        "near_real": [[repr(float(v)) for v in row] for row in solutions["real"]],
        "near_imag": [[repr(float(v)) for v in row] for row in solutions["imag"]],
        "near_center": [
            [repr(float(re)), repr(float(im))]
            for re, im in zip(near["center"]["real"], near["center"]["imag"], strict=True)
        ],
        "near_scale": [repr(float(v)) for v in near["scale"]],
        "near_radius": repr(float(near["radius"])),
    }


def _symmetry(chosen: dict) -> dict[str, object]:
    """The family's sign symmetry and the start paths it pairs (``parakin.solvers.path_tracking``): the C
    driver tracks one path of each pair and takes the image of its end for the other, as the
    NumPy pipeline does; empty when there is none."""
    exponents = np.array([e for _, e in chosen["terms"]], dtype=np.int64)
    equation = np.array([k for k, _ in chosen["terms"]], dtype=np.int64)
    start = np.array(chosen["start"]["real"], dtype=float) + 1j * np.array(chosen["start"]["imag"], dtype=float)
    pairs = path_pairs(exponents, equation, start)
    if pairs is None:
        return {"partner": None}
    return {"partner": [int(p) for p in pairs.partner], "flip": [repr(float(v)) for v in pairs.flip]}


def _product(factors: list[tuple[int, int]]) -> str | None:
    """The C expression of a product of powers pw[v][e] (None for the empty product, 1)."""
    expression = None
    for v, e in factors:
        factor = f"pw[{v}][{e}]"
        expression = factor if expression is None else f"c_mul({expression}, {factor})"
    return expression


def _term(equation: int, exponents: list[int]) -> dict[str, Any]:
    """A monomial for the unrolled C evaluation: its value's expression, and per variable the
    expression of the partial derivative over the coefficient (None: the partial is 1). No
    product by 1: the unrolled code multiplies only what the monomial holds."""
    support = [(v, e) for v, e in enumerate(exponents) if e]
    partials = []
    for v, e in support:
        others = _product([(w, f) for w, f in support if w != v])
        if e == 1:
            partials.append((v, others))
            continue
        power = f"c_scale({e}.0, pw[{v}][{e - 1}])"
        partials.append((v, power if others is None else f"c_mul({power}, {others})"))
    return {"equation": equation, "monomial": _product(support) or "(cplx){1.0, 0.0}", "partials": partials}


def _c_context(mechanism: str, programs: list[LoweredProgram], manifest: dict[str, Any]) -> dict[str, Any]:
    """What the C driver and the public header print: sizes, branch tables, the ABI."""
    from .abi import C_TYPES, describe

    kernels = {k["name"]: k for k in manifest["kernels"]}
    caps = manifest["capabilities"]
    newton = dict(manifest["c"]["newton"])
    work = {key: max(k["work"][key] for k in kernels.values()) for key in ("arg", "res", "iw", "w")}
    forward = inverse = None
    if caps["forward"] is not None:
        default = caps["forward"]["default"]
        chosen = caps["forward"]["methods"][default]
        homotopy = "start" in chosen
        if caps["inverse"] is None and not homotopy:
            raise ValueError(f"{mechanism}: a forward elimination needs a closed-form inverse (passive joints)")
        forward = {
            "degree": chosen["degree"],
            "combinations": chosen["combinations"],
            "branch_size": len(chosen["branches"]),
            "degeneracies": len(chosen["degeneracies"]),
            "method": default,
            "homotopy": homotopy,
        }
        if homotopy:
            start, alternative = chosen["start"], chosen["alternative"]
            forward |= {
                "unknowns": len(chosen["unknowns"]),
                "powers": chosen["powers"],
                "homogeneous": chosen["homogeneous"],
                "terms": [_term(k, exponents) for k, exponents in chosen["terms"]],
                "max_degree": max(max(e, default=0) for _, e in chosen["terms"]) or 1,
                "start_real": [[repr(float(v)) for v in row] for row in start["real"]],
                "start_imag": [[repr(float(v)) for v in row] for row in start["imag"]],
                "alternative_real": [[repr(float(v)) for v in row] for row in alternative["real"]],
                "alternative_imag": [[repr(float(v)) for v in row] for row in alternative["imag"]],
                "free": len(chosen["free"]),
                "circles": len(chosen["circles"]),
                "instances": [
                    [[repr(float(re)), repr(float(im))] for re, im in zip(i["real"], i["imag"], strict=True)]
                    for i in (chosen["start_instance"], chosen["alternative_instance"])
                    + ((chosen["near"]["instance"],) if "near" in chosen else ())
                ],
                **_near_start(chosen.get("near")),
                "circle_a": [repr(float(v)) for v in chosen["circle_constants"][0]],
                "circle_b": [repr(float(v)) for v in chosen["circle_constants"][1]],
                **_symmetry(chosen),
            }
    if caps["forward"] is not None and caps["inverse"] is not None:
        groups = caps["inverse"]["groups"]
        inverse = {
            "combinations": caps["inverse"]["combinations"],
            "branch_size": len(caps["inverse"]["branches"]),
            "validity": len(caps["inverse"]["validity"]),
            "groups": groups,
            "patterns": len(caps["inverse"]["patterns"]),
            "actuated_groups": caps["inverse"]["actuated_groups"],
            "passive_groups": caps["inverse"]["passive_groups"],
            "validity_groups": caps["inverse"]["validity_groups"],
        }
    folded = (caps["rates"] or {}).get("input_independent") or []
    names = manifest["singularity_factors"]
    return {
        "P": mechanism,
        "title": manifest["title"],
        "citation": ", ".join(manifest["citation"]["authors"]) + f" ({manifest['citation']['year']})",
        "conventions": manifest["conventions"].splitlines(),
        "NA": len(manifest["actuated"]),
        "NQ": len(manifest["passive"]),
        "actuated": [v["name"] for v in manifest["actuated"]],
        "passive": [v["name"] for v in manifest["passive"]],
        "parameters": manifest["parameters"],
        "pairs": newton["pairs"],
        "newton": newton,
        "work": work,
        "forward": forward,
        "inverse": inverse,
        "factors": {
            "count": len(names),
            "determinants": len(manifest["determinants"]),
            "input_independent": [int(name in folded) for name in names] if folded else [],
        },
        "actuated_revolute": [int(v["kind"] == "revolute") for v in manifest["actuated"]],
        "passive_revolute": [int(v["kind"] == "revolute") for v in manifest["passive"]] or [0],
        "abi": describe(),
        "c_types": C_TYPES,
        "version": manifest["generator"]["version"],
        "at_infinity": repr(float(manifest["tolerances"]["at_infinity"])),
        # the C tracker (generator/runtime/tracker.h) and its constants: the NumPy reference's
        # (parakin.solvers.path_tracking.track_hermite)
        "tracker": [(name, repr(getattr(tracking, name))) for name in TRACKER_CONSTANTS],
        "path_codes": {
            "reached": tracking.PATH_REACHED,
            "failed": tracking.PATH_FAILED,
            "diverged": tracking.PATH_DIVERGED,
        },
        "runtime": runtime_sources(),
        "source": manifest["generator"]["source"],
        "example": {
            "source": manifest["c"]["example"]["source"],
            "actuated": [_c_number(v) for v in manifest["c"]["example"]["actuated"]],
            "guess": [_c_number(v) for v in manifest["c"]["example"]["guess"]],
        },
        "actuated_units": [f"{v['name']} [{v['unit']}]" for v in manifest["actuated"]],
        "passive_units": [f"{v['name']} [{v['unit']}]" for v in manifest["passive"]],
        "lower": [_c_number(v["limits"][0], "-INFINITY") for v in manifest["passive"]],
        "upper": [_c_number(v["limits"][1], "INFINITY") for v in manifest["passive"]],
        "modes_settings": _example_job(manifest, "modes"),
        "newton_settings": _example_job(manifest, "newton"),
        "kernels": manifest["kernels"],
        # the names the files take where ``parakin export`` writes them (prefixed: several
        # mechanisms share one folder); the README and the example program speak of those
        "exported": {
            name.replace(".", "_"): export_name(mechanism, name)
            for name in ("driver.c", "kernels.c", "kernels.h", "real_roots.h", "example_main.c", "README_C.md")
        },
        "programs": [
            {
                "name": p.name,
                "inputs": [(group, len(symbols)) for group, symbols in p.source.inputs],
                "outputs": [(o.name, o.shape[0], o.shape[1] if len(o.shape) == 2 else 1) for o in p.outputs],
                "sizes": kernels[p.name]["work"],
            }
            for p in programs
        ],
    }


def _c_number(value: float | None, missing: str = "0.0") -> str:
    return missing if value is None else repr(float(value))


def _example_job(manifest: dict[str, Any], which: str) -> list[tuple[str, str]]:
    """Designated initialisers of the example program's job structures: every field named."""
    from .abi import MODES_JOB, NEWTON_JOB

    tol = manifest["tolerances"]
    common = {"n": "1", "actuated": "actuated", "actuated_stride": "0", "params": "(const double*)&params"}
    if which == "newton":
        values = {
            **common, "guess": "guess", "guess_stride": "0", "max_iterations": "30", "tolerance": "1e-12",
            "max_step": "0.5", "singular_ratio": repr(tol["singular_ratio"]), "passive": "solved", "pose": "pose",
            "residual": "&norm", "conditioning": "&ratio", "orientation": "&orientation", "first_step": "&first_step",
            "iterations": "&iterations", "status": "&newton_status",
        }  # fmt: skip
        return [(name, values[name]) for name, _ in NEWTON_JOB]
    values = {
        **common, "lower": "lower", "upper": "upper", "polish_iterations": str(int(tol["polish_iterations"])),
        "tolerance": repr(tol["polish"]), "leading_tolerance": repr(tol["leading"]),
        "near_tolerance": repr(tol["near_real"]),
        **{k: repr(tol[k]) for k in ("path_tolerance", "real_endpoint", "near_real_endpoint")},
        **{k: repr(tol[k]) for k in ("closure", "candidate", "duplicate", "factor_zero", "singular_ratio",
                                     "validity", "degenerate")},
        "poses": "poses", "passive": "passive", "residual": "residual", "conditioning": "conditioning",
        "roots": "roots", "outcome": "outcome", "root_kind": "root_kind", "count": "&count",
        "real_roots": "&real_roots", "near_roots": "&near_roots", "at_infinity": "&at_infinity", "status": "&status",
        "endpoints": "(double*)0",
    }  # fmt: skip
    return [(name, values[name]) for name, _ in MODES_JOB]


def render_c_example(mechanism: str, programs: list[LoweredProgram], manifest: dict[str, Any]) -> dict[str, str]:
    """``example_main.c`` and ``README_C.md`` of the exported C library."""
    context = _c_context(mechanism, programs, manifest)
    environment = _environment()
    return {
        "example_main.c": environment.get_template("c_example.c.j2").render(
            banner=banner(mechanism, "c_example.c.j2", programs, "//"), **context
        ),
        "README_C.md": environment.get_template("c_readme.md.j2").render(**context),
    }


def render_c_driver(mechanism: str, programs: list[LoweredProgram], manifest: dict[str, Any]) -> str:
    """The batched C entry points, the Newton loop and the all-modes pipeline (``c_driver.c.j2``)."""
    context = _c_context(mechanism, programs, manifest)
    return (
        _environment()
        .get_template("c_driver.c.j2")
        .render(banner=banner(mechanism, "c_driver.c.j2", programs, "//"), **context)
    )


def render_c_header(mechanism: str, programs: list[LoweredProgram], manifest: dict[str, Any]) -> str:
    """The public header ``<mechanism>.h``: parameters, status codes, job structures, prototypes."""
    context = _c_context(mechanism, programs, manifest)
    return (
        _environment()
        .get_template("c_header.h.j2")
        .render(banner=banner(mechanism, "c_header.h.j2", programs, "//"), **context)
    )


def render_symbolic(mechanism: str, objects: dict[str, Any]) -> str:
    """The derived objects with their repeated subexpressions stored once (``shared``): a tree
    CSE that only names identical subtrees, so ``load`` rebuilds every object exactly (a 6 x 6
    determinant written by Laplace expansion shares its minors: 10 MB become 0.1 MB)."""
    names = list(objects)
    values = [sp.ImmutableMatrix(v) if isinstance(v, sp.MatrixBase) else v for v in objects.values()]
    shared, reduced = shared_subtrees(sp, values)
    matrices = [name for name, value in objects.items() if isinstance(value, sp.MatrixBase)]
    return (
        _environment()
        .get_template("symbolic_module.py.j2")
        .render(
            banner=banner(mechanism, "symbolic_module.py.j2", [], "#"),
            shared=[(str(symbol), sp.srepr(value)) for symbol, value in shared],
            objects=[(name, sp.srepr(value)) for name, value in zip(names, reduced, strict=True)],
            matrices=matrices,
        )
    )
