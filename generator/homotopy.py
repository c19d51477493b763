"""The generated parameter homotopy of a ``ForwardHomotopy``: its kernels, written in real
arithmetic (every complex quantity as a real and an imaginary part, so that every backend and
CasADi can print them), and its start solutions, found once here by monodromy.

H(z, s) = F(z; p(s)), p(s) = (1 - s) p_target + s p_start, with p the actuated variables and
parameters, p_start a random complex instance (seeded, 3 decimals: exactly representable in every
printer), and F the mechanism's equations plus, for homogeneous unknowns, the random complex patch
a . z_h = 1. A straight segment from a generic complex p_start to any real target misses the
discriminant (complex codimension 1) with probability one, so each path is smooth until s = 0.

Start solutions: one solution of a random instance is made by choosing z and then the actuated
values that fit it (when the equations are linear in the squares of the actuated values: leg
lengths); monodromy loops p_start -> p1 -> p2 -> p_start with random complex p1, p2 permute the
solutions; a loop's endpoints are added until ``STABLE_LOOPS`` loops in a row bring nothing new
(the trace test is not attempted: the count is compared with the known generic root count by the
tests). The solutions are refined by Newton in 40-digit mpmath arithmetic and sorted, so the
stored doubles do not depend on the machine's floating point.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import mpmath
import numpy as np
import sympy as sp

from .errors import GenerationError
from .model import ForwardHomotopy, Mechanism
from .program import Program

STABLE_LOOPS = 8
MAX_LOOPS = 80
DIGITS = 3


@dataclass
class HomotopySetup:
    programs: list[Program]
    metadata: dict[str, object]
    symbolic: dict[str, object]


Pair = tuple[sp.Expr, sp.Expr]


def split_complex(expr: sp.Expr, table: dict[sp.Symbol, Pair], cache: dict[sp.Expr, Pair] | None = None) -> Pair:
    """(Re, Im) of a polynomial expression whose symbols in ``table`` are complex (given as their
    real and imaginary parts); other symbols are real. Products are not expanded."""
    cache = {} if cache is None else cache
    if expr in cache:
        return cache[expr]
    if expr in table:
        result = table[expr]
    elif expr == sp.I:
        result = (sp.Integer(0), sp.Integer(1))
    elif expr.is_Number or expr.is_Symbol:
        result = (expr, sp.Integer(0))
    elif isinstance(expr, sp.Add):
        parts = [split_complex(a, table, cache) for a in expr.args]
        result = (sp.Add(*(p[0] for p in parts)), sp.Add(*(p[1] for p in parts)))
    elif isinstance(expr, sp.Mul):
        result = (sp.Integer(1), sp.Integer(0))
        for factor in expr.args:
            re, im = split_complex(factor, table, cache)
            result = (result[0] * re - result[1] * im, result[0] * im + result[1] * re)
    elif isinstance(expr, sp.Pow) and expr.exp.is_Integer and expr.exp > 0:
        base = split_complex(expr.base, table, cache)
        result = (sp.Integer(1), sp.Integer(0))
        for _ in range(int(expr.exp)):
            result = (result[0] * base[0] - result[1] * base[1], result[0] * base[1] + result[1] * base[0])
    else:
        raise GenerationError(f"homotopy equations must be polynomials; cannot split {expr}")
    cache[expr] = result
    return result


def _random_complex(rng: np.random.Generator, count: int) -> list[complex]:
    values = np.round(rng.normal(size=(count, 2)), DIGITS)
    return [complex(a, b) for a, b in values]


def _exact(value: float) -> sp.Rational:
    return sp.Rational(repr(float(value)))


def _vectorised(expressions: list[sp.Expr], arguments: list[sp.Symbol]) -> Callable[..., np.ndarray]:
    """numpy function of arrays (broadcasting) returning (..., len(expressions))."""
    function = sp.lambdify(arguments, expressions, modules="numpy", cse=True)

    def evaluate(*values: np.ndarray) -> np.ndarray:
        shape = np.broadcast_shapes(*(np.shape(v) for v in values))
        out = function(*values)
        return np.stack([np.broadcast_to(np.asarray(o, dtype=complex), shape) for o in out], axis=-1)

    return evaluate


def build(
    mechanism: Mechanism, actuated: tuple[str, list[sp.Symbol]], params: tuple[str, list[sp.Symbol]]
) -> HomotopySetup:
    forward = mechanism.forward
    assert isinstance(forward, ForwardHomotopy)
    rng = np.random.default_rng(forward.seed)
    unknowns = list(forward.unknowns)
    n = len(unknowns)
    equations = [sp.expand(e) for e in forward.equations]
    if forward.homogeneous:
        patch = _random_complex(rng, len(forward.homogeneous))
        terms = ((_exact(a.real) + sp.I * _exact(a.imag)) * v for a, v in zip(patch, forward.homogeneous, strict=True))
        equations.append(sp.Add(*terms) - 1)
    if len(equations) != n:
        raise GenerationError(f"{mechanism.name}: the homotopy has {len(equations)} equations for {n} unknowns")
    free = set().union(*(e.free_symbols for e in equations)) - set(unknowns) - {sp.I}
    varying = [v for v in list(mechanism.actuated) + list(mechanism.parameters) if v in free]
    stray = free - set(varying)
    if stray:
        raise GenerationError(f"{mechanism.name}: homotopy equations use {sorted(map(str, stray))}")
    start_values = _random_complex(rng, len(varying))

    key = hashlib.sha256(repr((2, forward.seed, [sp.srepr(e) for e in equations], [str(v) for v in varying])).encode())
    cached = _cache_path(key.hexdigest())
    if cached.exists():
        stored = json.loads(cached.read_text())
        start_values = [complex(*v) for v in stored["instance"]]
        solutions = [[complex(*c) for c in row] for row in stored["solutions"]]
        second_values = [complex(*v) for v in stored["second_instance"]]
        second_solutions = [[complex(*c) for c in row] for row in stored["second_solutions"]]
    else:
        # numeric system for the monodromy: F, F_z and the directional derivative in p
        direction = sp.symbols(f"dp0:{len(varying)}")
        jacobian = sp.Matrix(equations).jacobian(unknowns)
        directional = [sp.Add(*(sp.diff(e, v) * d for v, d in zip(varying, direction, strict=True))) for e in equations]
        args = unknowns + varying
        numeric = (
            _vectorised(equations, args),
            _vectorised(list(jacobian), args),
            _vectorised(directional, args + list(direction)),
        )
        instance, point = _start_instance(mechanism, varying, numeric, np.array(start_values), rng, n)
        start_values = [complex(v) for v in instance]
        found = _monodromy(mechanism, numeric, instance, point, rng, n)
        solutions = _refine_exact(equations, jacobian, unknowns, varying, instance, found)
        # a second start system, for inputs where a path of the first fails: its own random
        # instance, its solutions followed from the first (a path failing from both is unlikely)
        second = np.array(_random_complex(np.random.default_rng(forward.seed + 1), len(varying)))
        second_values = [complex(v) for v in second]
        from parakin.homotopy import PATH_REACHED, track

        moved = track(_segment(numeric, instance, second, n), np.array(solutions))
        if not (moved.status == PATH_REACHED).all():
            raise GenerationError(f"{mechanism.name}: the second start system could not be reached from the first")
        second_solutions = _refine_exact(equations, jacobian, unknowns, varying, second, moved.z)
        spread = np.array(second_solutions)
        gaps = np.abs(spread[:, None] - spread[None]).max(-1) + np.eye(len(spread))
        if not gaps.min() > 1e-6:
            raise GenerationError(f"{mechanism.name}: two paths to the second start system met")
        record = {
            "instance": [[v.real, v.imag] for v in start_values],
            "solutions": [[[c.real, c.imag] for c in row] for row in solutions],
            "second_instance": [[v.real, v.imag] for v in second_values],
            "second_solutions": [[[c.real, c.imag] for c in row] for row in second_solutions],
        }
        cached.parent.mkdir(parents=True, exist_ok=True)
        partial = cached.with_suffix(f".{os.getpid()}.tmp")
        partial.write_text(json.dumps(record))
        partial.replace(cached)

    # the generated kernel: the coefficients of every equation as polynomials in s
    coefficients, powers = _quadric_coefficients(equations, unknowns, varying, start_values)
    alternative, powers_second = _quadric_coefficients(equations, unknowns, varying, second_values)
    if powers_second != powers:
        raise GenerationError(f"{mechanism.name}: the two start systems give coefficients of different degrees in s")
    system = Program(
        "homotopy_coefficients",
        "Coefficients of the homotopy H(z, s) = F(z; (1 - s) p + s p_start) as polynomials in s: "
        "flat index ((part * POWERS + d) * EQUATIONS + k) * TERMS + t for part 0 (real) / 1 (imaginary), "
        "the coefficient of s^d, equation k and term t: the symmetric matrix M (t = i * n + j) of the "
        "quadratic part z^T M z, then the linear part (t = n * n + i), then the constant (t = n * n + n). "
        "'alternative': the same from the second start instance.",
        [actuated, params],
        [("coefficients", sp.Matrix(coefficients)), ("alternative", sp.Matrix(alternative))],
    )
    z_real = sp.symbols(f"z0:{n}", real=True)
    passive = sp.Matrix(forward.passive).subs(dict(zip(unknowns, z_real, strict=True)), simultaneous=True)
    recover = Program(
        "homotopy_passive",
        "Passive variables of a real endpoint z of the homotopy (homogeneous unknowns scaled real).",
        [("z", list(z_real)), params],
        [("passive", passive)],
    )
    metadata = {
        "method": "homotopy",
        "unknowns": [str(u) for u in unknowns],
        "homogeneous": [unknowns.index(h) for h in forward.homogeneous],
        "degree": len(solutions),
        "paths": len(solutions),
        "powers": powers,
        "branches": [],
        "combinations": [[]],
        "degeneracies": [],
        "start": {
            "real": [[float(c.real) for c in row] for row in solutions],
            "imag": [[float(c.imag) for c in row] for row in solutions],
        },
        "alternative": {
            "real": [[float(c.real) for c in row] for row in second_solutions],
            "imag": [[float(c.imag) for c in row] for row in second_solutions],
        },
        "start_instance": {
            str(v): [float(value.real), float(value.imag)] for v, value in zip(varying, start_values, strict=True)
        },
    }
    symbolic = {"forward_equations": sp.Matrix(equations)}
    return HomotopySetup([system, recover], metadata, symbolic)


def _quadric_coefficients(
    equations: list[sp.Expr], unknowns: list[sp.Symbol], varying: list[sp.Symbol], start: list[complex]
) -> tuple[list[sp.Expr], int]:
    """The coefficients (real and imaginary parts, flat, see the kernel's doc) of every equation,
    of degree <= 2 in the unknowns, along p(s) = (1 - s) p + s p_start, by powers of s."""
    s = sp.Symbol("s_homotopy", real=True)
    n = len(unknowns)
    terms = n * n + n + 1
    along = {v: (1 - s) * v + s * (_exact(c.real) + sp.I * _exact(c.imag)) for v, c in zip(varying, start, strict=True)}
    tables = []  # per equation: term -> expression in s
    for equation in equations:
        polynomial = sp.Poly(sp.expand(equation.subs(along, simultaneous=True)), *unknowns)
        if polynomial.total_degree() > 2:
            raise GenerationError("homotopy equations must be of degree <= 2 in the unknowns")
        table: dict[int, sp.Expr] = {}
        for exponents, coefficient in polynomial.terms():
            used = [k for k, e in enumerate(exponents) for _ in range(e)]
            if len(used) == 2:
                i, j = used
                if i == j:
                    table[i * n + i] = coefficient
                else:
                    table[i * n + j] = table[j * n + i] = coefficient / 2
            elif len(used) == 1:
                table[n * n + used[0]] = coefficient
            else:
                table[n * n + n] = coefficient
        tables.append({t: sp.Poly(sp.expand(c), s) for t, c in table.items()})
    powers = 1 + max(p.degree() for table in tables for p in table.values())
    flat: list[sp.Expr] = [sp.Integer(0)] * (2 * powers * len(equations) * terms)
    for k, table in enumerate(tables):
        for t, polynomial in table.items():
            for (d,), coefficient in polynomial.terms():
                re, im = split_complex(sp.expand(coefficient), {})
                flat[((0 * powers + d) * len(equations) + k) * terms + t] = re
                flat[((1 * powers + d) * len(equations) + k) * terms + t] = im
    return flat, powers


def _cache_path(key: str) -> Path:
    """Where the start systems of these equations are kept between builds (the computation is
    deterministic, the cache only saves its minutes): $PARAKIN_CACHE/homotopy, else
    ~/.cache/parakin/homotopy (the compiled backend's cache root); an empty folder recomputes."""
    root = os.environ.get("PARAKIN_CACHE", str(Path.home() / ".cache" / "parakin"))
    return Path(root) / "homotopy" / f"{key}.json"


def _start_instance(mechanism: Mechanism, varying: list[sp.Symbol], numeric, values: np.ndarray, rng, n: int):
    """A random complex instance and one of its solutions: a random z is first put on the
    equations free of actuated variables (Study quadric, patch: least-squares Newton), then each
    actuated variable is fitted to it (the equations are affine in its square, as leg equations
    are in l_i^2) and rounded like every other value, and z is corrected to the rounded instance."""
    residual, jacobian, _ = numeric
    actuated = [k for k, v in enumerate(varying) if v in mechanism.actuated]
    instance = values.copy()
    instance[actuated] = 0.0
    point = np.array(_random_complex(rng, n))
    baseline = residual(*point, *instance)
    free_rows = [
        r for r in range(n) if all(residual(*point, *_with(instance, k, 1.0))[r] == baseline[r] for k in actuated)
    ]
    for _ in range(30):
        value = residual(*point, *instance)[free_rows]
        matrix = jacobian(*point, *instance).reshape(n, n)[free_rows]
        point = point - np.linalg.lstsq(matrix, value, rcond=None)[0]
    at_zero = residual(*point, *instance)
    for k in actuated:
        slope = residual(*point, *_with(instance, k, 1.0)) - at_zero
        row = int(np.argmax(np.abs(slope)))
        root = np.sqrt(-at_zero[row] / slope[row])
        instance[k] = complex(round(root.real, DIGITS), round(root.imag, DIGITS))
    for _ in range(30):
        value = residual(*point, *instance)
        point = point - np.linalg.solve(jacobian(*point, *instance).reshape(n, n), value)
    if not np.abs(residual(*point, *instance)).max() < 1e-10:
        raise GenerationError(f"{mechanism.name}: could not make a start solution for the homotopy")
    return instance, point


def _with(values: np.ndarray, index: int, value: complex) -> np.ndarray:
    out = values.copy()
    out[index] = value
    return out


def _monodromy(mechanism: Mechanism, numeric, instance: np.ndarray, point: np.ndarray, rng, n: int) -> np.ndarray:
    """Every solution of the instance reached by monodromy loops from ``point``."""
    from parakin.homotopy import PATH_REACHED, is_known, track

    residual = numeric[0]
    known = point[None, :]
    stable = 0
    for _ in range(MAX_LOOPS):
        first, second = (np.array(_random_complex(rng, instance.size)) for _ in range(2))
        z, ok = known, np.ones(known.shape[0], bool)
        for p_from, p_to in ((instance, first), (first, second), (second, instance)):
            paths = track(_segment(numeric, p_from, p_to, n), z)
            ok &= paths.status == PATH_REACHED
            z = paths.z
        added = 0
        for candidate in z[ok]:
            if not np.abs(residual(*candidate, *instance)).max() < 1e-8:
                continue
            if not is_known(known, candidate):
                known = np.vstack([known, candidate])
                added += 1
        stable = 0 if added else stable + 1
        if stable >= STABLE_LOOPS:
            return known
    raise GenerationError(f"{mechanism.name}: monodromy did not settle in {MAX_LOOPS} loops ({len(known)} solutions)")


def _segment(numeric, p_from: np.ndarray, p_to: np.ndarray, n: int):
    """The tracker's system along the straight segment from p_from (s = 1) to p_to (s = 0)."""
    residual, jacobian, directional = numeric
    step = p_from - p_to

    def system(index, z, s):
        p = p_to[None, :] + s[:, None] * step[None, :]
        columns = [z[:, k] for k in range(n)] + [p[:, k] for k in range(p.shape[1])]
        rate = directional(*columns, *[np.full(z.shape[0], d) for d in step])
        return residual(*columns), jacobian(*columns).reshape(z.shape[0], n, n), rate

    return system


def _refine_exact(
    equations, jacobian, unknowns, varying, instance: np.ndarray, found: np.ndarray
) -> list[list[complex]]:
    """Newton in 40-digit arithmetic from each double-precision solution, then rounded to the
    nearest double and sorted: the stored start system is the same on every machine."""
    arguments = list(unknowns) + list(varying)
    residual = sp.lambdify(arguments, equations, modules="mpmath")
    matrix = sp.lambdify(arguments, jacobian, modules="mpmath")
    refined = []
    with mpmath.workdps(40):
        parameters = [mpmath.mpc(mpmath.mpf(repr(float(v.real))), mpmath.mpf(repr(float(v.imag)))) for v in instance]
        for row in found:
            z = [mpmath.mpc(complex(c)) for c in row]
            for _ in range(8):
                value = mpmath.matrix(residual(*z, *parameters))
                step = mpmath.lu_solve(mpmath.matrix(matrix(*z, *parameters)), value)
                z = [a - b for a, b in zip(z, step, strict=True)]
            if mpmath.norm(mpmath.matrix(residual(*z, *parameters))) > mpmath.mpf(10) ** -30:
                raise GenerationError("a start solution did not refine to 30 digits")
            refined.append([complex(float(c.real), float(c.imag)) for c in z])
    refined.sort(key=lambda row: tuple(x for c in row for x in (round(c.real, 9), round(c.imag, 9))))
    return refined
