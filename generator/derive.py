"""Derivations: loop closure, Jacobians, determinants and named singularity factors.

Everything here is symbolic; the products are ``Program``s for the emitters and a dictionary of
SymPy objects for inspection. Conventions: Jacobians give (v, w) of the origin of {P} in {B}.
"""

from __future__ import annotations

import functools
import itertools
import random
from collections.abc import Callable
from dataclasses import dataclass, field

import mpmath
import sympy as sp

from . import homotopy
from .checks import check_closure, check_program_symbols
from .frames import vee
from .model import POSE_SYMBOLS, ForwardHomotopy, Mechanism
from .program import Program
from .trigpoly import factor_list


@dataclass
class Derivation:
    """What the generator derived for one mechanism."""

    programs: list[Program]
    symbolic: dict[str, object]
    metadata: dict[str, object] = field(default_factory=dict)


def _name(expr: sp.Expr) -> str:
    text = str(expr)
    for old, new in (("**", "_pow_"), ("(", "_"), (")", ""), ("*", "_"), (" ", ""), ("+", "_plus_"), ("-", "minus_")):
        text = text.replace(old, new)
    return text


def loop_closure(mechanism: Mechanism) -> tuple[sp.Matrix, sp.Matrix]:
    """Every leg must reach the pose of the first: for each other leg k, the position difference
    p_0 - p_k and the rotation error vee(R_0^T R_k), well conditioned near a solution, unlike a
    choice of three matrix entries. vee(R) also vanishes for a half-turn R, so the second
    output, trace(R_0^T R_k) - 1 (2 at a true closure, -2 at a half-turn), tells them apart."""
    transforms = [leg.end_transform() for leg in mechanism.legs]
    first = transforms[0]
    blocks, alignment = [], []
    for other in transforms[1:]:
        relative = first[:3, :3].T * other[:3, :3]
        blocks.append(first[:3, 3] - other[:3, 3])
        blocks.append(vee(relative))
        alignment.append(relative.trace() - 1)
    return sp.Matrix.vstack(*blocks), sp.Matrix(alignment)


def serial_factors(mechanism: Mechanism, jacobians: dict[str, sp.Matrix]) -> dict[str, dict]:
    """Each leg Jacobian's determinant, factored; every factor named (eq 13-14 for SAM)."""
    result = {}
    for leg in mechanism.legs:
        determinant = leg.determinant_jacobian().det(method="berkowitz")
        constant, factors = factor_list(determinant)
        named = []
        for factor, multiplicity in factors:
            name = mechanism.serial_factor_names.get(factor, f"{leg.name}_{_name(factor)}")
            named.append((name, factor, multiplicity))
        result[leg.name] = {"constant": constant, "factors": named}
    return result


def type2_matrix(mechanism: Mechanism, jacobians: dict[str, sp.Matrix]) -> sp.Matrix:
    """Closed-loop matrix of the passive rates with the actuators locked: J_0p qdot_0 = J_kp qdot_k
    for every other leg k. Singular exactly at forward (type II) singularities."""
    passive_columns = []
    for leg in mechanism.legs:
        columns = [i for i, joint in enumerate(leg.joints) if joint in mechanism.passive]
        passive_columns.append(jacobians[leg.name][:, columns])
    rows = []
    for k in range(1, len(mechanism.legs)):
        blocks = [sp.zeros(6, m.cols) for m in passive_columns]
        blocks[0] = passive_columns[0]
        blocks[k] = -passive_columns[k]
        rows.append(sp.Matrix.hstack(*blocks))
    return sp.Matrix.vstack(*rows)


def check_parallel_factors(
    mechanism: Mechanism, matrix: sp.Matrix, factors: dict[str, sp.Expr] | None = None, samples: int = 12
) -> int:
    """Prove numerically (30 digits, random closed configurations made by the inverse program) that
    det(matrix) = sign * product(factors) (default: the parallel factors); return the sign.
    Raise if it does not hold."""
    factors = mechanism.parallel_factors if factors is None else factors
    if mechanism.inverse is None or not factors:
        return 1
    try:
        return _check_factors(mechanism, matrix, factors, samples, dict(mechanism.parameters))
    except _VanishingDeterminant:
        # architecturally singular defaults (det = 0 at every pose, e.g. a Gough platform with its
        # base on a conic): the factorisation is an identity in the parameters, so verify it at a
        # nearby generic geometry instead
        rng = random.Random(20261122)
        nearby = {k: v + 0.1 * (1 + abs(v)) * rng.uniform(-1, 1) for k, v in mechanism.parameters.items()}
        return _check_factors(mechanism, matrix, factors, samples, nearby)


