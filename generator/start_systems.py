"""The generated parameter homotopy of a polynomial family (a mechanism's hand-written
``ForwardHomotopy`` or the polynomial form the generator derives from its closure,
``generator/polynomial_form.py``): its kernels, written in real arithmetic (every complex
quantity as a real and an imaginary part, so that every backend and CasADi can print them), its
start solutions, found once here by monodromy, and the proof that they are all of them.

H(z, s) = F(z; q(s)), q(s) = (1 - s) q_target + s q_start, with q the family's parameters and
q_start a random complex instance (seeded, 3 decimals: exactly representable in every printer).
A straight segment from a generic complex q_start to any target misses the discriminant
(complex codimension 1) with probability one, so each path is smooth until s = 0, and every
isolated solution of the target ends some path (Morgan and Sommese).

Start solutions, for any family: a random complex point (z, q) is pulled onto the incidence
variety F(z; q) = 0 by Gauss-Newton in z and q together (minimum-norm steps), the parameters are
rounded and z corrected; monodromy loops q_start -> q1 -> q2 -> q_start with random complex q1,
q2 permute the solutions; a loop's endpoints are added until ``STABLE_LOOPS`` loops bring nothing
new. The count is then *proven* by the trace test (Leykin, Rodriguez and Sottile, "Trace test",
2018, in the form of HomotopyContinuation.jl's verify_solution_completeness): on the curve
{(z, l): F(z; q_start + l v) = 0} the witness points of the pencil (a . z - 1) l + t = 0 are the
fibre's solutions (l = 0) and the curve's points on the hyperplane a . z = 1 (found by their own
monodromy); their sum moves on a line as t moves iff the set is complete. Generation fails, saying
why, when the test does not close. Solutions are refined in 40-digit mpmath arithmetic and sorted,
so the stored doubles do not depend on the machine.

That curve's hyperplane section grows fast with the family (the Hexaglide's 80 solutions: more
than 1200 witnesses), so it is tried only up to ``TRACE_MAX_SOLUTIONS``; families with a Bezout
number up to ``TOTAL_DEGREE_MAX`` are proven by total-degree runs instead (``_total_degree_bound``),
minutes for 8192 paths. Families above ``VALUE_FIRST_PATHS`` paths first try the value curve
(issue 32 item 3): C = {(z, l): F(z; q) + l w = 0}, the preimage of a random line through 0 under
z -> F(z; q). The z-space is irreducible, so monodromy in the values (loops of F(z; q) = c) reaches
every solution and C is irreducible where 0 is a generic value; the same pencil's trace test
(``value_trace_test``) then needs C's points on a . z = 1, far fewer (the Hexaglide's: 128). Where
0 is not a generic value (solutions at infinity over it: the tricept's) the trace stays off its
line and the older methods take over; the test never closes on a short set. Measured, generation
with the count proven, seconds of CPU: Hexaglide 232 -> 31 (80 solutions, 128 witnesses; the
same 80 as two total-degree runs of 8192 paths found).

The total-degree runs track the equilibrated system (``equilibration``: each equation scaled by a
power of two to unit geometric-mean coefficient; the same solutions) and judge their endpoints
on it: a family whose equations differ in size by 1e4 or more (the skew 3-RRS, tests/fixtures)
otherwise still follows the start system's smaller equations at the endgame's t and ends
outside Newton's basins (21-22 of its 32 solutions per run; equilibrated, 32 in each of six
runs: proven in 72 s of CPU). Where such a family's solutions leave a double-precision Newton
step at its rounding level (1e-10 to 2e-9 there), 40-digit Newton decides.

Where the mechanism's own values satisfy relations that lower the generic count (parameters
sharing a value: a user's Hexaglide with two sliders on each of three shared rails keeps 72 of the
family's 80 solutions, 8 at infinity for every input; ``generator/subfamily.py``), the start
instances are drawn in the subfamily those relations cut out (linear: the runtime's segment from a
start instance there to the mechanism's inputs stays in it) and its count is proven (Hexaglide: 72
by the value curve's trace test, 28 s of CPU); the manifest's ``subfamily`` names the relations,
which parameters loaded with other values break. A stored record of the family is kept where its
solutions, followed to a random member of the subfamily, all stay finite and distinct.

Parameters that share a value only by the user's choice (a layout with coordinates at zero: the
planar 3-RPR of docs/tutorials/my_robot.py, base_x1 = base_y1 = base_y2 = 0) must not tie the
proof to that choice. The rule (budget ``GENERIC_MAX_PATHS``): where the relations pair parameters,
no record is stored and the Bezout number is at most ``GENERIC_MAX_PATHS`` (total-degree runs of
seconds), the count is first proven for any parameter values (the family, restricted to its
constant values only: those no parameter changes) and kept, with no ``subfamily`` in the
manifest, where it is proven and its solutions, followed to a random member of the subfamily,
all stay finite, regular and distinct (the rule for stored records); otherwise (the shared-rail
Hexaglide: 8 of 80 go to infinity, and 8192 paths are over the budget) the subfamily's proof
follows. A generic count that is not proven is never kept (nor stored).

The runtime form is sparse: a table of monomials (equation, exponents) and, per input, each
monomial's coefficient as a polynomial in s.
"""

from __future__ import annotations

import copy
import hashlib
import json
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import mpmath
import numpy as np
import sympy as sp

from parakin.log import logger

from .errors import GenerationError
from .polynomial_form import MOEBIUS_A, MOEBIUS_B, PolynomialForm, circle_parametrisation
from .program import Program
from .subfamily import Relations, family_relations

STABLE_LOOPS = 6
START_ATTEMPTS = 8
#: version of monodromy's stopping rule (STABLE_LOOPS + solutions // 8 quiet loops, then
#: COMPONENT_PROBES fruitless random fibre Newton starts)
STABLE_RULE = 3
MAX_LOOPS = 120
DIGITS = 3
#: the trace test's tolerance: relative third singular value of the traces at three t
TRACE_TOLERANCE = 1e-8
#: rounds of witness monodromy before the trace test is given up
TRACE_ROUNDS = 2
#: points of the parameter line whose fibres seed the trace test's witnesses
SEED_LINES = 6
#: the trace test's budget: rounds of witness monodromy loops, a trace computed after each
WITNESS_ROUNDS = 8
#: the largest start system whose count the trace test proves (see start_systems)
TRACE_MAX_SOLUTIONS = 24
WITNESS_LOOPS = 3
#: random Newton starts in a row that find nothing new before every component is believed found
COMPONENT_PROBES = 48
#: the value-space proof (``value_monodromy``, ``value_trace_test``): quiet value loops before a
#: trace test (and one more per 16 solutions); fibre solutions carried along this many lines to
#: seed the witnesses; rounds of witness loops (a trace after each) that find no new witness
#: before the test is given up, and the most rounds; the pencil's |t| over the fibre's median
#: |a . z - 1|; the witness loops' size over the random offsets' (larger loops reach the far
#: witnesses: the Hexaglide's 128 in 3 rounds in 4 of 5 seeds, at 1.0 in 2 of 4); the trace tests
#: tried (each after more value loops) before the older methods
VALUE_QUIET_LOOPS = 3
VALUE_SEED_LINES = 3
VALUE_TRACE_ROUNDS = 3
VALUE_TRACE_MAX_ROUNDS = 20
VALUE_PENCIL_T = 0.5
VALUE_LOOP_SIZE = 3.0
VALUE_ATTEMPTS = 2
#: families whose Bezout number is above this try the value curve's trace test first
VALUE_FIRST_PATHS = 2048
#: the value curve's trace test closes below this twice in a row (stricter than TRACE_TOLERANCE,
#: which the manifest states: complete sets measure 1e-16..2e-12, one missing solution of the
#: Hexaglide or the 3-RPR 1e-3..5e-2, one missing far witness of the Hexaglide 9e-11..3e-9)
VALUE_TRACE_TOLERANCE = 1e-11
VALUE_TRACE_METHOD = "trace test (Leykin, Rodriguez, Sottile 2018) on the value curve F(z; q) + l w = 0"
CACHE_VERSION = 3
#: the proof's fields in the manifest, in this order
PROOF_KEYS = ("method", "proven", "stable_rule", "witnesses", "trace_deviation", "bezout_paths", "regular_endpoints")
#: a family whose mechanism's parameters share values (``generator/subfamily.py``) and that has no
#: stored record gets the proof for any parameter values first where its Bezout number is at most
#: this (see start_systems: total-degree runs of these paths take seconds, 30 s at 864)
GENERIC_MAX_PATHS = 1024
#: families with a Bezout number up to this get the total-degree bound (see ``total_degree_run``)
TOTAL_DEGREE_MAX = 10000
#: the total-degree homotopy's independent runs (another gamma and patch each) that must each
#: find the whole joined set, and how many are tried at most while fewer do
TOTAL_DEGREE_RUNS = 2
TOTAL_DEGREE_MAX_RUNS = 4
TOTAL_DEGREE_METHOD = "total-degree homotopy"
#: a run's paths are tracked in parts of at least this many, a progress line with an estimate
#: after each (the same endpoints: paths are tracked independently)
TOTAL_DEGREE_PART = 512
#: in the method of runs that tracked the equilibrated system (``equilibration``): an unproven
#: record without it (21-22 of the skew 3-RRS's 32 per run) is run again by today's rule
TOTAL_DEGREE_EQUILIBRATED = "equations equilibrated"
#: the total-degree paths stop at this t (the endgame boundary) and Newton on F finishes: a path
#: to a regular root is then within its basin, one to a singular endpoint costs no step halving
ENDGAME_T = 1e-6
#: the equilibration's fit (``equilibration``) leaves out a coefficient below this fraction of its
#: equation's largest (the rounding residue of a cancelled term: 2e-23 beside 6e-3 in the skew
#: 3-RRS's)
SCALING_FLOOR = 1e-10
#: endpoints that Newton in doubles leaves with a step below this (but above ``_regular``'s 1e-10,
#: the rounding level of a badly scaled family's equations) are judged again in 40 digits
REGULAR_RECHECK = 1e-6


@dataclass
class HomotopySetup:
    programs: list[Program]
    metadata: dict[str, object]
    symbolic: dict[str, object]


Pair = tuple[sp.Expr, sp.Expr]


def split_complex(expr: sp.Expr, table: dict[sp.Symbol, Pair], cache: dict[sp.Expr, Pair] | None = None) -> Pair:
    """(Re, Im) of a polynomial expression whose symbols in ``table`` are complex (given as their
    real and imaginary parts); other symbols and numbers are real. Products are not expanded."""
    cache = {} if cache is None else cache
    if expr in cache:
        return cache[expr]
    if expr in table:
        result = table[expr]
    elif expr == sp.I:
        result = (sp.Integer(0), sp.Integer(1))
    elif expr.is_number:
        re, im = expr.as_real_imag()
        result = (re, im)
    elif expr.is_Symbol:
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
    elif not (expr.free_symbols & set(table)):
        result = (expr, sp.Integer(0))  # a real expression of real symbols (a family parameter's value)
    else:
        raise GenerationError(f"homotopy equations must be polynomials; cannot split {expr}")
    cache[expr] = result
    return result


def _random_complex(rng: np.random.Generator, count: int) -> np.ndarray:
    values = np.round(rng.normal(size=(count, 2)), DIGITS)
    return values[:, 0] + 1j * values[:, 1]


def _exact(value: complex) -> sp.Expr:
    return sp.Rational(repr(float(value.real))) + sp.I * sp.Rational(repr(float(value.imag)))


