"""The manifest of a generated package: everything the runtime needs, language neutral (JSON).

``parakin/packages/manifest.py`` reads it into typed objects; nothing in the runtime knows a mechanism by
name. Bump ``SUPPORTED_SCHEMA`` there whenever a field changes meaning or is removed.
"""

from __future__ import annotations

import inspect
import math
from typing import Any

import sympy as sp

from parakin.packages.manifest import SUPPORTED_SCHEMA

from . import abi
from .derive import Derivation
from .emit import package_version
from .model import Mechanism
from .program import LoweredProgram

#: the schema written: the one the runtime's reader supports (one number, in one place)
SCHEMA = SUPPORTED_SCHEMA

#: numerical thresholds of the runtime, per mechanism (a mechanism file may override them)
DEFAULT_TOLERANCES = {
    "validity": 1e-9,  # an inverse validity measure must exceed this
    "closure": 1e-9,  # max |residual| of a closed configuration
    "candidate": 1e-4,  # max |residual| of a forward candidate before Newton polish
    "duplicate": 1e-7,  # two modes closer than this (max |pose difference|) are one
    "degenerate": 1e-9,  # an elimination degeneracy measure below this: no isolated solutions
    "singular_ratio": 1e-10,  # 1/cond of a Jacobian below this: singular
    "factor_zero": 1e-9,  # an input-independence factor below this vanishes
    "polish": 1e-13,  # Newton tolerance of the polish of every forward_pose_all mode
    "polish_iterations": 30,  # converges in 1-3 steps; near double roots only linearly
    "leading": 1e-13,  # leading coefficients below this (relative) are roots at infinity
    "near_real": 1e-9,  # a local extremum of the polynomial this close to 0: a near-real pair
    # back substitution point of a root at infinity: a tangent half-angle there is the half-turn,
    # which the polish reaches exactly (other unknowns give a far pose, rejected as not closed)
    "at_infinity": 1e8,
    # homotopy endpoints: relative imaginary part (after the phase of the homogeneous unknowns is
    # removed) below "real_endpoint": a real solution; below "near_real_endpoint": a candidate
    # that the real Newton polish confirms or rejects (a near-double real root); above: complex
    "real_endpoint": 1e-8,
    "near_real_endpoint": 1e-4,
    # corrector tolerance of the path tracker (relative Newton update accepted at each step)
    "path_tolerance": 1e-7,
}


def _bound(value: float) -> float | None:
    return None if math.isinf(value) else float(value)


def _variables(mechanism: Mechanism, symbols: list[sp.Symbol]) -> list[dict[str, Any]]:
    result = []
    for symbol in symbols:
        kind = "revolute" if symbol in mechanism.angular else "prismatic"
        kind = "dimensionless" if symbol in mechanism.dimensionless else kind
        low, high = mechanism.limits.get(symbol, (-math.inf, math.inf))
        result.append(
            {
                "name": str(symbol),
                "kind": kind,
                "unit": {"revolute": "rad", "prismatic": "m", "dimensionless": ""}[kind],
                "home": float(mechanism.home[symbol]) if symbol in mechanism.home else None,
                "limits": [_bound(low), _bound(high)],
            }
        )
    return result


def _parameters(mechanism: Mechanism) -> list[dict[str, Any]]:
    result = []
    for symbol, default in mechanism.parameters.items():
        info = mechanism.parameter_info.get(symbol)
        result.append(
            {
                "name": str(symbol),
                "default": float(default),
                "unit": info.unit if info else "",
                "description": info.description if info else "",
                "domain": info.domain if info else "real",
            }
        )
    return result


def _kernels(name: str, lowered: list[LoweredProgram], sizes: dict[str, dict[str, int]]) -> list[dict[str, Any]]:
    return [
        {
            "name": p.name,
            "doc": p.source.doc,
            "operations": p.operations,
            "inputs": [{"name": group, "size": len(symbols)} for group, symbols in p.source.inputs],
            "outputs": [{"name": o.name, "shape": list(o.shape)} for o in p.outputs],
            "work": sizes[p.name],
            "c_symbol": f"{name}_{p.name}_batch",
        }
        for p in lowered
    ]


def _example(example: Any) -> dict[str, Any]:
    return {
        "name": example.name,
        "description": example.description,
        "pose": example.pose,
        "actuated": example.actuated,
        "branch": example.branch,
        "parameters": dict(example.parameters),
        "expected": dict(example.expected),
        "tolerance": example.tolerance,
    }


def build_manifest(
    mechanism: Mechanism,
    conventions: str,
    source: str,
    derivation: Derivation,
    lowered: list[LoweredProgram],
    sizes: dict[str, dict[str, int]],
) -> dict[str, Any]:
    """The manifest dictionary (schema ``SCHEMA``) of one generated package."""
    meta: dict[str, Any] = dict(derivation.metadata)
    citation = mechanism.citation
    loop = next(p for p in lowered if p.name == "loop_closure")
    capabilities: dict[str, Any] = {
        "inverse": meta.get("inverse"),
        "forward": meta.get("forward"),
        "legs": meta.get("legs") or None,
        "rates": meta.get("rates"),
        "architecture": {"measures": meta["architecture"], "tolerance": mechanism.architecture_tolerance}
        if "architecture" in meta
        else None,
        "drawing": meta.get("drawing"),
        "statics": {"stiffness": [str(s) for s in mechanism.actuator_stiffness]}
        if mechanism.actuator_stiffness
        else None,
    }
    return {
        "schema": SCHEMA,
        "name": mechanism.name,
        "title": mechanism.title,
        "citation": {
            "authors": list(citation.authors),
            "title": citation.title,
            "year": citation.year,
            "venue": citation.venue,
            "doi": citation.doi,
        },
        "conventions": inspect.cleandoc(conventions),
        "generator": {"version": package_version(), "source": source},
        "pose_kind": mechanism.pose_kind,
        "parameters": _parameters(mechanism),
        "parameter_groups": [
            {"name": name, "shape": [matrix.rows, matrix.cols], "symbols": [str(s) for s in matrix]}
            for name, matrix in mechanism.parameter_groups.items()
        ],
        "actuated": _variables(mechanism, mechanism.actuated),
        "passive": _variables(mechanism, mechanism.passive),
        "singularity_factors": meta["singularity_factors"],
        "determinants": meta["determinants"],
        "capabilities": capabilities,
        # the bodies and joints (``generator.graph.to_json``): what the MJCF export builds from
        "joints": meta.get("joints"),
        "examples": [_example(e) for e in mechanism.examples],
        "tolerances": DEFAULT_TOLERANCES,
        "kernels": _kernels(mechanism.name, lowered, sizes),
        "c": {
            "sources": ["kernels.c", "driver.c"],
            "header": f"{mechanism.name}.h",
            "headers": ["kernels.h", "real_roots.h", f"{mechanism.name}.h"],
            "abi": abi.describe(),
            "newton": {
                "symbol": f"{mechanism.name}_forward_pose",
                "unknowns": len(loop.source.inputs[1][1]),
                "actuated": len(loop.source.inputs[0][1]),
                "pairs": next(o.shape[0] for o in loop.outputs if o.name == "alignment"),
                "outputs": {o.name: index for index, o in enumerate(loop.outputs)},
                "residual": "loop_closure",
                "pose": "platform_pose",
            },
            "modes": {"symbol": f"{mechanism.name}_forward_pose_all"} if meta.get("forward") else None,
            # the configuration example_main.c solves (chosen regular at generation time)
            "example": meta["example"],
        },
    }