class _VanishingDeterminant(ValueError):
    """det(matrix) vanishes (relative to its rows) at a sample: nothing to compare factors with."""


def _check_factors(
    mechanism: Mechanism, matrix: sp.Matrix, factors: dict[str, sp.Expr], samples: int, parameters: dict
) -> int:
    assert mechanism.inverse is not None
    mpmath.mp.dps = 30
    variables = [*mechanism.actuated, *mechanism.passive, *mechanism.parameters]
    product = sp.Mul(*factors.values())
    det_fn = sp.lambdify(variables, matrix, modules="mpmath", cse=True)
    product_fn = sp.lambdify(variables, product, modules="mpmath", cse=True)
    inverse_fn = _inverse_function(mechanism, parameters)
    rng = random.Random(20261121)
    signs = set()
    checked = 0
    for _ in range(50 * samples):
        if checked == samples:
            break
        pose = _random_pose(rng)
        branch = [1] * len(mechanism.inverse.branches)
        values = inverse_fn(pose, branch)
        joints = [values[v] for v in mechanism.actuated + mechanism.passive]
        if any(not isinstance(a, mpmath.mpf) for a in joints) or not all(
            _evaluate(condition, values) > 0 for condition in mechanism.inverse.validity.values()
        ):
            continue  # unreachable pose for this mechanism: draw another
        args = joints + [mpmath.mpf(v) for v in parameters.values()]  # floats would evaluate in double
        checked += 1
        numeric = mpmath.matrix(det_fn(*args).tolist())
        determinant = mpmath.det(numeric)
        rows = [mpmath.sqrt(sum(numeric[i, j] ** 2 for j in range(numeric.cols))) for i in range(numeric.rows)]
        if abs(determinant) <= mpmath.mpf(10) ** -20 * mpmath.fprod(rows):
            raise _VanishingDeterminant(f"{mechanism.name}: det vanishes at the parameters {parameters}")
        expected = product_fn(*args)
        ratio = determinant / expected
        if abs(abs(ratio) - 1) > mpmath.mpf(10) ** -20:
            raise ValueError(f"{mechanism.name}: named factors {list(factors)} do not multiply to det (ratio {ratio})")
        signs.add(int(mpmath.sign(ratio)))
    if len(signs) != 1:
        raise ValueError(
            f"{mechanism.name}: sign of det / product({list(factors)}) is not constant ({checked} samples)"
        )
    return signs.pop()


def _random_pose(rng: random.Random) -> list:
    """A random rigid pose: rotation from a unit quaternion, position in a 1 m cube above {B}."""
    q = [mpmath.mpf(rng.gauss(0, 1)) for _ in range(4)]
    norm = mpmath.sqrt(sum(x * x for x in q))
    w, x, y, z = (c / norm for c in q)
    rotation = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]
    position = [
        mpmath.mpf(rng.uniform(-0.3, 0.3)),
        mpmath.mpf(rng.uniform(-0.3, 0.3)),
        mpmath.mpf(rng.uniform(0.4, 1.0)),
    ]
    return [c for row in rotation for c in row] + position


@functools.cache
def _compiled(expr: sp.Expr) -> tuple[tuple[sp.Symbol, ...], Callable]:
    """lambdify once per expression: the random-pose checks evaluate the same inverse steps for
    every sample (and a mechanism with narrow validity, e.g. actuator strokes, draws hundreds)."""
    symbols = tuple(sorted(expr.free_symbols, key=sp.default_sort_key))
    return symbols, sp.lambdify(symbols, expr, modules="mpmath")


def _evaluate(expr: sp.Expr, values: dict) -> mpmath.mpf:
    symbols, function = _compiled(expr)
    return function(*[values[s] for s in symbols])


