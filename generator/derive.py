"""Derivations: loop closure, Jacobians, determinants and named singularity factors.

Everything here is symbolic; the products are ``Program``s for the emitters and a dictionary of
SymPy objects for inspection. Conventions: Jacobians give (v, w) of the origin of {P} in {B}.
"""

from __future__ import annotations

import itertools
import random
from dataclasses import dataclass, field
from typing import Any

import mpmath
import sympy as sp

from parakin.log import logger
from parakin.solvers.modes import SCALED_UNITS, length_unit

from . import configurations, graph, polynomial_form, stages, start_systems
from .checks import check_closure, check_home_regular, check_pose_kind, check_program_symbols
from .drawing import drawing_metadata
from .errors import GenerationError
from .frames import vee
from .model import POSE_SYMBOLS, ForwardHomotopy, InverseReading, Mechanism
from .polynomial_form import PolynomialForm
from .program import Program


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
        constant, factors = leg.factored_determinant
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
    mechanism: Mechanism,
    matrix: sp.Matrix,
    found: configurations.Anchors,
    factors: dict[str, sp.Expr] | None = None,
    what: str = "det of the closed-loop matrix = product of parallel_factors",
    samples: int = 12,
) -> int:
    """Prove numerically (40 digits, closed configurations made by the inverse program from poses
    sampled around ``found``) that det(matrix) = sign * product(factors) (default: the parallel
    factors); return the sign. Raise if it does not hold, or if fewer than ``samples`` sampled
    poses are reachable (naming the check ``what``)."""
    factors = mechanism.parallel_factors if factors is None else factors
    if mechanism.inverse is None or not factors:
        return 1
    try:
        with mpmath.workdps(40):  # local: a worker process builds several mechanisms
            return _check_factors(mechanism, matrix, factors, samples, dict(mechanism.parameters), found, what)
    except _VanishingDeterminant:
        # architecturally singular defaults (det = 0 at every pose, e.g. a Gough platform with its
        # base on a conic): the factorisation is an identity in the parameters, so verify it at a
        # nearby generic geometry instead (10 % relative; a zero parameter moves by 10 % of the
        # mechanism's size if it is a length)
        rng = random.Random(20261122)
        nearby = {k: v + 0.1 * rng.uniform(-1, 1) * (abs(v) or found.length) for k, v in mechanism.parameters.items()}
        with mpmath.workdps(40):
            return _check_factors(mechanism, matrix, factors, samples, nearby, found, what)


class _VanishingDeterminant(ValueError):
    """det(matrix) vanishes (relative to its rows) at a sample: nothing to compare factors with."""


