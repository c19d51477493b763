"""Rendering of lowered programs through the Jinja templates in ``generator/templates``.

Each backend has its own template; this module only prepares the values the templates print
(expressions as strings, shapes, operation counts). No code is assembled by concatenation here.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import jinja2
import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from . import GENERATOR_VERSION
from .program import LoweredProgram

TEMPLATES = Path(__file__).parent / "templates"

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
            version=GENERATOR_VERSION,
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
    printer = ModulePrinter("casadi")
    return (
        _environment()
        .get_template("casadi_module.py.j2")
        .render(
            banner=banner(mechanism, "casadi_module.py.j2", programs, "#"),
            programs=[_printed_program(p, printer) for p in programs],
        )
    )


def render_c_driver(mechanism: str, programs: list[LoweredProgram], manifest: dict[str, Any]) -> str:
    """The batched C entry points and the Newton loop, laid out as the manifest describes them."""
    kernels = {k["name"]: k for k in manifest["kernels"]}
    described = [
        {
            "name": p.name,
            "inputs": [(group, len(symbols)) for group, symbols in p.source.inputs],
            "outputs": [(o.name, o.shape[0], o.shape[1] if len(o.shape) == 2 else 1) for o in p.outputs],
            "sizes": kernels[p.name]["work"],
        }
        for p in programs
    ]
    newton = dict(manifest["c"]["newton"])
    pair = [kernels[newton["residual"]]["work"], kernels[newton["pose"]]["work"]]
    newton["sizes"] = {key: max(w[key] for w in pair) for key in pair[0]}
    newton["pose_sizes"] = kernels[newton["pose"]]["work"]
    return (
        _environment()
        .get_template("c_driver.c.j2")
        .render(
            banner=banner(mechanism, "c_driver.c.j2", programs, "//"),
            mechanism=mechanism,
            programs=described,
            newton=newton,
        )
    )


def render_symbolic(mechanism: str, objects: dict[str, Any]) -> str:
    return (
        _environment()
        .get_template("symbolic_module.py.j2")
        .render(
            banner=banner(mechanism, "symbolic_module.py.j2", [], "#"),
            objects=[(name, sp.srepr(value)) for name, value in objects.items()],
        )
    )