def _branch_groups(mechanism: Mechanism) -> dict[str, list]:
    """Which inverse branch symbols each output depends on, merged into independent groups (one
    per leg, typically). Recovering the passive joints of a pose then costs 2^(largest group)
    inverse evaluations, each group choosing its signs alone, instead of 2^(all symbols)."""
    inverse = mechanism.inverse
    assert inverse is not None
    index = {b: k for k, b in enumerate(inverse.branches)}
    depends: dict[sp.Symbol, set[int]] = {b: {k} for b, k in index.items()}
    for target, value in inverse.steps:
        depends[target] = set().union(*(depends.get(s, set()) for s in value.free_symbols))

    def of(expr: sp.Expr) -> set[int]:
        return set().union(*(depends.get(s, set()) for s in sp.sympify(expr).free_symbols))

    outputs = {
        "actuated": [of(v) for v in mechanism.actuated],
        "passive": [of(v) for v in mechanism.passive],
        "validity": [of(v) for v in inverse.validity.values()],
    }
    owner = list(range(len(inverse.branches)))  # union-find over symbols sharing an output

    def root(k: int) -> int:
        while owner[k] != k:
            k = owner[k]
        return k

    for sets in outputs.values():
        for symbols in sets:
            ordered = sorted(symbols)
            for other in ordered[1:]:
                owner[root(other)] = root(ordered[0])
    roots = sorted({root(k) for k in range(len(owner))})
    groups = [[k for k in range(len(owner)) if root(k) == r] for r in roots]
    group_of = {k: g for g, members in enumerate(groups) for k in members}

    def group(symbols: set[int]) -> int:
        return group_of[min(symbols)] if symbols else -1

    return {
        "groups": groups,
        **{f"{name}_groups": [group(symbols) for symbols in sets] for name, sets in outputs.items()},
    }


def _pattern_signs(groups: list[list[int]], count: int) -> list[list[int]]:
    """Branch signs of each evaluation pattern: symbol k takes bit (its position in its group) of
    the pattern, so one pattern sets every group at once (the C driver's numbering)."""
    position = {k: group.index(k) for group in groups for k in group}
    patterns = 2 ** max((len(g) for g in groups), default=0)
    return [[-1 if (p >> position[k]) & 1 else 1 for k in range(count)] for p in range(patterns)]


def _inverse_patterns(mechanism: Mechanism, params: tuple[str, list], groups: list[list[int]]) -> Program:
    """The inverse pose for every sign pattern in one function: the steps that no branch symbol
    reaches are computed once (what makes recovering passive joints cheaper than one inverse
    call per pattern)."""
    inverse = mechanism.inverse
    assert inverse is not None
    signs = _pattern_signs(groups, len(inverse.branches))
    branched = set(inverse.branches)
    steps: list[tuple[sp.Symbol, sp.Expr]] = []
    renamed: list[dict] = [dict(zip(inverse.branches, pattern, strict=True)) for pattern in signs]
    for target, value in inverse.steps:
        if value.free_symbols & branched:
            branched.add(target)
            for p, mapping in enumerate(renamed):
                symbol = sp.Symbol(f"{target.name}_pattern{p}", real=True)
                steps.append((symbol, value.xreplace(mapping)))
                mapping[target] = symbol
        else:
            steps.append((target, value))

    def stacked(values: list) -> sp.Matrix:
        return sp.Matrix([[sp.sympify(v).xreplace(mapping) for mapping in renamed] for v in values])

    return Program(
        "inverse_pose_patterns",
        "Closed-form inverse pose for every sign pattern of the independent branch groups (column p: "
        "symbol k of a group takes sign -1 where bit (its place in the group) of p is set).",
        [("pose", POSE_SYMBOLS), params],
        [
            ("actuated", stacked(list(mechanism.actuated))),
            ("passive", stacked(list(mechanism.passive))),
            ("validity", stacked(list(inverse.validity.values()))),
        ],
        steps=steps,
    )


def _inverse_function(mechanism: Mechanism, parameters: dict | None = None):
    inverse = mechanism.inverse
    assert inverse is not None
    steps = inverse.steps
    parameters = dict(mechanism.parameters if parameters is None else parameters)

    def evaluate(pose: list, branch: list) -> dict:
        values: dict = dict(zip(POSE_SYMBOLS, pose, strict=True))
        values.update(zip(inverse.branches, branch, strict=True))
        values.update({k: mpmath.mpf(v) for k, v in parameters.items()})
        for target, expr in steps:
            values[target] = _evaluate(expr, values)
        return values

    return evaluate


@dataclass
class _Closure:
    """What the two model styles (DH legs, or a written closure with A/B rates) both provide."""

    platform: sp.Matrix
    residual: sp.Matrix
    alignment: sp.Matrix
    rate_program: Program | None
    factors: dict[str, sp.Expr]
    determinants: dict[str, sp.Expr]
    symbolic: dict[str, object]
    metadata: dict[str, object]