def _check_factors(
    mechanism: Mechanism,
    matrix: sp.Matrix,
    factors: dict[str, sp.Expr],
    samples: int,
    parameters: dict,
    found: configurations.Anchors,
    what: str,
) -> int:
    assert mechanism.inverse is not None
    if not found.poses:
        raise GenerationError(
            f"{mechanism.name}: cannot check {what} {list(factors)}: no pose to sample around (the home "
            f"{found.home}, and no named example has a pose); give a home configuration that closes, or "
            "named examples with poses in the workspace"
        )
    variables = [*mechanism.actuated, *mechanism.passive, *mechanism.parameters]
    product = sp.Mul(*factors.values())
    det_fn = sp.lambdify(variables, matrix, modules="mpmath", cse=True)
    product_fn = sp.lambdify(variables, product, modules="mpmath", cse=True)
    inverse_fn = configurations.inverse_function(mechanism, parameters)
    branches = configurations.branch_signs(mechanism)
    rng = random.Random(20261121)
    signs = set()
    checked = tried = near = 0
    while checked < samples and tried < 50 * samples:
        pose = configurations.sample_pose(rng, mechanism, found, tried)
        tried += 1
        for branch in branches:  # the first branch that reaches the pose
            values = inverse_fn(pose, branch)
            joints = [values[v] for v in mechanism.actuated + mechanism.passive]
            if all(isinstance(a, mpmath.mpf) for a in joints) and all(
                configurations.evaluate(condition, values) > 0 for condition in mechanism.inverse.validity.values()
            ):
                break
        else:
            continue  # out of reach for every branch: draw another
        args = joints + [mpmath.mpf(v) for v in parameters.values()]  # floats would evaluate in double
        numeric = mpmath.matrix(det_fn(*args).tolist())
        determinant = mpmath.det(numeric)
        rows = [mpmath.sqrt(sum(numeric[i, j] ** 2 for j in range(numeric.cols))) for i in range(numeric.rows)]
        relative = abs(determinant) / mpmath.fprod(rows)
        if relative <= mpmath.mpf(10) ** -20:
            raise _VanishingDeterminant(f"{mechanism.name}: det vanishes at the parameters {parameters}")
        if relative < mpmath.mpf(10) ** -10:  # near a singularity: cancellation leaves too few digits
            near += 1
            continue
        checked += 1
        expected = product_fn(*args)
        ratio = determinant / expected
        if abs(abs(ratio) - 1) > mpmath.mpf(10) ** -20:
            raise ValueError(f"{mechanism.name}: named factors {list(factors)} do not multiply to det (ratio {ratio})")
        signs.add(int(mpmath.sign(ratio)))
    if checked < samples:
        raise GenerationError(
            f"{mechanism.name}: cannot check {what} {list(factors)}: only {checked} of {tried} poses sampled "
            f"{found.describe()} are reachable and regular (the closed-form inverse has no valid branch at "
            f"{tried - checked - near}, {near} are next to a singularity), {samples} are needed; give a home "
            "configuration that closes and is not singular, or named examples with poses in the workspace"
        )
    if len(signs) != 1:
        raise ValueError(
            f"{mechanism.name}: sign of det / product({list(factors)}) is not constant ({checked} samples)"
        )
    return signs.pop()


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