class Family:
    """The numeric family F(z; q) of a polynomial form: q = the free parameters, then one circle
    parameter u per angle (C, S, D replaced by their polynomials in u)."""

    def __init__(self, form: PolynomialForm, equations: list[sp.Expr]) -> None:
        self.unknowns = list(form.unknowns)
        self.free = [symbol for symbol, _ in form.family if any(e.has(symbol) for e in equations)]
        self.circles = [u for u, _, _ in form.circles]
        self.parameters = self.free + self.circles
        circle_values: dict[sp.Symbol, sp.Expr] = {}
        chain: dict[sp.Symbol, list[tuple[sp.Symbol, sp.Expr]]] = {}
        for u, _, symbols in form.circles:
            polynomials = circle_parametrisation(u)
            circle_values.update(zip(symbols, polynomials, strict=True))
            chain[u] = [(c, sp.diff(p, u)) for c, p in zip(symbols, polynomials, strict=True)]
        # derivatives taken in (C, S, D) before the circle polynomials go in (chain rule for u):
        # far cheaper than differentiating the substituted products
        matrix = sp.Matrix(equations)

        def substituted(entries: sp.Matrix) -> list[sp.Expr]:
            return [e.xreplace(circle_values) for e in entries]

        by_u = [[sp.Add(*(sp.diff(e, c) * dc for c, dc in chain[u])) for u in self.circles] for e in equations]
        self.equations = substituted(matrix)
        self.n, self.m = len(self.unknowns), len(self.parameters)
        args = self.unknowns + self.parameters
        jacobian_z = matrix.jacobian(self.unknowns)
        jacobian_free = matrix.jacobian(self.free) if self.free else sp.zeros(len(equations), 0)
        jacobian_q = sp.Matrix.hstack(jacobian_free, sp.Matrix(by_u)) if self.circles else jacobian_free
        self._value = sp.lambdify(args, self.equations, modules="numpy", cse=True)
        self._jz = sp.lambdify(args, substituted(jacobian_z), modules="numpy", cse=True)
        self._jq = sp.lambdify(args, substituted(jacobian_q), modules="numpy", cse=True)
        self.jacobian_z = sp.Matrix(jacobian_z.rows, jacobian_z.cols, substituted(jacobian_z))
        self._terms: MonomialTable | None = None
        #: None: q is the family's values; else q is the coordinates t of the subfamily
        self.relations: Relations | None = None

    def restricted(self, relations: Relations) -> Family:
        """The same family on the subfamily of ``relations`` (``generator/subfamily.py``): its
        parameters q are the subfamily's coordinates t, every method maps them to the family's
        values, so that monodromy, trace tests and total-degree runs move inside the subfamily."""
        restricted = copy.copy(self)
        restricted.relations, restricted.m, restricted._terms = relations, relations.size, None
        return restricted

    def full(self, q: np.ndarray) -> np.ndarray:
        """The family's values at parameters q (the subfamily's coordinates where restricted)."""
        return q if self.relations is None else self.relations.full(q)

    def terms(self) -> MonomialTable:
        """The equations as monomials in the unknowns with coefficients in the parameters (built
        once, for the 40-digit refinement)."""
        if self._terms is None:
            self._terms = MonomialTable(self.equations, self.unknowns, self.parameters, self.relations)
        return self._terms

    def _call(self, function, z: np.ndarray, q: np.ndarray, width: int | None) -> np.ndarray:
        """``function``'s outputs at (z, q), broadcast: a vector, or rows of ``width`` columns
        (a matrix even when one row or one column, as with a single unknown)."""
        q = self.full(q)
        shape = np.broadcast_shapes(z.shape[:-1], q.shape[:-1])
        columns = [z[..., k] for k in range(self.n)] + [q[..., k] for k in range(len(self.parameters))]
        out = function(*columns)
        return np.stack([np.broadcast_to(np.asarray(o, dtype=complex), shape) for o in out], axis=-1).reshape(
            shape + ((len(out),) if width is None else (len(out) // width, width))
        )

    def value(self, z: np.ndarray, q: np.ndarray) -> np.ndarray:
        return self._call(self._value, z, q, None)

    def jacobian(self, z: np.ndarray, q: np.ndarray) -> np.ndarray:
        return self._call(self._jz, z, q, self.n)

    def parameter_jacobian(self, z: np.ndarray, q: np.ndarray) -> np.ndarray:
        jacobian = self._call(self._jq, z, q, len(self.parameters))
        return jacobian if self.relations is None else jacobian @ self.relations.matrix()


class MonomialTable:
    """Equations sum_t c_t(q) z^e_t in mpmath: the coefficients as one function of the parameters,
    the values and the Jacobian from the exponent table."""

    def __init__(
        self,
        equations: list[sp.Expr],
        unknowns: list[sp.Symbol],
        parameters: list[sp.Symbol],
        relations: Relations | None = None,
    ) -> None:
        self.relations = relations
        self.rows: list[list[tuple[int, ...]]] = []
        expressions: list[sp.Expr] = []
        for equation in equations:
            poly = sp.Poly(sp.expand(equation), *unknowns)
            self.rows.append([tuple(int(e) for e in monomial) for monomial in poly.monoms()])
            expressions += poly.coeffs()
        self.n = len(unknowns)
        self.degree = max(max(sum(m) for m in row) for row in self.rows)
        self._coefficients = sp.lambdify(parameters, expressions, modules="mpmath")

    def coefficients(self, *parameters: mpmath.mpc) -> list:
        """The coefficients at the parameters (the subfamily's coordinates where restricted)."""
        values = parameters if self.relations is None else self.relations.full_mp(parameters)
        return list(self._coefficients(*values))

    def evaluate(self, coefficients: list, z: list) -> tuple[mpmath.matrix, mpmath.matrix]:
        """F(z) and its Jacobian in z, at the working precision."""
        n = self.n
        powers = [[mpmath.mpc(1)] for _ in range(n)]
        for j in range(n):
            for _ in range(self.degree):
                powers[j].append(powers[j][-1] * z[j])
        value = mpmath.matrix(len(self.rows), 1)
        jacobian = mpmath.matrix(len(self.rows), n)
        index = 0
        for k, row in enumerate(self.rows):
            for exponents in row:
                c = coefficients[index]
                index += 1
                factors = [powers[j][e] for j, e in enumerate(exponents)]
                product = c
                for f in factors:
                    product = product * f
                value[k] += product
                for j, e in enumerate(exponents):
                    if e:
                        partial = c * e * powers[j][e - 1]
                        for i, f in enumerate(factors):
                            if i != j:
                                partial = partial * f
                        jacobian[k, j] += partial
        return value, jacobian


def _segment(family: Family, q_from: np.ndarray, q_to: np.ndarray):
    """The tracker's system along the straight segment from q_from (s = 1) to q_to (s = 0)."""
    step = q_from - q_to

    def system(index, z, s):
        q = q_to[None, :] + s[:, None] * step[None, :]
        return family.value(z, q), family.jacobian(z, q), family.parameter_jacobian(z, q) @ step

    return system


def _slice_system(family: Family, base: np.ndarray, target: np.ndarray):
    """The curve's points on a hyperplane, in (z, l): F(z; q + l v) = 0, a . z - 1 = 0, with
    (q, v, a) moving on the segment from ``base`` (s = 1; one row per path, or one for all) to
    ``target`` (s = 0)."""
    n, m = family.n, family.m
    steps = np.atleast_2d(base - target)

    def system(index, w, s):
        step = steps[index] if steps.shape[0] > 1 else np.broadcast_to(steps, (len(s), steps.shape[1]))
        b = target[None, :] + s[:, None] * step
        q, v, a = b[:, :m], b[:, m : 2 * m], b[:, 2 * m :]
        z, lam = w[:, :n], w[:, n]
        at = q + lam[:, None] * v
        jq = family.parameter_jacobian(z, at)
        value = np.concatenate([family.value(z, at), ((a * z).sum(-1) - 1)[:, None]], axis=1)
        top = np.concatenate([family.jacobian(z, at), (jq @ v[..., None])], axis=2)
        bottom = np.concatenate([a, np.zeros((len(s), 1))], axis=1)[:, None, :]
        dq, dv, da = step[:, :m], step[:, m : 2 * m], step[:, 2 * m :]
        moving = jq @ (dq + lam[:, None] * dv)[..., None]
        rate = np.concatenate([moving, (z * da).sum(-1)[:, None, None]], 1)
        return value, np.concatenate([top, bottom], axis=1), rate[..., 0]

    return system


def _pencil_system(family: Family, q: np.ndarray, v: np.ndarray, a: np.ndarray, t_from: complex, t_to: complex):
    """The trace test's pencil in (z, l): F(z; q + l v) = 0, (a . z - 1) l + t = 0, t on a segment."""
    n = family.n
    step = t_from - t_to

    def system(index, w, s):
        z, lam = w[:, :n], w[:, n]
        at = q[None, :] + lam[:, None] * v[None, :]
        t = t_to + s * step
        linear = (a[None, :] * z).sum(-1) - 1
        value = np.concatenate([family.value(z, at), (linear * lam + t)[:, None]], axis=1)
        top = np.concatenate([family.jacobian(z, at), family.parameter_jacobian(z, at) @ v[:, None]], axis=2)
        bottom = np.concatenate([lam[:, None] * a[None, :], linear[:, None]], axis=1)[:, None, :]
        rate = np.zeros((len(s), n + 1), dtype=complex)
        rate[:, n] = step
        return value, np.concatenate([top, bottom], axis=1), rate

    return system


def _track(system, start: np.ndarray):
    from parakin.solvers.path_tracking import PATH_REACHED, track

    paths = track(system, start)
    return paths.z, paths.status == PATH_REACHED


def _add_new(known: np.ndarray, candidates: np.ndarray) -> tuple[np.ndarray, int]:
    from parakin.solvers.path_tracking import is_known

    added = 0
    for candidate in candidates:
        if not is_known(known, candidate):
            known = np.vstack([known, candidate])
            added += 1
    return known, added


def _loop(make_system, base: np.ndarray, found: np.ndarray, check, rng) -> tuple[np.ndarray, int]:
    """One monodromy loop base -> b1 -> b2 -> base (random complex b1, b2): every new endpoint
    that passes ``check`` joins ``found``; returns them and how many were new."""
    first = base + _random_complex(rng, base.size)
    second = base + _random_complex(rng, base.size)
    z, ok = found, np.ones(len(found), bool)
    for b_from, b_to in ((base, first), (first, second), (second, base)):
        z, reached = _track(make_system(b_from, b_to), z)
        ok &= reached
    z = z[ok]
    return _add_new(found, z[check(z)])


def _loops(make_system, base: np.ndarray, found: np.ndarray, check, rng, loops: int) -> np.ndarray:
    """``loops`` monodromy loops (``_loop``), whatever they find."""
    for _ in range(loops):
        found, _ = _loop(make_system, base, found, check, rng)
    return found


def _monodromy(name: str, make_system, base: np.ndarray, found: np.ndarray, check, rng, loops: int = MAX_LOOPS):
    """Every solution reached by monodromy loops, until enough loops in a row find nothing new.
    Every tenth loop is logged with the solutions so far and the quiet loops still needed."""
    stable = 0
    began = time.perf_counter()
    for loop in range(1, loops + 1):
        found, added = _loop(make_system, base, found, check, rng)
        stable = 0 if added else stable + 1
        # a larger set needs more quiet loops before it is believed (an unproven count rests on it)
        needed = STABLE_LOOPS + len(found) // 8
        if stable >= needed:
            return found
        if loop % 10 == 0:
            each = (time.perf_counter() - began) / loop
            logger.info(
                "%s: monodromy loop %d: %d solutions, %d more quiet loops needed (about %.0f s at %.1f s a loop)",
                name, loop, len(found), needed - stable, (needed - stable) * each, each,
            )  # fmt: skip
    raise GenerationError(f"{name}: monodromy did not settle in {loops} loops ({len(found)} solutions)")


def _other_components(name: str, family: Family, q: np.ndarray, found: np.ndarray, flips, rng) -> np.ndarray:
    """Monodromy stays on one irreducible component of the incidence variety; a family can have
    several (spm's closure v_i . v_j = cos psi holds for a triad and its mirror, det V = +-k with
    k polynomial in the parameters). Newton from random points of the fibre lands on any of them:
    each solution it finds that monodromy did not is the seed of another orbit. The trace test
    judges the union afterwards."""
    check = _solves(family, q)
    quiet = 0
    while quiet < COMPONENT_PROBES:
        z = _random_complex(rng, family.n) * 2
        with np.errstate(all="ignore"):
            for _ in range(60):
                try:
                    z = z - np.linalg.solve(family.jacobian(z[None], q[None])[0], family.value(z[None], q[None])[0])
                except np.linalg.LinAlgError:
                    break
        if not (np.isfinite(z).all() and np.abs(z).max() < 1e6 and check(z[None])[0]):
            quiet += 1
            continue
        _, added = _add_new(found, z[None])
        if not added:
            quiet += 1
            continue
        orbit = _monodromy(name, lambda a, b: _segment(family, a, b), q, z[None], check, rng)
        found = _closed(_add_new(found, orbit)[0], flips)
        quiet = 0
    return found


def _start_instance(name: str, family: Family, rng) -> tuple[np.ndarray, np.ndarray]:
    """A random complex instance and one of its solutions (module docstring); a few random points
    are tried where Newton does not settle (a point near a singular one)."""
    for _ in range(START_ATTEMPTS):
        z = _random_complex(rng, family.n)
        q = _random_complex(rng, family.m)
        for _ in range(60):
            value = family.value(z, q)
            matrix = np.concatenate([family.jacobian(z, q), family.parameter_jacobian(z, q)], axis=1)
            step = np.linalg.lstsq(matrix, value, rcond=None)[0]
            z, q = z - step[: family.n], q - step[family.n :]
            if np.abs(step).max() < 1e-14 * (1 + np.abs(np.concatenate([z, q])).max()):
                break
        q = np.round(q.real, DIGITS) + 1j * np.round(q.imag, DIGITS)
        with np.errstate(all="ignore"):
            for _ in range(40):
                z = z - np.linalg.lstsq(family.jacobian(z, q), family.value(z, q), rcond=None)[0]
        if newton_size(family, z[None, :], q).max() < 1e-10 and np.abs(z).max() < 1e6:
            return q, z
    raise GenerationError(f"{name}: could not make a start solution for the homotopy in {START_ATTEMPTS} attempts")


def sign_symmetries(family: Family, rng) -> list[np.ndarray]:
    """Sign flips of unknowns under which every equation is even or odd (q -> -q of a quaternion,
    the other Euler-angle triple): the solution set is closed under them, so a solution
    monodromy missed is its twin's image. Found by evaluation at a random point."""
    if family.n > 12:
        return []
    z, q = _random_complex(rng, family.n), _random_complex(rng, family.m)
    value = family.value(z, q)
    flips = []
    for mask in range(1, 2**family.n):
        sign = np.array([-1.0 if mask >> k & 1 else 1.0 for k in range(family.n)])
        flipped = family.value(sign * z, q)
        if np.all(
            (np.abs(flipped - value) < 1e-9 * (1 + np.abs(value)))
            | (np.abs(flipped + value) < 1e-9 * (1 + np.abs(value)))
        ):
            flips.append(sign)
    return flips


def _closed(found: np.ndarray, flips: list[np.ndarray]) -> np.ndarray:
    """``found`` with the images of its solutions under the sign symmetries."""
    for sign in flips:
        found, _ = _add_new(found, found * sign)
    return found


def newton_size(family: Family | _Scaled, z: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The size of a Newton step at solutions z (P, n) of F(.; q), relative to 1 + |z|: how far
    each is from a solution, whatever the scale of the equations' coefficients."""
    from parakin.solvers.path_tracking import _solve

    with np.errstate(all="ignore"):
        jacobian = family.jacobian(z, np.broadcast_to(q, (len(z), q.size)))
        value = family.value(z, np.broadcast_to(q, (len(z), q.size)))
        # row by row where one matrix is singular: one singular point spoils no other
        size = np.abs(_solve(jacobian, value)).max(-1) / (1 + np.abs(z).max(-1))
    return np.where(np.isfinite(size), size, np.inf)


def _solves(family: Family, q: np.ndarray):
    def check(z: np.ndarray) -> np.ndarray:
        if not len(z):
            return np.zeros(0, bool)
        return newton_size(family, z, q) < 1e-8

    return check


def trace_test(name: str, family: Family, q: np.ndarray, solutions: np.ndarray, rng) -> dict[str, object]:
    """Prove that ``solutions`` are every isolated solution of F(z; q) = 0 (module docstring):
    returns the witnesses found on the curve, the trace's deviation from a line and the verdict."""
    n, m = family.n, family.m
    v = _random_complex(rng, m)
    # a point of the curve off the fibre: a solution carried to q + v, and a hyperplane through it
    moved, reached = _track(_segment(family, q, q + v), solutions[:1])
    if not reached.all():
        raise GenerationError(f"{name}: trace test: could not leave the start fibre")
    point = moved[0]
    a = _random_complex(rng, n)
    a = a + (1 - a @ point) * np.conj(point) / (np.abs(point) ** 2).sum()
    base = np.concatenate([q, v, a])
    start = np.concatenate([point, [1.0]])[None, :]

    def on_slice(w: np.ndarray) -> np.ndarray:
        if not len(w):
            return np.zeros(0, bool)
        at = q[None, :] + w[:, n : n + 1] * v[None, :]
        value = np.abs(family.value(w[:, :n], at)).max(-1)
        size = np.abs(w).max(-1)
        return (value < 1e-8) & (np.abs(w[:, :n] @ a - 1) < 1e-8) & (np.abs(w[:, n]) > 1e-8) & (size < 1e6)

    # many witnesses at once: fibre solutions carried to a few points q + l v of the line lie on
    # the curve, each on its own hyperplane a . z = c; moving c to 1 takes each to a witness
    seeds, bases = [start], [base[None, :]]
    for lam in _random_complex(rng, SEED_LINES):
        moved, reached = _track(_segment(family, q, q + lam * v), solutions)
        for z in moved[reached]:
            c = a @ z
            if abs(c) > 1e-8:
                seeds.append(np.concatenate([z, [lam]])[None, :])
                bases.append(np.concatenate([q, v, a / c])[None, :])
    ended, reached = _track(_slice_system(family, np.concatenate(bases), base), np.concatenate(seeds))
    candidates = ended[reached]
    witnesses, _ = _add_new(start, candidates[on_slice(candidates)])
    deviation = np.inf
    for _ in range(WITNESS_ROUNDS):
        # a few more loops between trace computations: the trace test itself says when the
        # witnesses are complete (a missing one shows as a deviation too)
        witnesses = _loops(lambda b0, b1: _slice_system(family, b0, b1), base, witnesses, on_slice, rng, WITNESS_LOOPS)
        points = np.concatenate([np.concatenate([solutions, np.zeros((len(solutions), 1))], axis=1), witnesses])
        traces = [points.sum(0)]
        for _ in range(8):
            if len(traces) == 3:
                break
            t = complex(_random_complex(rng, 1)[0]) * 0.3
            ended, reached = _track(_pencil_system(family, q, v, a, 0.0, t), points)
            # a path that failed or met another (a jump) spoils the sum: another t
            if reached.all() and _smallest_gap(ended) > 1e-8:
                traces.append(ended.sum(0))
        if len(traces) < 3:
            raise GenerationError(f"{name}: trace test: the pencil's paths failed or met at every t tried")
        matrix = np.concatenate([np.ones((3, 1)), np.array(traces)], axis=1)
        singular = np.linalg.svd(matrix, compute_uv=False)
        deviation = float(singular[2] / singular[0])
        if deviation < TRACE_TOLERANCE:
            break
    return {"witnesses": len(witnesses), "deviation": deviation, "complete": deviation < TRACE_TOLERANCE}


def _value_system(family: Family, q: np.ndarray, c_from: np.ndarray, c_to: np.ndarray):
    """The tracker's system F(z; q) = c with the values c on the segment from c_from (s = 1) to
    c_to (s = 0): the family moved in its equations' values, not its parameters."""
    step = c_from - c_to
    qq = q[None, :]

    def system(index, z, s):
        at = np.broadcast_to(qq, (len(s), q.size))
        c = c_to[None, :] + s[:, None] * step[None, :]
        return family.value(z, at) - c, family.jacobian(z, at), np.broadcast_to(-step, z.shape).copy()

    return system


def _value_slice_system(family: Family, q: np.ndarray, w: np.ndarray, base: np.ndarray, target: np.ndarray):
    """The value curve's points on a hyperplane, in (z, l): F(z; q) + l w = 0, a . z - 1 = 0, with
    a on the segment from ``base`` (s = 1; one row per path, or one for all) to ``target``."""
    n = family.n
    steps = np.atleast_2d(base - target)
    qq = q[None, :]

    def system(index, v, s):
        step = steps[index] if steps.shape[0] > 1 else np.broadcast_to(steps, (len(s), n))
        a = target[None, :] + s[:, None] * step
        z, lam = v[:, :n], v[:, n]
        at = np.broadcast_to(qq, (len(s), q.size))
        value = np.concatenate([family.value(z, at) + lam[:, None] * w[None, :], ((a * z).sum(-1) - 1)[:, None]], 1)
        top = np.concatenate([family.jacobian(z, at), np.broadcast_to(w[None, :, None], (len(s), n, 1))], axis=2)
        bottom = np.concatenate([a, np.zeros((len(s), 1))], axis=1)[:, None, :]
        rate = np.concatenate([np.zeros((len(s), n), complex), (z * step).sum(-1)[:, None]], axis=1)
        return value, np.concatenate([top, bottom], axis=1), rate

    return system


def _value_pencil_system(family: Family, q: np.ndarray, w: np.ndarray, a: np.ndarray, t_to: complex):
    """The pencil on the value curve, in (z, l): F(z; q) + l w = 0, (a . z - 1) l + t = 0, t on the
    segment from 0 (s = 1) to ``t_to`` (s = 0)."""
    n = family.n
    qq = q[None, :]

    def system(index, v, s):
        z, lam = v[:, :n], v[:, n]
        at = np.broadcast_to(qq, (len(s), q.size))
        linear = (a[None, :] * z).sum(-1) - 1
        value = np.concatenate(
            [family.value(z, at) + lam[:, None] * w[None, :], (linear * lam + t_to * (1 - s))[:, None]], 1
        )
        top = np.concatenate([family.jacobian(z, at), np.broadcast_to(w[None, :, None], (len(s), n, 1))], axis=2)
        bottom = np.concatenate([lam[:, None] * a[None, :], linear[:, None]], axis=1)[:, None, :]
        rate = np.zeros((len(s), n + 1), dtype=complex)
        rate[:, n] = -t_to
        return value, np.concatenate([top, bottom], axis=1), rate

    return system


def value_scale(family: Family, q: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Each equation's natural size near the solutions z (P, n) of F(.; q): the norm of its
    Jacobian row times 1 + |z|, the change of its value over a move of z by its own size (the
    value loops and the trace test's direction w move each equation by about this)."""
    at = np.broadcast_to(q, (len(z), q.size))
    rows = np.abs(family.jacobian(z, at)).max(-1) * (1 + np.abs(z).max(-1))[:, None]
    return np.maximum(np.median(rows, axis=0), 1e-12)


def value_monodromy(
    name: str, family: Family, q: np.ndarray, found: np.ndarray, flips, rng, quiet_loops: int = VALUE_QUIET_LOOPS
) -> np.ndarray:
    """The solutions of F(z; q) = 0 that monodromy in the equations' values reaches: loops
    0 -> c1 -> c2 -> 0 of F(z; q) = c (random complex c1, c2 at each equation's scale) permute the
    solutions, until ``quiet_loops`` loops in a row bring nothing new. The z-space is irreducible,
    so when 0 is a generic value these loops act transitively on the solutions (no component is
    out of reach as in the parameters' monodromy); completeness is the trace test's to judge
    (``value_trace_test``), not this stopping rule's."""
    check = _solves(family, q)
    scale = value_scale(family, q, found)
    base = np.zeros(family.n, complex)
    quiet = 0
    began = time.perf_counter()
    for loop in range(1, MAX_LOOPS + 1):
        found, added = _loop(lambda b0, b1: _value_system(family, q, scale * b0, scale * b1), base, found, check, rng)
        grown = _closed(found, flips)
        added += len(grown) - len(found)
        found = grown
        quiet = 0 if added else quiet + 1
        if quiet >= quiet_loops + len(found) // 16:
            break
        if loop % 10 == 0:
            logger.info(
                "%s: value monodromy loop %d: %d solutions (%.1f s a loop)",
                name, loop, len(found), (time.perf_counter() - began) / loop,
            )  # fmt: skip
    return found


def value_trace_test(name: str, family: Family, q: np.ndarray, solutions: np.ndarray, rng) -> dict[str, object]:
    """Prove that ``solutions`` are every isolated solution of F(z; q) = 0 by the trace test
    (Leykin, Rodriguez and Sottile 2018) on the value curve C = {(z, l): F(z; q) + l w = 0}, w a
    random complex direction: C is the preimage of a generic line through 0 under the map
    z -> F(z; q) of the irreducible z-space, so (Zariski: a generic line's loops reach the whole
    monodromy group) it is irreducible wherever 0 is a generic value, and every regular isolated
    solution is a point of C over l = 0. The witness points of the pencil (a . z - 1) l + t = 0 at
    t = 0 are the fibre's solutions and C's points on a . z = 1 (found by monodromy of that
    hyperplane); their sum moves on a line as t moves iff the set is complete. A missing
    solution, a singular one, or solutions at infinity over l = 0 (0 not a generic value) each
    leave the trace off its line: the test then fails, it never passes short.

    The deviation is scale-free: the trace's secant slopes to two random t differ by
    ``deviation`` times the sum of the points' own secant slopes (0 for a complete set; a missing
    point leaves its own slope's curvature, a fraction of one point's in the sum).

    Returns the witnesses on C's hyperplane section, the deviation and the verdict (below
    ``TRACE_TOLERANCE``)."""
    n = family.n
    w = value_scale(family, q, solutions) * _random_complex(rng, n)
    a = _random_complex(rng, n)
    a = a / np.median(np.abs(solutions @ a))
    qq = np.broadcast_to(q, (1, q.size))

    def on_slice(v: np.ndarray) -> np.ndarray:
        if not len(v):
            return np.zeros(0, bool)
        at = np.broadcast_to(qq, (len(v), q.size))
        size = 1 + np.abs(v).max(-1)
        residual = np.abs(family.value(v[:, :n], at) + v[:, n : n + 1] * w[None, :]) / value_scale(family, q, v[:, :n])
        return (residual.max(-1) < 1e-8 * size) & (np.abs(v[:, :n] @ a - 1) < 1e-8 * size) & (size < 1e6)

    # witnesses from the fibre: its solutions carried to a few l of the curve, each on its own
    # hyperplane a . z = c there; moving c to 1 takes each to a witness
    seeds, bases = [], []
    for lam in _random_complex(rng, VALUE_SEED_LINES) * np.logspace(-1, 1, VALUE_SEED_LINES):
        moved, reached = _track(_value_system(family, q, np.zeros(n, complex), -lam * w), solutions)
        for z in moved[reached]:
            c = a @ z
            if abs(c) > 1e-8:
                seeds.append(np.concatenate([z, [lam]]))
                bases.append(a / c)
    witnesses = np.zeros((0, n + 1), complex)
    if seeds:
        ended, reached = _track(_value_slice_system(family, q, w, np.array(bases), a), np.array(seeds))
        witnesses, _ = _add_new(witnesses, ended[reached][on_slice(ended[reached])])
    points0 = np.concatenate([np.concatenate([solutions, np.zeros((len(solutions), 1))], axis=1), witnesses])
    deviation = np.inf
    spread = float(np.median(np.abs(solutions @ a - 1)))
    quiet = 0
    previous = (np.inf, 0)
    began = time.perf_counter()
    for round_ in range(1, VALUE_TRACE_MAX_ROUNDS + 1):
        before = len(witnesses)
        witnesses = _loops(
            lambda b0, b1: _value_slice_system(
                family, q, w, a + VALUE_LOOP_SIZE * (b0 - a), a + VALUE_LOOP_SIZE * (b1 - a)
            ),
            a,
            witnesses,
            on_slice,
            rng,
            WITNESS_LOOPS,
        )
        quiet = 0 if len(witnesses) > before else quiet + 1
        points0 = np.concatenate([np.concatenate([solutions, np.zeros((len(solutions), 1))], axis=1), witnesses])
        slopes: list[np.ndarray] = []
        for _ in range(8):
            if len(slopes) == 2:
                break
            t = complex(np.exp(2j * np.pi * rng.random())) * VALUE_PENCIL_T * spread
            ended, reached = _track(_value_pencil_system(family, q, w, a, t), points0)
            # a path that failed or met another (a jump) spoils the sum: another t
            if reached.all() and _smallest_gap(ended) > 1e-8:
                slopes.append((ended - points0) / t)
        if len(slopes) < 2:
            raise GenerationError(f"{name}: trace test: the pencil's paths failed or met at every t tried")
        difference = np.linalg.norm(slopes[0].sum(0) - slopes[1].sum(0))
        total = float(np.linalg.norm(slopes[0], axis=1).sum() + np.linalg.norm(slopes[1], axis=1).sum())
        deviation = float(difference / total) if total > 0 else np.inf
        logger.info(
            "%s: trace test round %d: %d witnesses, deviation %.1e (%.1f s a round; at most %d more)",
            name, round_, len(witnesses), deviation, (time.perf_counter() - began) / round_,
            min(VALUE_TRACE_ROUNDS - quiet, VALUE_TRACE_MAX_ROUNDS - round_),
        )  # fmt: skip
        # the witnesses are complete when the trace closes; while loops still find new ones it
        # may yet, and a set that stopped growing for VALUE_TRACE_ROUNDS rounds is given up
        # closed: below the tolerance at two pairs of t in a row, with the same witnesses (a far
        # witness or solution moves almost on a line: a single small deviation is not enough)
        closed = deviation < VALUE_TRACE_TOLERANCE and previous[0] < VALUE_TRACE_TOLERANCE
        if closed and previous[1] == len(witnesses):
            return {"witnesses": len(witnesses), "deviation": max(deviation, previous[0]), "complete": True}
        previous = (deviation, len(witnesses))
        if quiet >= VALUE_TRACE_ROUNDS:
            break
    return {"witnesses": len(witnesses), "deviation": max(deviation, previous[0]), "complete": False}


def _total_degree_system(
    family: Family | _Scaled, q: np.ndarray, degrees: np.ndarray, gamma: complex, patch: np.ndarray
):
    """H(w, t) = (1 - t) F^h(w; q) + t gamma G(w), t = ENDGAME_T + (1 - ENDGAME_T) s, with the
    random patch p . w = 1, w = (z0, z): F^h_k = z0^d_k F_k(z / z0) (values and derivatives by the
    chain rule from F's), G_k = z_k^d_k - z0^d_k. In projective coordinates a path to a solution
    at infinity ends at z0 = 0 instead of leaving every bound."""
    n = family.n
    qq = q[None, :]

    def system(index, w, s):
        z0, z = w[:, 0], w[:, 1:]
        x = z / z0[:, None]
        f = family.value(x, np.broadcast_to(qq, (len(w), q.size)))
        jx = family.jacobian(x, np.broadcast_to(qq, (len(w), q.size)))
        lift = z0[:, None] ** (degrees[None, :] - 1)
        fh = lift * z0[:, None] * f
        jz = lift[:, :, None] * jx
        j0 = lift * (degrees[None, :] * f - (jx * x[:, None, :]).sum(-1))
        g = z ** degrees[None, :] - z0[:, None] ** degrees[None, :]
        gz = degrees[None, :] * z ** (degrees[None, :] - 1)
        g0 = -degrees[None, :] * z0[:, None] ** (degrees[None, :] - 1)
        t = ENDGAME_T + (1 - ENDGAME_T) * s[:, None]
        value = np.concatenate([(1 - t) * fh + t * gamma * g, (w @ patch - 1)[:, None]], axis=1)
        top = np.concatenate([((1 - t) * j0 + t * gamma * g0)[:, :, None], (1 - t)[..., None] * jz], axis=2)
        top[:, np.arange(n), 1 + np.arange(n)] += t * gamma * gz
        matrix = np.concatenate([top, np.broadcast_to(patch, (len(w), 1, n + 1))], axis=1)
        rate = np.concatenate([(1 - ENDGAME_T) * (gamma * g - fh), np.zeros((len(w), 1))], axis=1)
        return value, matrix, rate

    return system


def equilibration(family: Family, q: np.ndarray, columns: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Row (and optionally column) scales of F(z; q) at the instance q that bring its
    coefficients near 1.

    The fit of Meintjes and Morgan ("A methodology for solving chemical equilibrium systems",
    1987; Morgan, "Solving polynomial systems using continuation", 1987, ch. 5): with
    F_k = sum_t c_t z^e_t, the scaled system r_k F_k(col * y) has coefficients r_k c_t col^e_t;
    log2 r (and log2 col) minimise sum_t (log2|c_t| + log2 r_k + e_t . log2 col)^2 over every
    coefficient (those below ``SCALING_FLOOR`` of their equation's largest left out), the
    columns' mean fixed at 0 (a common size of the unknowns is the projective patch's business).
    Both are rounded to powers of two, so that scaling is exact in floating point: the scaled
    system has exactly the solutions z = col * y of F's, the same regular ones. Without
    ``columns`` (the total-degree runs' choice) col = 1 and r_k is the inverse geometric mean of
    equation k's coefficients. Measured on the skew 3-RRS (32 solutions), regular solutions per
    total-degree run at seeds 3..8: unscaled 21-22; rows 32 at every seed; rows and columns
    32, 32, 32, 30, 30, 32 (its columns, 1/2 to 2, unbalance the paths' step control).

    Parameters
    ----------
    family : Family
        The family F(z; q), n equations in n unknowns.
    q : numpy.ndarray, shape (m,), complex
        The instance (the subfamily's coordinates where ``family`` is restricted).
    columns : bool
        Whether the unknowns are scaled too.

    Returns
    -------
    rows : numpy.ndarray, shape (n,)
        The equations' factors r_k, powers of two.
    columns : numpy.ndarray, shape (n,)
        The unknowns' factors col_j (z_j = col_j y_j), powers of two with mean exponent 0; ones
        without ``columns``.

    Example
    -------
    >>> rows, columns = equilibration(family, q)  # doctest: +SKIP
    >>> scaled_value = rows * family.value(columns * y, q)  # doctest: +SKIP
    """
    terms = family.terms()
    with mpmath.workdps(20):
        values = terms.coefficients(*[mpmath.mpc(complex(v)) for v in q])
        sizes = np.array([float(abs(c)) for c in values])
    n = family.n
    width = 2 * n if columns else n
    design, target = [], []
    index = 0
    for k, row in enumerate(terms.rows):
        size = sizes[index : index + len(row)]
        index += len(row)
        for powers, c in zip(row, size, strict=True):
            if c > SCALING_FLOOR * size.max():
                design.append(np.concatenate([np.eye(n)[k], np.asarray(powers, float)])[:width])
                target.append(-np.log2(c))
    if columns:  # the columns' mean exponent is fixed at 0: one more equation, weighted to hold
        design.append(np.concatenate([np.zeros(n), np.full(n, 1e3)]))
        target.append(0.0)
    fit = np.round(np.linalg.lstsq(np.array(design), np.array(target), rcond=None)[0]).astype(float)
    return 2.0 ** fit[:n], 2.0 ** fit[n:] if columns else np.ones(n)


class _Scaled:
    """The family's equations scaled by ``equilibration``: r_k F_k(col * y; q), in y."""

    def __init__(self, family: Family, rows: np.ndarray, columns: np.ndarray) -> None:
        self.family, self.rows, self.columns, self.n = family, rows, columns, family.n

    def value(self, y: np.ndarray, q: np.ndarray) -> np.ndarray:
        return self.rows * self.family.value(y * self.columns, q)

    def jacobian(self, y: np.ndarray, q: np.ndarray) -> np.ndarray:
        return self.rows[:, None] * self.family.jacobian(y * self.columns, q) * self.columns


def total_degree_run(
    family: Family, q: np.ndarray, degrees: list[int], rng, equilibrate: bool = True, name: str = ""
) -> np.ndarray:
    """Every regular isolated solution of F(z; q) = 0 that one total-degree homotopy of
    prod(degrees) paths reaches (Morgan and Sommese; Bates, Hauenstein, Sommese and Wampler,
    "Numerically solving polynomial systems with Bertini", 2013, ch. 2): with a random gamma
    every regular isolated solution ends exactly one path, with probability one. A path that
    fails is tracked again with 100 times tighter steps; endpoints, and the last points of paths
    that fail again, are kept where Newton on F takes them to a regular solution (``_regular``,
    or ``_regular_in_40_digits`` where the doubles' Newton step stops at their rounding level),
    judged on the equilibrated system: regularity is the solution's, and a condition bound on
    equations scaled 1e-6 and 1e6 apart would measure their scales.

    ``equilibrate``: the homotopy is that of the equilibrated system (``equilibration``: rows
    and columns scaled by powers of two, the same solutions). Without it an equation whose
    coefficients are 1e-6 of another's is still the start system's at the endgame's t = 1e-6,
    and its paths end outside Newton's basins (the skew 3-RRS: 21 or 22 of its 32 solutions per
    run; equilibrated, 32).

    Parameters
    ----------
    family : Family
        The family F(z; q).
    q : numpy.ndarray, shape (m,), complex
        The instance.
    degrees : list of int
        The equations' total degrees (the Bezout number is their product).
    rng : numpy.random.Generator
        The run's gamma and projective patch.
    equilibrate : bool
        Whether the equations are equilibrated first.
    name : str
        The family's name in the progress lines (one per ``TOTAL_DEGREE_PART`` paths).

    Returns
    -------
    numpy.ndarray, shape (k, n), complex
        The distinct regular solutions reached.
    """
    from parakin.solvers.path_tracking import PATH_REACHED, _solve, track

    n = family.n
    d = np.asarray(degrees, dtype=np.int64)
    # start solutions: z_k = omega_k z0 over the d_k-th roots of unity, z0 from the patch
    grids = np.meshgrid(*[np.exp(2j * np.pi * np.arange(k) / k) for k in d], indexing="ij")
    omega = np.stack([g.ravel() for g in grids], axis=-1)
    gamma = complex(_random_complex(rng, 1)[0])
    patch = _random_complex(rng, n + 1)
    z0 = 1.0 / (patch[0] + omega @ patch[1:])
    start = np.concatenate([z0[:, None], omega * z0[:, None]], axis=1)
    # solutions are judged on the equilibrated system whether or not the paths were (the
    # condition bound is one of the solution, not of how its equations happen to be scaled)
    judge = _Scaled(family, *equilibration(family, q))
    tracked = judge if equilibrate else _Scaled(family, np.ones(n), np.ones(n))
    system = _total_degree_system(tracked, q, d, gamma, patch)
    ended = _tracked_in_parts(system, start, name)
    z = ended.z.copy()
    again = np.nonzero(ended.status != PATH_REACHED)[0]
    if again.size:
        retracked = track(system, start[again], 1e-9)
        z[again] = np.where((retracked.status == PATH_REACHED)[:, None], retracked.z, z[again])
    with np.errstate(all="ignore"):
        x = z[:, 1:] / z[:, :1] * tracked.columns
        x = x[np.isfinite(x).all(-1) & (np.abs(x).max(-1) < 1e8)]
        at = np.broadcast_to(q, (len(x), q.size))
        for _ in range(8):
            step = _solve(family.jacobian(x, at), family.value(x, at))
            x = np.where(np.isfinite(step), x - step, x)
    regular = _regular(judge, q, x / judge.columns)
    found = _add_new(np.zeros((0, n), complex), x[regular])[0]
    # the others near a solution, each once, judged again in 40 digits (``_regular_in_40_digits``)
    known = len(found)
    near = newton_size(judge, x / judge.columns, q) < REGULAR_RECHECK
    candidates = _add_new(found, x[~regular & near])[0][known:]
    return _add_new(found, _regular_in_40_digits(judge, q, candidates))[0]


def _part_of(system, part: np.ndarray):
    """``system`` for the paths ``part`` of a run (the tracker's indices are the part's)."""

    def restricted(index, w, s):
        return system(part[index], w, s)

    return restricted


def _tracked_in_parts(system, start: np.ndarray, name: str):
    """``track`` of every start point, in parts of ``TOTAL_DEGREE_PART`` paths or more with a
    progress line and an estimate of the time left after each but the last (a Hexaglide's run of
    8192 paths takes minutes); the endpoints are the same as one call's."""
    from parakin.solvers.path_tracking import Paths, track

    parts = np.array_split(np.arange(len(start)), max(1, len(start) // TOTAL_DEGREE_PART))
    began = time.perf_counter()
    ended = []
    for k, part in enumerate(parts, 1):
        ended.append(track(_part_of(system, part), start[part]))
        if k < len(parts):
            spent = time.perf_counter() - began
            done = sum(len(p) for p in parts[:k])
            logger.info(
                "%s: total-degree run: %d of %d paths tracked in %.0f s, about %.0f s left",
                name, done, len(start), spent, spent * (len(start) - done) / done,
            )  # fmt: skip
    return Paths(*(np.concatenate(field) for field in zip(*ended, strict=True)))


def _regular_in_40_digits(judge: _Scaled, q: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The points z (P, n) that Newton in 40-digit arithmetic takes quadratically to a solution
    (a last step below 1e-30 of 1 + |z| within 8 steps: a singular solution converges linearly
    and fails) whose Jacobian is as far from singular as ``_regular`` asks (the equilibrated
    system ``judge``'s condition below 1e10), refined. ``_regular``'s double-precision step of 1e-10 is what rounding leaves of a
    badly scaled family's equations (the skew 3-RRS's: 8e-11 to 1.1e-10 over successive Newton
    steps at its 32 solutions, condition 2e7 to 2e9): there the same question is asked in
    40 digits, where rounding does not decide it."""
    refined = [row for row in _newton_40(judge.family, q, z) if row is not None]
    if not refined:
        return np.zeros((0, judge.n), complex)
    points = np.array(refined)
    with np.errstate(all="ignore"):
        jacobian = judge.jacobian(points / judge.columns, np.broadcast_to(q, (len(points), q.size)))
        finite = np.isfinite(jacobian).all((-2, -1))
        condition = np.full(len(points), np.inf)
        if finite.any():
            condition[finite] = np.linalg.cond(jacobian[finite])
    return points[condition < 1e10]


def _regular(family: Family | _Scaled, q: np.ndarray, z: np.ndarray, equilibrated: bool = False) -> np.ndarray:
    """Which points z (P, n) are regular solutions of F(.; q): a Newton step below 1e-10 of 1 + |z|
    and a Jacobian far from singular (a point of a positive-dimensional component is neither);
    ``equilibrated``: the Jacobian's rows and then columns scaled to unit size first (a member far
    from the start instance can have coefficients of very different sizes: the spm's at 1e21)."""
    if not len(z):
        return np.zeros(0, bool)
    with np.errstate(all="ignore"):
        jacobian = family.jacobian(z, np.broadcast_to(q, (len(z), q.size)))
        if equilibrated:
            jacobian = jacobian / np.maximum(np.abs(jacobian).max(-1, keepdims=True), 1e-300)
            jacobian = jacobian / np.maximum(np.abs(jacobian).max(-2, keepdims=True), 1e-300)
        finite = np.isfinite(jacobian).all((-2, -1))
        condition = np.full(len(z), np.inf)
        if finite.any():
            condition[finite] = np.linalg.cond(jacobian[finite])
    return (newton_size(family, z, q) < 1e-10) & (condition < 1e10)


def _total_degree_bound(
    name: str, family: Family, q: np.ndarray, solutions: np.ndarray, degrees: list[int], flips, seed: int
) -> tuple[np.ndarray, dict[str, object]]:
    """``solutions`` joined with every regular solution the total-degree runs find, and the proof:
    complete when ``TOTAL_DEGREE_RUNS`` independent runs each found exactly the joined set (no
    solution that one run reached was lost by the others, and monodromy missed none that the runs
    could not also see). Runs are added, up to ``TOTAL_DEGREE_MAX_RUNS``, while too few agree."""
    rng = np.random.default_rng(seed + 3)
    runs: list[np.ndarray] = []
    joined = solutions

    def agreeing() -> int:
        return sum(len(found) == len(joined) for found in runs)

    paths = int(np.prod(degrees))
    began = time.perf_counter()
    while len(runs) < TOTAL_DEGREE_MAX_RUNS and (len(runs) < TOTAL_DEGREE_RUNS or agreeing() < TOTAL_DEGREE_RUNS):
        if runs:  # the runs are alike: the next takes about as long as the mean of those done
            each = (time.perf_counter() - began) / len(runs)
            logger.info(
                "%s: total-degree run %d (%d paths; about %.0f s, as each so far), %d regular solutions so far",
                name, len(runs) + 1, paths, each, len(joined),
            )  # fmt: skip
        else:
            logger.info("%s: total-degree run 1 of at least %d (%d paths)", name, TOTAL_DEGREE_RUNS, paths)
        runs.append(total_degree_run(family, q, degrees, rng, True, name))
        joined = _closed(_add_new(joined, runs[-1])[0], flips)
    complete = agreeing() >= TOTAL_DEGREE_RUNS
    counts = ", ".join(str(len(found)) for found in runs)
    method = (
        f"{TOTAL_DEGREE_METHOD} ({len(runs)} independent runs of {paths} paths, {TOTAL_DEGREE_EQUILIBRATED},"
        f" regular endpoints {counts})"
    )
    if not complete:
        logger.warning(
            "%s: the total-degree runs found %s regular solutions, monodromy %d, together %d: the count is NOT proven",
            name, counts, len(solutions), len(joined),
        )  # fmt: skip
    return joined, {
        "method": method if complete else method + f"; NOT proven: fewer than {TOTAL_DEGREE_RUNS} runs found them all",
        "proven": complete,
        "stable_rule": STABLE_RULE,
        "witnesses": 0,
        "trace_deviation": 1.0,
        "bezout_paths": paths,
        "regular_endpoints": [len(found) for found in runs],
    }


def _newton_40(
    family: Family, q: np.ndarray, found: np.ndarray, lambdified: bool = False
) -> list[list[complex] | None]:
    """Newton in 40-digit arithmetic from each double-precision point, rounded to the nearest
    double; None for a point whose last step (of at most 8) is not below 1e-30 of 1 + |z| (no
    regular isolated solution: a singular point converges linearly, if at all). The equations as
    sums of monomials in z with coefficients evaluated once at q (the family's monomial table,
    built once per family), or with ``lambdified`` as the lambdified equations and Jacobian (no
    table: it costs minutes on the larger families, sam's, where only a few points are refined)."""
    refined: list[list[complex] | None] = []
    with mpmath.workdps(40):
        parameters = [mpmath.mpc(mpmath.mpf(repr(float(v.real))), mpmath.mpf(repr(float(v.imag)))) for v in q]
        if lambdified:
            arguments = family.unknowns + family.parameters
            value = sp.lambdify(arguments, family.equations, modules="mpmath", cse=True)
            jacobian = sp.lambdify(arguments, list(family.jacobian_z), modules="mpmath", cse=True)
            n = family.n

            def evaluate(z: list) -> tuple:
                entries = jacobian(*z, *parameters)
                matrix = mpmath.matrix([[entries[i * n + j] for j in range(n)] for i in range(n)])
                return mpmath.matrix(value(*z, *parameters)), matrix

        else:
            # each Newton step costs the monomials, not the coefficients' expressions again
            terms = family.terms()
            coefficients = terms.coefficients(*parameters)

            def evaluate(z: list) -> tuple:
                return terms.evaluate(coefficients, z)  # type: ignore[no-any-return]

        for row in found:
            z = [mpmath.mpc(complex(c)) for c in row]
            # converged: the last Newton step is at 40-digit rounding relative to |z| (a residual
            # threshold would depend on how the equations are scaled)
            converged = False
            for _ in range(8):
                f, jacobian_z = evaluate(z)
                try:
                    step = mpmath.lu_solve(jacobian_z, f)
                except ZeroDivisionError:  # an exactly singular Jacobian: no regular solution
                    converged = False
                    break
                z = [a - b for a, b in zip(z, step, strict=True)]
                converged = mpmath.norm(step) < mpmath.mpf(10) ** -30 * (1 + mpmath.norm(mpmath.matrix(z)))
                if converged:
                    break  # quadratically: z is now at the working precision
            refined.append([complex(float(c.real), float(c.imag)) for c in z] if converged else None)
    return refined


def _refine_exact(family: Family, q: np.ndarray, found: np.ndarray) -> list[list[complex]]:
    """Newton in 40-digit arithmetic from each double-precision solution (``_newton_40``), then
    rounded to the nearest double and sorted: the stored start system is the same on every
    machine. A point that does not converge (a singular point monodromy brushed) is no start."""
    refined = [row for row in _newton_40(family, q, found) if row is not None]
    refined.sort(key=lambda row: tuple(x for c in row for x in (round(c.real, 9), round(c.imag, 9))))
    return refined


def _cache_path(key: str) -> Path:
    """Where the start systems of these equations are kept between builds (the computation is
    deterministic, the cache only saves its minutes): $PARAKIN_CACHE/homotopy, else
    ~/.cache/parakin/homotopy (the compiled backend's cache root); an empty folder recomputes.
    A record is trusted only there and private (``_from_cache``)."""
    from parakin.packages.compiled import cache_directory

    return cache_directory() / "homotopy" / f"{key}.json"


def _smallest_gap(z: np.ndarray) -> float:
    """The smallest max-norm distance between two of the points z (P, n); inf for fewer than two."""
    if len(z) < 2:
        return np.inf
    gaps = np.abs(z[:, None] - z[None]).max(-1)
    return float(np.where(np.eye(len(z), dtype=bool), np.inf, gaps).min())


def _pairs(values) -> list[list[float]]:
    return [[float(v.real), float(v.imag)] for v in values]


def start_systems(
    name: str,
    form: PolynomialForm,
    equations: list[sp.Expr],
    seed: int,
    method: str,
    parameter_values: Mapping[sp.Symbol, float] | None = None,
) -> tuple[Family, dict]:
    """The two start instances with their solutions and the proof of their count (cached).

    Where the mechanism imposes relations on the family's values (``generator/subfamily.py``:
    constant angles; with ``parameter_values``, parameters sharing a value) and the family's
    generic count is not the subfamily's (a stored generic record is tried first: its solutions
    followed to a random member of the subfamily must all stay finite and distinct), the start
    instances are drawn in the subfamily and the count is proven there; the record then carries
    the ``Relations`` (key ``relations``) for the manifest. Where parameters share a value and the
    family is small (``GENERIC_MAX_PATHS``), the count for any parameter values is tried first
    (``_generic_record``)."""
    family = Family(form, equations)
    key = hashlib.sha256(
        repr(
            (CACHE_VERSION, seed, [sp.srepr(e) for e in family.equations], [str(v) for v in family.parameters])
        ).encode()
    )
    cached = _cache_path(key.hexdigest())
    flips = sign_symmetries(family, np.random.default_rng(seed + 2))
    degrees = [int(sp.Poly(e, *form.unknowns).total_degree()) for e in equations]
    angles = {u: angle for u, angle, _ in form.circles}
    relations = family_relations(family.parameters, dict(form.family), angles, parameter_values)
    # the generic record first, wherever one is stored: a subfamily record that another build left
    # in the cache must not change what a build with the committed packages writes
    record = _stored_record(name, family, key.hexdigest(), cached, method, flips, degrees, seed)
    if record is not None and (relations is None or _keeps_count(name, family, record, relations, seed)):
        return family, record
    if record is None and relations is not None and relations.groups and int(np.prod(degrees)) <= GENERIC_MAX_PATHS:
        generic = _generic_record(name, family, key.hexdigest(), cached, relations, degrees, seed, method)
        if generic is not None:
            return family, generic
    if relations is not None:
        sub_key = hashlib.sha256(repr((key.hexdigest(), relations.key())).encode()).hexdigest()
        for stored in (_from_cache(_cache_path(sub_key)), _from_package(name, method, sub_key)):
            if stored is not None and _verified(family, stored, flips) is not None and _in(relations, stored):
                return family, {**stored, "key": sub_key, "relations": relations}
    if relations is None:
        record = _new_record(name, family, degrees, flips, seed, method)
        _store(cached, record)
        return family, {**record, "key": key.hexdigest()}
    logger.info(
        "%s (%s): the count is proven where %s (the mechanism's own relations)", name, method, relations.describe()
    )
    restricted = family.restricted(relations)
    record = _new_record(
        name, restricted, degrees, sign_symmetries(restricted, np.random.default_rng(seed + 2)), seed, method
    )
    _store(_cache_path(sub_key), record)
    return family, {**record, "key": sub_key, "relations": relations}


def _generic_record(
    name: str,
    family: Family,
    key: str,
    cached: Path,
    relations: Relations,
    degrees: list[int],
    seed: int,
    method: str,
) -> dict | None:
    """The count proven for any values of the parameters that share a value in ``relations``
    (the module docstring's budget rule): new start systems of the family (restricted to its
    constant values only, which no parameter changes), kept where proven and where their
    solutions, followed to a random member of the subfamily, all stay finite, regular and
    distinct (``_keeps_count``); None otherwise (the subfamily's proof takes over)."""
    constants = relations.constants_only()
    generic_key = key if constants is None else hashlib.sha256(repr((key, constants.key())).encode()).hexdigest()
    where = cached if constants is None else _cache_path(generic_key)
    if constants is not None:
        # a constants-only record that an earlier build proved
        for stored in (_from_cache(where), _from_package(name, method, generic_key)):
            if stored is None or not _in(constants, stored):
                continue
            flips = sign_symmetries(family, np.random.default_rng(seed + 2))
            if _verified(family, stored, flips) is not None:
                if bool(stored["proof"].get("proven")) and _keeps_count(name, family, stored, relations, seed):
                    return {**stored, "key": generic_key, "relations": constants}
                return None
    began = time.perf_counter()
    logger.info(
        "%s (%s): the count is proven for any parameter values first (%d paths at most %d; then %s is checked)",
        name, method, int(np.prod(degrees)), GENERIC_MAX_PATHS, relations.describe(),
    )  # fmt: skip
    proven_on = family if constants is None else family.restricted(constants)
    record = _new_record(
        name, proven_on, degrees, sign_symmetries(proven_on, np.random.default_rng(seed + 2)), seed, method
    )
    if not record["proof"].get("proven"):
        # never a generic count not proven: the subfamily's proof takes over (nothing stored)
        logger.info("%s: the count for any parameter values is not proven: proven where %s", name, relations.describe())
        return None
    _store(where, record)
    if not _keeps_count(name, family, record, relations, seed):
        return None
    logger.info(
        "%s: %d solutions for any parameter values (%.1f s; they stay finite where %s)",
        name, len(record["solutions"]), time.perf_counter() - began, relations.describe(),
    )  # fmt: skip
    out = {**record, "key": generic_key}
    return out if constants is None else {**out, "relations": constants}


def _in(relations: Relations, record: dict) -> bool:
    """Whether a record's two start instances lie in the subfamily of ``relations``."""
    try:
        return all(
            relations.holds(np.array([complex(*v) for v in record[instance]]))
            for instance in ("instance", "second_instance")
        )
    except (KeyError, TypeError, ValueError):
        return False


def _keeps_count(name: str, family: Family, record: dict, relations: Relations, seed: int) -> bool:
    """Whether the generic count of ``record`` is the subfamily's too: its solutions followed from
    its instance to a random member of the subfamily all end at distinct regular solutions there
    (the count at a generic member is at most the family's; every one reached makes it equal)."""
    q = np.array([complex(*v) for v in record["instance"]])
    solutions = np.array([[complex(*c) for c in row] for row in record["solutions"]])
    target = relations.full(_random_complex(np.random.default_rng(seed + 7), relations.size))
    moved, reached = _track(_segment(family, q, target), solutions)
    ends = moved[reached]
    ends = ends[_regular(family, target, ends, equilibrated=True)]
    kept = len(_add_new(np.zeros((0, family.n), complex), ends)[0])
    if kept < len(solutions):
        logger.info(
            "%s: where %s (the mechanism's own relations) %d of the family's %d solutions stay finite",
            name, relations.describe(), kept, len(solutions),
        )  # fmt: skip
    return kept == len(solutions)


def _stored_record(
    name: str, family: Family, key: str, cached: Path, method: str, flips, degrees: list[int], seed: int
) -> dict | None:
    """The family's record from the committed package or the cache, verified (and completed
    where an older rule left it short), or None. The package's comes first: regeneration must
    give the committed bytes whatever the cache holds (another mechanism of the same family,
    a test's, may have left a record of its own there, proven with other words)."""
    bounded = int(np.prod(degrees)) <= TOTAL_DEGREE_MAX
    for stored in (_from_package(name, method, key), _from_cache(cached)):
        if stored is None:
            continue
        if _verified(family, stored, flips) is not None:
            if bounded and not (_total_degree_settled(stored["proof"]) or _value_trace_proof(stored["proof"])):
                # a record proven (or counted) another way gets the total-degree bound on its own
                # instance: seconds, where a new monodromy takes minutes
                q = np.array([complex(*v) for v in stored["instance"]])
                solutions = np.array([[complex(*c) for c in row] for row in stored["solutions"]])
                joined, bound = _total_degree_bound(name, family, q, solutions, degrees, flips, seed)
                record = {**stored, "proof": bound}
                if len(joined) > len(solutions):
                    refined = np.array(_refine_exact(family, q, joined))
                    second, second_solutions = _second_start(name, family, q, refined, seed)
                    record |= {"solutions": [_pairs(row) for row in refined], "second_instance": _pairs(second)}
                    record["second_solutions"] = [_pairs(row) for row in second_solutions]
                _store(cached, record)
                return {**record, "key": key}
            return {**stored, "key": key}
        if _verified(family, stored, flips, second=False) is not None:
            # the first start system and its proof hold, the second does not (a record written
            # before its solutions were counted): only the second is computed again
            q = np.array([complex(*v) for v in stored["instance"]])
            solutions = np.array([[complex(*c) for c in row] for row in stored["solutions"]])
            second, second_solutions = _second_start(name, family, q, solutions, seed)
            record = {**stored, "second_instance": _pairs(second)}
            record["second_solutions"] = [_pairs(row) for row in second_solutions]
            _store(cached, record)
            return {**record, "key": key}
    return None


def _new_record(name: str, family: Family, degrees: list[int], flips, seed: int, method: str) -> dict:
    """New start systems of ``family`` (restricted to a subfamily or not) and the proof of their
    count: the record, its instances as the family's values."""
    bounded = int(np.prod(degrees)) <= TOTAL_DEGREE_MAX
    paths = int(np.prod(degrees))
    first = "the value curve's trace test" if paths > VALUE_FIRST_PATHS else None
    first = first or ("total-degree runs" if bounded else "the trace test")
    logger.info("%s (%s): new start systems: monodromy and %s (then cached)", name, method, first)
    rng = np.random.default_rng(seed)
    q, point = _start_instance(name, family, rng)
    # small Bezout numbers: the total-degree runs take seconds (tricept 864 paths: 30 s in all,
    # rps3 1024: 18 s); larger ones try the value curve's trace test first (the Hexaglide's 8192)
    fast = (
        None
        if paths <= VALUE_FIRST_PATHS
        else _value_proof(name, family, q, point, flips, np.random.default_rng(seed + 5))
    )
    if fast is not None:
        solutions, value_proof = fast
        second, second_solutions = _second_start(name, family, q, solutions, seed)
        record = {
            "instance": _pairs(q),
            "solutions": [_pairs(row) for row in solutions],
            "second_instance": _pairs(second),
            "second_solutions": [_pairs(row) for row in second_solutions],
            "proof": {
                "method": f"{VALUE_TRACE_METHOD} after monodromy in the values",
                "proven": True,
                "stable_rule": STABLE_RULE,
                "witnesses": value_proof["witnesses"],
                "trace_deviation": float(f"{float(value_proof['deviation']):.2e}"),  # type: ignore[arg-type]
                "tolerance": TRACE_TOLERANCE,
            },
        }
        return _lifted(family, record)
    if paths > VALUE_FIRST_PATHS:
        proof_text = "total-degree runs" if bounded else "the trace test"
        logger.info(
            "%s (%s): the value curve's trace test did not close: monodromy and %s (minutes)", name, method, proof_text
        )
    found = point[None, :]
    proof: dict[str, object] = {}
    if bounded:
        # monodromy finds the start solutions fast; the total-degree runs prove the count (and
        # catch a component monodromy cannot reach)
        found = _closed(_monodromy(name, lambda a, b: _segment(family, a, b), q, found, _solves(family, q), rng), flips)
        joined, proof = _total_degree_bound(name, family, q, found, degrees, flips, seed)
        solutions = np.array(_refine_exact(family, q, joined))
        second, second_solutions = _second_start(name, family, q, solutions, seed)
        record = {
            "instance": _pairs(q),
            "solutions": [_pairs(row) for row in solutions],
            "second_instance": _pairs(second),
            "second_solutions": [_pairs(row) for row in second_solutions],
            "proof": proof,
        }
        return _lifted(family, record)
    for _ in range(TRACE_ROUNDS):
        # loops until the trace test proves the set complete: a missed solution shows there
        found = _closed(_monodromy(name, lambda a, b: _segment(family, a, b), q, found, _solves(family, q), rng), flips)
        found = _other_components(name, family, q, found, flips, rng)
        solutions = np.array(_refine_exact(family, q, found))
        if len(solutions) > TRACE_MAX_SOLUTIONS:
            # the witness monodromy grows with the curve's degree: past this size it takes far
            # longer than a build may; the count stays monodromy's and the manifest says so
            proof = {"witnesses": 0, "deviation": np.inf, "complete": False, "attempted": False}
            break
        proof = trace_test(name, family, q, solutions, rng)
        if proof["complete"]:
            break
    deviation = float(proof["deviation"])  # type: ignore[arg-type]
    if proof["complete"]:
        method_text = "trace test (Leykin, Rodriguez, Sottile 2018) after monodromy"
    else:
        method_text = f"monodromy ({STABLE_LOOPS} loops in a row found nothing new); NOT proven: " + (
            "the trace test did not close within its budget"
            if proof.get("attempted", True)
            else f"the trace test is not attempted above {TRACE_MAX_SOLUTIONS} solutions"
        )
        # the count is monodromy's, and the manifest says so
        logger.warning("%s (%s): %d solutions, %s", name, method, len(solutions), method_text)
    second, second_solutions = _second_start(name, family, q, solutions, seed)
    record = {
        "instance": _pairs(q),
        "solutions": [_pairs(row) for row in solutions],
        "second_instance": _pairs(second),
        "second_solutions": [_pairs(row) for row in second_solutions],
        "proof": {
            "method": method_text,
            "proven": bool(proof["complete"]),
            "stable_rule": STABLE_RULE,
            "witnesses": proof["witnesses"],
            "trace_deviation": float(f"{deviation:.2e}") if np.isfinite(deviation) else 1.0,
            "tolerance": TRACE_TOLERANCE,
        },
    }
    return _lifted(family, record)


def _lifted(family: Family, record: dict) -> dict:
    """``record`` with its instances as the family's values (a restricted family's are its
    subfamily's coordinates)."""
    if family.relations is None:
        return record
    lift = family.relations.full
    instances = {
        key: _pairs(lift(np.array([complex(*v) for v in record[key]]))) for key in ("instance", "second_instance")
    }
    return {**record, **instances}


def _store(cached: Path, record: dict) -> None:
    """Keep a record for the next build, naming its family (the file's key), in folders created
    private (0700); a cache folder that is not private gets nothing, as it would not be read back
    (``_from_cache``), and neither does one that cannot be written: the record only saves time."""
    import tempfile

    from parakin.packages.compiled import distrust

    folder = cached.parent
    try:
        folder.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
        reason = distrust(folder.parent)
        if reason is None:
            folder.mkdir(exist_ok=True, mode=0o700)
            reason = distrust(folder)
        if reason is not None:
            logger.warning("start systems not stored in %s: %s", folder, reason)
            return
        # a name of its own (O_EXCL), so a concurrent build never writes into this one's file
        handle, partial = tempfile.mkstemp(prefix=f".{cached.stem}.", suffix=".tmp", dir=folder)
    except OSError as error:
        logger.warning("start systems not stored in %s: %s: %s", folder, type(error).__name__, error)
        return
    try:
        with os.fdopen(handle, "w") as file:
            json.dump({**record, "family_key": cached.stem}, file)
        os.replace(partial, cached)
    except OSError as error:
        logger.warning("start systems not stored in %s: %s: %s", folder, type(error).__name__, error)
    finally:
        if os.path.exists(partial):
            os.unlink(partial)


def _second_start(
    name: str, family: Family, q: np.ndarray, solutions: np.ndarray, seed: int
) -> tuple[np.ndarray, np.ndarray]:
    """A second start system, for inputs where a path of the first fails: its own random
    instance, every solution of the first followed to it and refined; all of them or an error."""
    second = _random_complex(np.random.default_rng(seed + 1), family.m)
    moved, reached = _track(_segment(family, q, second), solutions)
    if not reached.all():
        raise GenerationError(f"{name}: the second start system could not be reached from the first")
    second_solutions = np.array(_refine_exact(family, second, moved))
    if len(second_solutions) != len(solutions):
        raise GenerationError(
            f"{name}: of {len(solutions)} paths to the second start system, {len(second_solutions)} end at "
            "regular solutions"
        )
    if not _smallest_gap(second_solutions) > 1e-6:
        raise GenerationError(f"{name}: two paths to the second start system met")
    return second, second_solutions


def _from_cache(path: Path) -> dict | None:
    """The record this user stored for the family ``path.stem``, or None. A record's solutions
    are verified before use, but its proof cannot be redone cheaply: a record with fewer
    solutions and a forged proof would shrink a proven root count. So it is read only from a
    cache and record folder and a file this user (or root) owns and no one else can write
    (``parakin.packages.compiled.distrust``), and only when it names the family it is stored for;
    anything else is ignored, with a warning, and the start systems come from the package or are
    computed again."""
    from parakin.packages.compiled import distrust

    if not path.is_file():
        return None
    reason = distrust(path.parent.parent) or distrust(path.parent) or distrust(path)
    if reason is not None:
        logger.warning("the start-system record %s is not used: the cache is not private: %s", path, reason)
        return None
    try:
        record = dict(json.loads(path.read_text()))
    except (OSError, ValueError, TypeError):
        return None
    family_key = record.pop("family_key", None)
    if family_key is None:  # an older parakin's record: the package's, or a new one, replaces it
        logger.info("the start-system record %s is not used: it does not name its family (an older record)", path)
        return None
    if family_key != path.stem:
        logger.warning("the start-system record %s is not used: it is for another family (%s)", path, family_key)
        return None
    return record


def _from_package(name: str, method: str, key: str) -> dict | None:
    """The start systems recorded in the committed package of the same equations (the manifest's
    ``family_key``): a fresh clone regenerates without redoing minutes of monodromy. Verified
    like a cached record before it is used."""
    from .build import GENERATED

    try:
        manifest = json.loads((GENERATED / name / "manifest.json").read_text())
        entry = manifest["capabilities"]["forward"]["methods"][method]
        if entry.get("family_key") != key:
            return None

        def pairs(block: dict) -> list:
            return [[re, im] for re, im in zip(block["real"], block["imag"], strict=True)]

        def rows(block: dict) -> list:
            return [
                [[re, im] for re, im in zip(r, i, strict=True)]
                for r, i in zip(block["real"], block["imag"], strict=True)
            ]

        proof = entry["root_count"]
        return {
            "instance": pairs(entry["start_instance"]),
            "solutions": rows(entry["start"]),
            "second_instance": pairs(entry["alternative_instance"]),
            "second_solutions": rows(entry["alternative"]),
            "proof": {k: proof[k] for k in PROOF_KEYS if k in proof},
        }
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _value_trace_proof(proof: dict) -> bool:
    """A count proven by the value curve's trace test (``value_trace_test``)."""
    return str(proof.get("method", "")).startswith(VALUE_TRACE_METHOD) and bool(proof.get("proven"))


def _value_proof(
    name: str, family: Family, q: np.ndarray, point: np.ndarray, flips, rng
) -> tuple[np.ndarray, dict[str, object]] | None:
    """The solutions of F(z; q) = 0 from ``point`` by monodromy in the values, refined, with the
    value curve's trace test that proves them complete; more loops after a test that does not
    close, up to ``VALUE_ATTEMPTS`` tests; None when none closes (the older methods take over)."""
    found = point[None, :]
    began = time.perf_counter()
    for attempt in range(1, VALUE_ATTEMPTS + 1):
        found = value_monodromy(name, family, q, found, flips, rng)
        solutions = np.array(_refine_exact(family, q, found))
        if not len(solutions) or not _smallest_gap(solutions) > 1e-6:
            return None
        logger.info(
            "%s: %d solutions by monodromy in the values (%.0f s); trace test %d of at most %d",
            name, len(solutions), time.perf_counter() - began, attempt, VALUE_ATTEMPTS,
        )  # fmt: skip
        try:
            proof = value_trace_test(name, family, q, solutions, rng)
        except GenerationError as error:
            logger.info("%s: %s", name, error)
            return None
        if proof["complete"]:
            return solutions, proof
        found = solutions
    return None


def _total_degree_proof(proof: dict) -> bool:
    return str(proof.get("method", "")).startswith(TOTAL_DEGREE_METHOD) and "regular_endpoints" in proof


def _total_degree_settled(proof: dict) -> bool:
    """A total-degree proof that today's rule would not extend: proven, or every run tried on
    the equilibrated system."""
    return _total_degree_proof(proof) and (
        bool(proof["proven"])
        or (len(proof["regular_endpoints"]) >= TOTAL_DEGREE_MAX_RUNS and TOTAL_DEGREE_EQUILIBRATED in proof["method"])
    )


def _solutions_at(family: Family, q: np.ndarray, z: np.ndarray) -> bool:
    """Whether the stored points z (P, n) are solutions of F(.; q): a Newton step in doubles below
    1e-10 of 1 + |z|, or, where rounding leaves more (a badly scaled family's: the skew 3-RRS's
    exact solutions, rounded to doubles, take steps up to 1.7e-9), the point that Newton in 40
    digits converges to quadratically from it (``_newton_40``) is the stored one to 1e-13."""
    size = newton_size(family, z, q)
    loose = size >= 1e-10
    if not loose.any():
        return True
    if not (size < REGULAR_RECHECK).all():
        return False
    refined = _newton_40(family, q, z[loose])
    return all(
        row is not None and np.abs(np.array(row) - point).max() <= 1e-13 * (1 + np.abs(point).max())
        for row, point in zip(refined, z[loose], strict=True)
    )


def _verified(family: Family, record: dict, flips: list[np.ndarray], second: bool = True) -> dict | None:
    """A stored record, if it still proves what it claims: its solutions (as many in both start
    systems; the first one only where ``second`` is False) solve their instances (``_solutions_at``), are
    distinct and closed under the sign symmetries, its trace test closed within today's
    tolerance."""
    try:
        count = len(record["solutions"])
        parts = [("instance", "solutions")] + ([("second_instance", "second_solutions")] if second else [])
        for instance, solutions in parts:
            q = np.array([complex(*v) for v in record[instance]])
            z = np.array([[complex(*c) for c in row] for row in record[solutions]])
            if not (count and len(z) == count and _solutions_at(family, q, z)):
                return None
            if not _smallest_gap(z) > 1e-6 or len(_closed(z, flips)) != len(z):
                return None
        proof = record["proof"]
        if _total_degree_proof(proof):
            endpoints = [int(k) for k in proof["regular_endpoints"]]
            if proof["proven"] and (sum(k == count for k in endpoints) < TOTAL_DEGREE_RUNS or max(endpoints) > count):
                return None
        elif proof.get("proven", True) and not float(proof["trace_deviation"]) < TRACE_TOLERANCE:
            return None
        if not proof.get("proven", True) and proof.get("stable_rule") != STABLE_RULE:
            return None  # an unproven count rests on the monodromy's stopping rule: only today's
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return record


def build(
    name: str,
    form: PolynomialForm,
    actuated: tuple[str, list[sp.Symbol]],
    params: tuple[str, list[sp.Symbol]],
    prefix: str,
    seed: int = 2026,
    parameter_values: Mapping[sp.Symbol, float] | None = None,
    home: Mapping[sp.Symbol, float] | None = None,
) -> HomotopySetup:
    """Kernels ``{prefix}_family``, ``{prefix}_monomials`` and ``{prefix}_passive`` and the
    manifest's record. Along H(z, s) each coefficient is a polynomial of degree < ``powers`` in s;
    the runtime gets its coefficients by evaluating the monomials kernel at the ``powers``-th roots
    of unity of the s-plane and one discrete Fourier transform (exact for a polynomial of that
    degree, and perfectly conditioned), so that no expansion in s is generated. With the
    mechanism's ``parameter_values``, parameters that share a value are relations of the family
    (``start_systems``): where they lower its count, the count is proven on their subfamily and
    the manifest's ``subfamily`` names them. With ``home`` (the actuated values at the mechanism's
    home and its parameter values), a third start instance next to it (``near_start``)."""
    rng = np.random.default_rng(seed)
    equations = list(form.equations)
    patch_index = None
    if form.homogeneous:
        patch = _random_complex(rng, len(form.homogeneous))
        equations.append(sp.Add(*(_exact(a) * v for a, v in zip(patch, form.homogeneous, strict=True))) - 1)
        patch_index = len(equations) - 1
    n = len(form.unknowns)
    if len(equations) != n:
        raise GenerationError(f"{name}: the homotopy has {len(equations)} equations for {n} unknowns")
    family, record = start_systems(name, form, equations, seed, prefix, parameter_values)

    # the monomials of every equation, with (C, S, D) and the free parameters as coefficients
    terms: list[tuple[int, tuple[int, ...]]] = []
    coefficients: list[sp.Expr] = []
    for k, equation in enumerate(equations):
        for exponents, coefficient in sp.Poly(equation, *form.unknowns).terms():
            terms.append((k, tuple(int(e) for e in exponents)))
            coefficients.append(coefficient)

    # kernel 1: the family's values at the inputs: the free parameters (real), and the angles
    inputs = set(actuated[1]) | set(params[1])
    steps = [
        (symbol, expression) for symbol, expression in form.family if symbol not in inputs and symbol in family.free
    ]
    angles = [angle for _, angle, _ in form.circles]
    values = Program(
        f"{prefix}_family",
        "The family's parameters at the inputs: the free ones (the manifest's homotopy 'free'), then the angles "
        "that enter through the circle parametrisation (the manifest's 'circles').",
        [actuated, params],
        [("free", sp.Matrix(list(family.free) or [sp.Integer(0)])), ("angles", sp.Matrix(angles or [sp.Integer(0)]))],
        steps=steps,
    )
    # kernel 2: every monomial's coefficient at complex family values, (C, S, D) given per angle
    complex_inputs: list[sp.Symbol] = list(family.free) + [c for _, _, symbols in form.circles for c in symbols]
    real_parts = [sp.Symbol(f"{v}_re", real=True) for v in complex_inputs]
    imag_parts = [sp.Symbol(f"{v}_im", real=True) for v in complex_inputs]
    table = {v: (re, im) for v, re, im in zip(complex_inputs, real_parts, imag_parts, strict=True)}
    cache: dict[sp.Expr, Pair] = {}
    split = [split_complex(c, table, cache) for c in coefficients]
    monomials = Program(
        f"{prefix}_monomials",
        "Each monomial's coefficient (the manifest's term table) at complex family values: the free parameters, "
        "then (C, S, D) of each angle (cos, sin, 1 at the inputs, a point of C^2 + S^2 = D^2 along the homotopy); "
        "real parts, imaginary parts.",
        [("family_re", real_parts or [sp.Symbol("unused_re")]), ("family_im", imag_parts or [sp.Symbol("unused_im")])],
        [("re", sp.Matrix([re for re, _ in split])), ("im", sp.Matrix([im for _, im in split]))],
    )
    # the degree in s along the path: free parameters move linearly, (C, S, D) quadratically
    weights = {v: 1 for v in family.free} | {c: 2 for _, _, symbols in form.circles for c in symbols}

    def degree_in_s(coefficient: sp.Expr) -> int:
        if not weights:
            return 0
        poly = sp.Poly(coefficient, *weights)
        return max(sum(weights[g] * e for g, e in zip(poly.gens, m, strict=True)) for m in poly.monoms())

    powers = 1 + max(degree_in_s(c) for c in coefficients)
    z_real = sp.symbols(f"z0:{n}", real=True)
    passive = sp.Matrix(form.passive).xreplace(dict(zip(form.unknowns, z_real, strict=True)))
    recover = Program(
        f"{prefix}_passive",
        "Passive variables of a real endpoint z of the homotopy (homogeneous unknowns scaled real).",
        [("z", list(z_real)), params],
        [("passive", passive)],
    )
    start = np.array([[complex(*c) for c in row] for row in record["solutions"]])
    alternative = np.array([[complex(*c) for c in row] for row in record["second_solutions"]])
    metadata: dict[str, object] = {
        "method": prefix,
        "unknowns": [str(u) for u in form.unknowns],
        "homogeneous": [form.unknowns.index(h) for h in form.homogeneous],
        "patch_equation": patch_index,
        "degree": len(start),
        "paths": len(start),
        "powers": powers,
        "terms": [[k, list(e)] for k, e in terms],
        "free": [str(v) for v in family.free],
        "circles": [str(angle) for angle in angles],
        "circle_constants": [[float(sp.re(c)), float(sp.im(c))] for c in (MOEBIUS_A, MOEBIUS_B)],
        "branches": [],
        "combinations": [[]],
        "degeneracies": [],
        # one key order whether the record was computed or read back from the package
        "root_count": {
            "count": len(start),
            **{key: record["proof"][key] for key in PROOF_KEYS if key in record["proof"]},
            "tolerance": TRACE_TOLERANCE,
        },
        # sha256 of the equations, seed and parameters: a later build of the same family reuses
        # (after verifying them) the start systems recorded here
        "family_key": record["key"],
        "start": {"real": start.real.tolist(), "imag": start.imag.tolist()},
        "alternative": {"real": alternative.real.tolist(), "imag": alternative.imag.tolist()},
        # the two start instances: free parameters then circle parameters u (complex)
        "start_instance": {"real": [v[0] for v in record["instance"]], "imag": [v[1] for v in record["instance"]]},
        "alternative_instance": {
            "real": [v[0] for v in record["second_instance"]],
            "imag": [v[1] for v in record["second_instance"]],
        },
        "notes": list(form.notes),
    }
    relations = record.get("relations")
    if home is not None and not isinstance(relations, Relations):
        # inside a subfamily the offset would break its relations: those start as before
        from .near_start import near_record

        near = near_record(name, family, form, record, home, seed)
        if near is not None:
            metadata["near"] = near
    if isinstance(relations, Relations):
        # the count is the subfamily's: proven where these relations hold (parameters loaded
        # with other values break them, and with them the count)
        metadata["subfamily"] = relations.manifest()
    symbolic = {f"{prefix}_equations": sp.Matrix(form.equations)}
    return HomotopySetup([values, monomials, recover], metadata, symbolic)