def _from_legs(mechanism: Mechanism, state: list) -> _Closure:
    residual, alignment = loop_closure(mechanism)
    jacobians = {leg.name: leg.geometric_jacobian() for leg in mechanism.legs}
    serial = serial_factors(mechanism, jacobians)
    sign = check_parallel_factors(mechanism, type2_matrix(mechanism, jacobians))
    factors = {name: factor for leg in mechanism.legs for name, factor, _ in serial[leg.name]["factors"]}
    factors.update(mechanism.parallel_factors)
    determinants = {
        f"{leg.name}_leg_determinant": serial[leg.name]["constant"]
        * sp.Mul(*(f**m for _, f, m in serial[leg.name]["factors"]))
        for leg in mechanism.legs
    }
    determinants["closed_loop_determinant"] = sign * sp.Mul(*mechanism.parallel_factors.values())
    program = Program(
        "leg_jacobians",
        "Each leg's 6x6 serial Jacobian (eq 9): rows (v, w) of {P} in {B}, columns the leg's joints.",
        state,
        [(f"{leg.name}", jacobians[leg.name]) for leg in mechanism.legs],
    )
    return _Closure(
        mechanism.legs[0].end_transform(),
        residual,
        alignment,
        program,
        factors,
        determinants,
        {
            **{f"leg_jacobian_{name}": jacobian for name, jacobian in jacobians.items()},
            **{f"leg_transform_{leg.name}": leg.end_transform() for leg in mechanism.legs},
            "closed_loop_matrix": type2_matrix(mechanism, jacobians),
        },
        {"legs": [{"name": leg.name, "joints": [str(j) for j in leg.joints]} for leg in mechanism.legs]},
    )


def _from_closure(mechanism: Mechanism, state: list) -> _Closure:
    closure, rates = mechanism.closure, mechanism.rates
    assert closure is not None
    if rates is None:  # a serial chain: no closed loop, only its own named factors
        return _Closure(
            closure.pose, closure.residual, closure.alignment, None, dict(mechanism.factors), {}, {}, {"legs": []}
        )
    sign_a = check_parallel_factors(mechanism, rates.a)
    serial_product = sp.Mul(*rates.serial_factors.values())
    sign_b = check_parallel_factors(mechanism, rates.b, {"det B": serial_product})
    factors = {**rates.serial_factors, **mechanism.parallel_factors}
    determinants = {"det_A": sign_a * sp.Mul(*mechanism.parallel_factors.values()), "det_B": sign_b * serial_product}
    program = Program(
        "rate_jacobians",
        "Input-output Jacobians of A twist = B actuated_rates.",
        state,
        [("a", rates.a), ("b", rates.b)],
    )
    return _Closure(
        closure.pose,
        closure.residual,
        closure.alignment,
        program,
        factors,
        determinants,
        {"rate_matrix_A": rates.a, "rate_matrix_B": rates.b},
        {"legs": [], "rates": {"twist": rates.twist, "input_independent": rates.input_independent}},
    )