def _reading_metadata(reading: InverseReading | None) -> dict[str, Any] | None:
    """The manifest's ``capabilities.inverse.reading``: the axis k of the controlled height and
    tilt (expressions of the parameters), the coordinates in words, what the inverse says of a
    pose off the reachable set and the validity conditions that test it; None where the inverse
    takes the pose as given."""
    if reading is None:
        return None
    return {
        "axis": [str(component) for component in reading.axis],
        "controlled": reading.controlled,
        "unreachable": reading.unreachable,
        "reachable": list(reading.reachable),
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
    check_closure(mechanism, residual)  # before anything evaluates it
    platform = mechanism.legs[0].end_transform()
    jacobians = {leg.name: leg.geometric_jacobian() for leg in mechanism.legs}
    serial = serial_factors(mechanism, jacobians)
    found = configurations.anchors(mechanism, platform, residual)
    sign = check_parallel_factors(mechanism, type2_matrix(mechanism, jacobians), found)
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
        platform,
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
    check_closure(mechanism, closure.residual)  # before anything evaluates it
    if rates is None:  # a serial chain: no closed loop, only its own named factors
        return _Closure(
            closure.pose, closure.residual, closure.alignment, None, dict(mechanism.factors), {}, {}, {"legs": []}
        )
    found = configurations.anchors(mechanism, closure.pose, closure.residual)
    sign_a = check_parallel_factors(mechanism, rates.overall(), found, what="det A = product of parallel_factors")
    serial_product = sp.Mul(*rates.serial_factors.values())
    sign_b = check_parallel_factors(
        mechanism, rates.b, found, {"det B": serial_product}, "det B = product of the rate model's serial_factors"
    )
    factors = {**rates.serial_factors, **mechanism.parallel_factors}
    determinants = {"det_A": sign_a * sp.Mul(*mechanism.parallel_factors.values()), "det_B": sign_b * serial_product}
    program = Program(
        "rate_jacobians",
        "Input-output Jacobians of A twist = B actuated_rates."
        + ("" if rates.constraints is None else " Constraint wrenches: constraints twist = 0."),
        state,
        [("a", rates.a), ("b", rates.b), *([] if rates.constraints is None else [("constraints", rates.constraints)])],
    )
    views = {"rate_matrix_A": rates.a, "rate_matrix_B": rates.b}
    if rates.constraints is not None:
        views["constraint_wrenches"] = rates.constraints
    return _Closure(
        closure.pose,
        closure.residual,
        closure.alignment,
        program,
        factors,
        determinants,
        views,
        {
            "legs": [],
            "rates": {
                "twist": rates.twist,
                "input_independent": rates.input_independent,
                "constraints": 0 if rates.constraints is None else rates.constraints.rows,
            },
        },
    )


def _parameter_jacobians(mechanism: Mechanism, state: list, closed: _Closure) -> Program:
    """The closure's and the pose's sensitivities to the geometric parameters: what calibration fits."""
    parameters = list(mechanism.parameters)
    pose_entries = sp.Matrix([closed.platform[i, j] for i in range(3) for j in range(4)])

    # a guard such as Max(0, gram) differentiates to a Heaviside step, which no backend prints: the
    # same step as (sign + 1) / 2 (one-half exactly on the guard's kink, where no derivative exists)
    def smooth(jacobian: sp.Matrix) -> sp.Matrix:
        return jacobian.replace(sp.Heaviside, lambda x, *_: (sp.sign(x) + 1) / 2)

    return Program(
        "parameter_jacobians",
        "Jacobians of the loop-closure residual and of the pose's 12 entries (r11, r12, r13, px, r21, ..., pz: row-major 3 x 4) with respect to the geometric parameters.",
        state,
        [
            ("closure_parameters", smooth(closed.residual.jacobian(parameters))),
            ("pose_parameters", smooth(pose_entries.jacobian(parameters))),
        ],
    )


def check_mobility(mechanism: Mechanism, residual: sp.Matrix) -> graph.Motion:
    """The platform's mobility and motion by screw analysis of the joint graph at the home and at
    generic configurations near it (``graph.analyse``), checked against the declared pose kind
    and actuators; logged. Raise GenerationError saying what differs."""
    joint_graph = mechanism.joint_graph
    assert joint_graph is not None
    found = graph.analyse(
        joint_graph, residual, mechanism.actuated, mechanism.passive, mechanism.parameters, mechanism.home,
        mechanism.angular,
    )  # fmt: skip
    logger.info("%s: %s (screw analysis at %d configurations)", mechanism.name, found.text(), found.samples)
    graph.check_motion(mechanism.name, joint_graph, found, len(mechanism.actuated))
    return found


def _home_values(mechanism: Mechanism) -> dict[sp.Symbol, float] | None:
    """The actuated values at the mechanism's home and its parameter values, where the start
    instance near home is placed (``generator/near_start.py``), in the numbers the runtime's
    all-modes solver works in: every length divided by the power of two nearest the largest
    length parameter (``parakin.mechanism.Mechanism._unit_free``). None where the home does not
    give every actuated value."""
    if not all(a in mechanism.home for a in mechanism.actuated):
        return None
    units = {
        p: (mechanism.parameter_info[p].unit if p in mechanism.parameter_info else "") for p in mechanism.parameters
    }
    lengths = [abs(float(v)) for p, v in mechanism.parameters.items() if units[p] == "m"]
    known = all(u in SCALED_UNITS for u in units.values())
    unit = length_unit(max(lengths, default=0.0)) if known else 1.0
    prismatic = [a for a in mechanism.actuated if a not in mechanism.angular and a not in mechanism.dimensionless]
    return {a: float(mechanism.home[a]) / (unit if a in prismatic else 1.0) for a in mechanism.actuated} | {
        p: float(v) / (unit if units[p] == "m" else 1.0) for p, v in mechanism.parameters.items()
    }


def derive(mechanism: Mechanism) -> Derivation:
    actuated = ("actuated", mechanism.actuated)
    passive = ("passive", mechanism.passive)
    params = ("params", list(mechanism.parameters))
    state = [actuated, passive, params]
    stages.begin("derivations")
    check_pose_kind(mechanism)
    closed = _from_closure(mechanism, state) if mechanism.closure is not None else _from_legs(mechanism, state)
    residual = closed.residual
    joints = None
    if mechanism.joint_graph is not None:
        joints = graph.to_json(mechanism.joint_graph, check_mobility(mechanism, residual))
    if mechanism.passive:
        jacobian_passive = residual.jacobian(mechanism.passive)
        jacobian_actuated = residual.jacobian(mechanism.actuated)
        check_home_regular(mechanism, jacobian_passive)  # warns near a type II singularity
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
        *([_parameter_jacobians(mechanism, state, closed)] if mechanism.parameters else []),
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
        "example": configurations.example_configuration(
            mechanism, closed.platform, residual, closed.alignment, jacobian_passive
        ),
        "singularity_factors": factor_names,
        "determinants": list(determinants),
        "pose_kind": mechanism.pose_kind,
        **closed.metadata,
    }
    if joints is not None:  # the bodies and joints, for a manifest that carries them (not written yet)
        metadata["joints"] = joints
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
        metadata["drawing"] = drawing_metadata(drawing, set(mechanism.actuated) | set(mechanism.passive))

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
            "reading": _reading_metadata(inverse.reading),
        }
        if mechanism.forward is not None:
            programs.append(_inverse_patterns(mechanism, params, groups["groups"]))
        symbolic["inverse_steps"] = sp.Tuple(*(sp.Tuple(t, v) for t, v in inverse.steps))

    methods: dict[str, dict] = {}
    if isinstance(mechanism.forward, ForwardHomotopy):
        forward_homotopy = mechanism.forward
        form = PolynomialForm(
            list(forward_homotopy.unknowns),
            [sp.expand(e) for e in forward_homotopy.equations],
            [(v, v) for v in list(mechanism.actuated) + list(mechanism.parameters)],
            list(forward_homotopy.passive),
            list(forward_homotopy.homogeneous),
            ["the mechanism's own polynomial system (ForwardHomotopy)"],
        )
        stages.begin("own homotopy")
        setup = start_systems.build(
            mechanism.name, form, actuated, params, "homotopy", forward_homotopy.seed, home=_home_values(mechanism)
        )
        programs += setup.programs
        methods["homotopy"] = setup.metadata
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
        methods["elimination"] = {
            "method": "elimination",
            "unknown": str(forward.unknown),
            "degree": len(forward.coefficients) - 1,
            "branches": [str(b) for b in forward.branches],
            "combinations": [list(c) for c in itertools.product((1, -1), repeat=len(forward.branches))],
            "degeneracies": list(forward.degeneracies),
        }
        symbolic["forward_polynomial"] = sp.Add(*(c * forward.unknown**k for k, c in enumerate(forward.coefficients)))
        symbolic["forward_auxiliary"] = sp.Tuple(*(sp.Tuple(t, v) for t, v in forward.auxiliary))
    if mechanism.passive:
        # every mechanism with a loop to close: its modes by the homotopy of the derived polynomial form
        stages.begin("polynomial form")
        form = polynomial_form.derive(
            list(residual), mechanism.passive, mechanism.actuated, list(mechanism.parameters), mechanism.angular
        )
        stages.begin("automatic homotopy")
        try:
            # with the parameter values: parameters sharing a value (sliders on shared rails) can
            # lower the root count, which is then proven where that relation holds
            setup = start_systems.build(
                mechanism.name,
                form,
                actuated,
                params,
                "automatic",
                parameter_values=mechanism.parameters,
                home=_home_values(mechanism),
            )
        except GenerationError as error:
            if not methods:
                raise
            # the mechanism has its own method: it keeps it, and the build says what failed
            logger.warning("%s: no automatic method, the mechanism keeps its own (%s)", mechanism.name, error)
        else:
            programs += setup.programs
            methods["automatic"] = setup.metadata
            symbolic.update(setup.symbolic)
    if methods:
        # the default: a closed form where one was written (exact root isolation, fastest), else the
        # mechanism's own homotopy, else the derived one
        default = next(m for m in ("elimination", "homotopy", "automatic") if m in methods)
        metadata["forward"] = {"default": default, "methods": methods}
    for program in programs:
        inputs = [symbol for _, group in program.inputs for symbol in group]
        check_program_symbols(mechanism, program.name, inputs, program.steps, [m for _, m in program.outputs])
    return Derivation(programs, symbolic, metadata)