def derive(mechanism: Mechanism) -> Derivation:
    actuated = ("actuated", mechanism.actuated)
    passive = ("passive", mechanism.passive)
    params = ("params", list(mechanism.parameters))
    state = [actuated, passive, params]
    closed = _from_closure(mechanism, state) if mechanism.closure is not None else _from_legs(mechanism, state)
    residual = closed.residual
    check_closure(mechanism, residual)
    if mechanism.passive:
        jacobian_passive = residual.jacobian(mechanism.passive)
        jacobian_actuated = residual.jacobian(mechanism.actuated)
    else:  # nothing to solve for: a serial chain
        jacobian_passive = sp.zeros(residual.rows, 0)
        jacobian_actuated = sp.zeros(residual.rows, len(mechanism.actuated))
    factor_names, factor_values = list(closed.factors), list(closed.factors.values())
    determinants = closed.determinants

    programs = [
        Program(
            "platform_pose",
            "^B_P T (4x4) from actuated and passive values.",
            state,
            [("pose", closed.platform)],
        ),
        Program(
            "loop_closure",
            "Loop-closure residual, its Jacobian with respect to the passive variables, and the alignment measures (positive at a true closure). The Newton kernel.",
            state,
            [("residual", residual), ("jacobian", jacobian_passive), ("alignment", closed.alignment)],
        ),
        Program(
            "loop_closure_actuated",
            "Jacobian of the loop-closure residual with respect to the actuated variables (for passive rates).",
            state,
            [("jacobian_actuated", jacobian_actuated)],
        ),
        *([closed.rate_program] if closed.rate_program is not None else []),
        Program(
            "singularity_factors",
            "Every named singularity factor, then the determinants.",
            state,
            [
                ("factors", sp.Matrix(len(factor_values), 1, factor_values)),
                ("determinants", sp.Matrix(len(determinants), 1, list(determinants.values()))),
            ],
        ),
    ]
    metadata: dict[str, object] = {
        "singularity_factors": factor_names,
        "determinants": list(determinants),
        "pose_kind": mechanism.pose_kind,
        **closed.metadata,
    }
    symbolic: dict[str, object] = {
        "platform_pose": closed.platform,
        "loop_closure": residual,
        **closed.symbolic,
        **{name: value for name, value in determinants.items()},
        **{f"factor_{name}": value for name, value in zip(factor_names, factor_values, strict=True)},
    }

    if mechanism.architecture:
        programs.append(
            Program(
                "architecture",
                "Architecture-singularity measures (parameters only): zero means singular at every pose.",
                [params],
                [("measures", sp.Matrix(list(mechanism.architecture.values())))],
            )
        )
        metadata["architecture"] = list(mechanism.architecture)
        symbolic.update({f"architecture_{name}": value for name, value in mechanism.architecture.items()})

    if mechanism.drawing is not None:
        drawing = mechanism.drawing
        programs.append(
            Program(
                "drawing",
                "Named point sets (3 x n, in {B}) of the mechanism in one configuration, for plots.",
                state,
                list(drawing.points.items()),
            )
        )
        metadata["drawing"] = {
            "points": {name: matrix.cols for name, matrix in drawing.points.items()},
            "polylines": {name: [[s, int(c)] for s, c in line] for name, line in drawing.polylines.items()},
        }

    if mechanism.inverse is not None:
        inverse = mechanism.inverse
        programs.append(
            Program(
                "inverse_pose",
                "Closed-form inverse pose for one branch-sign combination: pose (r11..r33, px, py, pz) -> joints.",
                [("pose", POSE_SYMBOLS), ("branch", inverse.branches), params],
                [
                    ("actuated", sp.Matrix(len(mechanism.actuated), 1, mechanism.actuated)),
                    ("passive", sp.Matrix(len(mechanism.passive), 1, mechanism.passive)),
                    ("validity", sp.Matrix(list(inverse.validity.values()))),
                ],
                steps=inverse.steps,
            )
        )
        groups = _branch_groups(mechanism)
        metadata["inverse"] = {
            "branches": [str(b) for b in inverse.branches],
            "combinations": [list(c) for c in itertools.product((1, -1), repeat=len(inverse.branches))],
            "validity": list(inverse.validity),
            **groups,
            "patterns": _pattern_signs(groups["groups"], len(inverse.branches)),
        }
        if mechanism.forward is not None:
            programs.append(_inverse_patterns(mechanism, params, groups["groups"]))
        symbolic["inverse_steps"] = sp.Tuple(*(sp.Tuple(t, v) for t, v in inverse.steps))

    if isinstance(mechanism.forward, ForwardHomotopy):
        setup = homotopy.build(mechanism, actuated, params)
        programs += setup.programs
        metadata["forward"] = setup.metadata
        symbolic.update(setup.symbolic)
    elif mechanism.forward is not None:
        forward = mechanism.forward
        programs.append(
            Program(
                "forward_polynomial",
                "Coefficients (ascending powers) of the univariate forward-kinematics polynomial, and the elimination's degeneracy measures.",
                [actuated, params],
                [("coefficients", sp.Matrix(forward.coefficients))]
                + ([("degeneracies", sp.Matrix(list(forward.degeneracies.values())))] if forward.degeneracies else []),
                steps=forward.auxiliary,
            )
        )
        programs.append(
            Program(
                "forward_back_substitution",
                "Platform pose ^B_P T from one root of the forward polynomial and one branch-sign combination.",
                [actuated, ("root", [forward.unknown]), ("branch", forward.branches), params],
                [("pose", forward.pose)],
                steps=forward.auxiliary + forward.back_substitution,
            )
        )
        metadata["forward"] = {
            "unknown": str(forward.unknown),
            "degree": len(forward.coefficients) - 1,
            "branches": [str(b) for b in forward.branches],
            "combinations": [list(c) for c in itertools.product((1, -1), repeat=len(forward.branches))],
            "degeneracies": list(forward.degeneracies),
        }
        symbolic["forward_polynomial"] = sp.Add(*(c * forward.unknown**k for k, c in enumerate(forward.coefficients)))
        symbolic["forward_auxiliary"] = sp.Tuple(*(sp.Tuple(t, v) for t, v in forward.auxiliary))
    for program in programs:
        inputs = [symbol for _, group in program.inputs for symbol in group]
        check_program_symbols(mechanism, program.name, inputs, program.steps, [m for _, m in program.outputs])
    return Derivation(programs, symbolic, metadata)
