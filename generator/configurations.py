"""Configurations the generator evaluates numerically: the poses that the singularity-factor
checks sample around, and the regular configuration that the exported C example runs.

Both come from the mechanism's own data, never from a fixed box: the platform pose of the home
configuration (when it closes) and the named examples' poses (``Example.pose`` and the printed
assembly modes ``expected["poses"]``). Spreads are relative to ``length_scale``, so a mechanism
of any size, or with a thin workspace, is sampled where it can be assembled. Poses are lists of
the 12 values of ``POSE_SYMBOLS`` (r11..r33, px, py, pz of ^B_P T).
"""

from __future__ import annotations

import functools
import itertools
import math
import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import mpmath
import numpy as np
import sympy as sp

from .frames import quaternion_from_rotation, quaternion_product, quaternion_rotation
from .model import POSE_KINDS, POSE_SYMBOLS, Example, Mechanism

#: position spread of the samples around an anchor, in length scales, and the rotation spread
#: (radians), taken in turn: near samples are reachable, far ones cover more of the workspace
SPREADS = (0.05, 0.15, 0.4)
#: a home whose loop-closure residual is below this (times 1 + the length scale) closes
HOME_CLOSES = 1e-6
#: the C example's configuration: closure to this (times 1 + the length scale), and a closure
#: Jacobian whose 1/condition exceeds REGULAR (far above the runtime's singular_ratio)
CLOSED = 1e-11
REGULAR = 1e-6
#: an inverse validity measure must exceed this for the mode to be recovered (the runtime's)
VALIDITY = 1e-9


def length_scale(mechanism: Mechanism) -> float:
    """The mechanism's size in metres: the median magnitude of its nonzero length parameters
    (``ParameterInfo`` unit "m"), or 1 m when it declares none."""
    lengths = sorted(
        abs(float(value))
        for symbol, value in mechanism.parameters.items()
        if (info := mechanism.parameter_info.get(symbol)) is not None and info.unit == "m" and value != 0
    )
    return lengths[len(lengths) // 2] if lengths else 1.0


@functools.cache
def _compiled(expr: sp.Expr) -> tuple[tuple[sp.Symbol, ...], Callable]:
    """lambdify once per expression: the random-pose checks evaluate the same inverse steps for
    every sample (and a mechanism with narrow validity, e.g. actuator strokes, draws hundreds)."""
    symbols = tuple(sorted(expr.free_symbols, key=sp.default_sort_key))
    return symbols, sp.lambdify(symbols, expr, modules="mpmath")


def evaluate(expr: sp.Expr, values: dict) -> mpmath.mpf:
    """``expr`` at ``values`` (symbol -> number) in mpmath arithmetic."""
    symbols, function = _compiled(expr)
    return function(*[values[s] for s in symbols])


def inverse_function(mechanism: Mechanism, parameters: dict | None = None) -> Callable[[list, list], dict]:
    """(pose values, branch signs) -> every symbol of the closed-form inverse, in mpmath (a
    complex value where the pose is out of reach for that branch)."""
    inverse = mechanism.inverse
    assert inverse is not None
    parameters = dict(mechanism.parameters if parameters is None else parameters)

    def run(pose: list, branch: list) -> dict:
        values: dict = dict(zip(POSE_SYMBOLS, pose, strict=True))
        values.update(zip(inverse.branches, branch, strict=True))
        values.update({k: mpmath.mpf(v) for k, v in parameters.items()})
        for target, expr in inverse.steps:
            values[target] = evaluate(expr, values)
        return values

    return run


def branch_signs(mechanism: Mechanism, limit: int = 64) -> list[list[int]]:
    """Branch sign combinations of the inverse, all +1 first (at most ``limit``)."""
    count = len(mechanism.inverse.branches) if mechanism.inverse is not None else 0
    return [list(c) for c in itertools.islice(itertools.product((1, -1), repeat=count), limit)]


def _pose_values(matrix: Sequence[Sequence[float]] | sp.Matrix) -> list[float]:
    """12 pose values of a 4 x 4 ^B_P T, or of a 3 x 3 rotation (an orienting platform, p = 0)."""
    rows = [[float(v) for v in row] for row in (matrix.tolist() if isinstance(matrix, sp.Matrix) else matrix)]
    position = [rows[i][3] for i in range(3)] if len(rows) == 4 else [0.0, 0.0, 0.0]
    return [rows[i][j] for i in range(3) for j in range(3)] + position


def _printed_modes(example: Example) -> list:
    """The 4 x 4 poses of the assembly modes an example prints (``expected["poses"]``), if any."""
    modes = example.expected.get("poses")
    return list(modes) if isinstance(modes, list) else []


def close(numeric: _Numeric, actuated: list[float], guess: list[float], tolerance: float) -> list[float] | None:
    """Newton on the loop closure (``numeric`` returns the residual and its passive Jacobian
    first) from ``guess``, steps limited to 0.5 as the runtime's: the passive values where every
    residual is within ``tolerance``, or None."""
    passive = np.array(guess, dtype=float)
    for _ in range(40):
        values, matrix = numeric(actuated, list(passive))[:2]
        if not np.all(np.isfinite(values)):
            return None
        if np.abs(values).max(initial=0.0) <= tolerance:
            return [float(v) for v in passive]
        step = np.linalg.lstsq(matrix.reshape(values.size, passive.size), -values, rcond=None)[0]
        passive = passive + step * min(1.0, 0.5 / max(np.abs(step).max(initial=0.0), 1e-300))
    return None


class _Numeric:
    """Float evaluation of matrices of the actuated, passive and parameter symbols (each
    returned flat, row-major)."""

    def __init__(self, mechanism: Mechanism, matrices: Sequence[sp.Matrix]) -> None:
        self.mechanism = mechanism
        symbols = [*mechanism.actuated, *mechanism.passive, *mechanism.parameters]
        self.function = sp.lambdify(symbols, list(matrices), modules="numpy", cse=True)
        self.parameters = [float(v) for v in mechanism.parameters.values()]

    def __call__(self, actuated: Sequence[float], passive: Sequence[float]) -> list[np.ndarray]:
        values = self.function(*actuated, *passive, *self.parameters)
        return [np.asarray(v, dtype=float).ravel() for v in values]


@dataclass
class Anchors:
    """Poses to sample around, each with what it is ("home", "example 'x'"), the mechanism's
    length scale, and what became of the home (for the message when too few samples reach).
    ``project`` moves a sampled pose onto the reachable set of a lower-mobility platform (None:
    every pose of the pose kind is a candidate)."""

    poses: list[tuple[str, list[float]]]
    length: float
    home: str
    project: Callable[[list], list] | None = None

    def describe(self) -> str:
        where = ", ".join(name for name, _ in self.poses) or "nothing"
        return f"around {where} (length scale {self.length:.3g} m; the home {self.home})"


def anchors(mechanism: Mechanism, platform: sp.Matrix, residual: sp.Matrix) -> Anchors:
    """The home's platform pose when the home closes (after Newton on its passive values, if
    needed), then every named example's pose (examples at other parameters are skipped: their
    poses belong to another geometry)."""
    length = length_scale(mechanism)
    poses: list[tuple[str, list[float]]] = []
    variables = [*mechanism.actuated, *mechanism.passive]
    missing = [str(v) for v in variables if v not in mechanism.home]
    if missing:
        home = f"does not give {missing}"
    else:
        numeric = _Numeric(mechanism, [residual, residual.jacobian(mechanism.passive), platform])
        actuated = [float(mechanism.home[v]) for v in mechanism.actuated]
        passive = [float(mechanism.home[v]) for v in mechanism.passive]
        values, _, pose = numeric(actuated, passive)
        worst = float(np.abs(values).max(initial=0.0))
        closed = close(numeric, actuated, passive, HOME_CLOSES * (1 + length)) if mechanism.passive else passive
        if closed is None:
            home = f"does not close (loop-closure residual {worst:.3g}; Newton from it does not converge)"
        else:
            home = "closes" if closed == passive else f"closes after Newton (its residual is {worst:.3g})"
            pose = numeric(actuated, closed)[2]
            poses.append(("the home", _pose_values(pose.reshape(4, 4).tolist())))
    for example in mechanism.examples:
        if example.parameters:
            continue
        if example.pose is not None:
            poses.append((f"example {example.name!r}", _pose_values(example.pose)))
        for k, mode in enumerate(_printed_modes(example)):
            poses.append((f"example {example.name!r} mode {k}", _pose_values(mode)))
    return Anchors(poses, length, home, _projection(mechanism, platform, residual, length))


def _projection(
    mechanism: Mechanism, platform: sp.Matrix, residual: sp.Matrix, length: float
) -> Callable[[list], list] | None:
    """For a lower-mobility platform (constraint wrenches in its rate model): a function that
    moves a pose onto the set its constraints allow, by minimum-norm Newton steps on the closure
    rows free of actuated variables (its plane constraints, a unit quaternion) from the pose's
    coordinates as the inverse reads them. A pose sampled around an anchor in every direction
    of its kind is otherwise off that set, and an inverse that checks reachability refuses
    almost all of them. None where there is nothing to project (or no way to)."""
    if mechanism.rates is None or mechanism.rates.constraints is None or mechanism.inverse is None:
        return None
    rows = [row for row in residual if not row.has(*mechanism.actuated)]
    if platform.has(*mechanism.actuated):
        return None
    # no such row: the coordinates are the constrained motion's own (a Tricept's passive leg
    # joints), and the pose they place from the inverse's reading is on the set
    constraint = sp.Matrix(rows) if rows else sp.zeros(0, 1)
    # constraints that turn with the actuated joints (a skew R-R-S leg: fewer rows free of them
    # than constraint wrenches): Newton on the whole closure, actuated joints (from the home) and
    # passive coordinates together
    joint = 0 < len(rows) < mechanism.rates.constraints.rows
    unknowns = [*mechanism.actuated, *mechanism.passive] if joint else list(mechanism.passive)
    constraint = residual if joint else constraint
    variables = [*unknowns, *mechanism.parameters]
    numeric = sp.lambdify(variables, [constraint, constraint.jacobian(unknowns)], modules="numpy", cse=True)
    placed = sp.lambdify([*mechanism.passive, *mechanism.parameters], platform, modules="mpmath")
    parameters = [float(v) for v in mechanism.parameters.values()]
    read = inverse_function(mechanism)
    signs = branch_signs(mechanism)[0]
    tolerance = 1e-14 * (1 + length)
    start = [float(mechanism.home.get(v, 0.0)) for v in mechanism.actuated] if joint else []

    def project(pose: list) -> list:
        values = read(pose, signs)
        coordinates = [values[v] for v in mechanism.passive]
        if not all(isinstance(v, mpmath.mpf) for v in coordinates):
            return pose
        state = np.array([*start, *(float(v) for v in coordinates)])
        for _ in range(50):
            value, matrix = (np.asarray(v, dtype=float) for v in numeric(*state, *parameters))
            value = value.ravel()
            if not np.all(np.isfinite(value)) or not np.all(np.isfinite(matrix)):
                return pose
            if np.abs(value).max(initial=0.0) <= tolerance:
                # the pose at the working precision from the coordinates, as sample_pose builds it
                passive = state[len(start) :]
                transform = placed(*(mpmath.mpf(v) for v in passive), *(mpmath.mpf(v) for v in parameters))
                entries = mpmath.matrix(transform)
                return [entries[i, j] for i in range(3) for j in range(3)] + [entries[i, 3] for i in range(3)]
            step = np.linalg.lstsq(matrix.reshape(value.size, state.size), -value, rcond=None)[0]
            state = state + step
        return pose

    return project


def sample_pose(rng: random.Random, mechanism: Mechanism, found: Anchors, index: int) -> list:
    """Sample ``index``: anchor ``index`` (in turn) moved along and turned about the axes its
    pose kind moves in, by up to SPREADS[...] length scales and radians; mpmath values."""
    _, anchor = found.poses[index % len(found.poses)]
    spread = SPREADS[(index // len(found.poses)) % len(SPREADS)]
    kind = POSE_KINDS[mechanism.pose_kind]
    turn = [mpmath.mpf(spread * rng.uniform(-1, 1)) if k in kind.rotation_axes else mpmath.mpf(0) for k in range(3)]
    half = mpmath.sqrt(sum(v * v for v in turn)) / 2
    sinc = mpmath.sin(half) / (2 * half) if half else mpmath.mpf(1) / 2
    # anchor * turn (the turn about axes of {P}), in quaternions at the working precision, so
    # that the sampled rotation is orthogonal to it (one rounded to doubles breaks the closure
    # identities at 1e-16); frames holds the one set of rotation helpers
    digits = mpmath.mp.dps
    anchor_rotation = sp.Matrix(3, 3, [sp.Float(v, digits) for v in anchor[:9]])
    turn_quaternion = [sp.Float(mpmath.cos(half), digits), *(sp.Float(v * sinc, digits) for v in turn)]
    quaternion = quaternion_product(quaternion_from_rotation(anchor_rotation), turn_quaternion)
    rotation = quaternion_rotation(quaternion).evalf(digits).tolist()
    position = [
        anchor[9 + k] + (spread * found.length * rng.uniform(-1, 1) if k in kind.translation_axes else 0.0)
        for k in range(3)
    ]
    pose = [mpmath.mpf(v) for row in rotation for v in row] + [mpmath.mpf(v) for v in position]
    return pose if found.project is None else found.project(pose)


def _same_angle(a: float, b: float, angular: bool, tolerance: float) -> bool:
    difference = a - b
    if angular:
        difference = math.remainder(difference, 2 * math.pi)
    return abs(difference) <= tolerance


@dataclass
class _Candidate:
    source: str
    actuated: list[float]
    guess: list[float]


def example_configuration(
    mechanism: Mechanism, platform: sp.Matrix, residual: sp.Matrix, alignment: sp.Matrix, jacobian: sp.Matrix
) -> dict[str, object]:
    """See ``_example_configuration``; the inverse is evaluated to 30 digits whatever the global
    mpmath precision (the output must not depend on what a worker process built before)."""
    with mpmath.workdps(30):
        return _example_configuration(mechanism, platform, residual, alignment, jacobian)


def _example_configuration(
    mechanism: Mechanism, platform: sp.Matrix, residual: sp.Matrix, alignment: sp.Matrix, jacobian: sp.Matrix
) -> dict[str, object]:
    """The configuration the exported C example solves: the first candidate that closes and is
    regular (well-conditioned closure Jacobian, positive alignment, within limits, and recovered
    by the closed-form inverse with every validity measure positive). Candidates, in order: each
    named example with actuated inputs (Newton from the passive values of its printed modes, or
    from the home's), the home, the inverse of the home's pose (each branch), each named example
    pose (each branch). Returns its ``source`` (what it is), ``actuated``, the ``passive`` values
    and the Newton ``guess`` (the passive values rounded to 4 digits, from which Newton is checked
    to come back), or the home with ``verified`` False when no candidate is regular."""
    length = length_scale(mechanism)
    numeric = _Numeric(mechanism, [residual, jacobian, alignment, platform])
    home_actuated = [float(mechanism.home.get(v, 0.0)) for v in mechanism.actuated]
    home_passive = [float(mechanism.home.get(v, 0.0)) for v in mechanism.passive]
    inverse = inverse_function(mechanism) if mechanism.inverse is not None else None

    def inverted(pose: list[float]) -> list[tuple[int, list[float], list[float]]]:
        """(branch, actuated, passive) of every branch that reaches ``pose``."""
        if inverse is None:
            return []
        result = []
        for k, signs in enumerate(branch_signs(mechanism)):
            values = inverse([mpmath.mpf(v) for v in pose], signs)
            joints = [values[v] for v in [*mechanism.actuated, *mechanism.passive]]
            if all(isinstance(v, mpmath.mpf) for v in joints):
                count = len(mechanism.actuated)
                result.append((k, [float(v) for v in joints[:count]], [float(v) for v in joints[count:]]))
        return result

    def candidates():
        for example in mechanism.examples:
            if example.parameters or example.actuated is None:
                continue
            guesses = [
                passive
                for mode in _printed_modes(example)
                for _, actuated, passive in inverted(_pose_values(mode))
                if all(
                    _same_angle(a, b, v in mechanism.angular, 1e-3 * (1 + length))
                    for a, b, v in zip(actuated, example.actuated, mechanism.actuated, strict=True)
                )
            ]
            for guess in [*guesses, home_passive]:
                yield _Candidate(f"example {example.name!r}", [float(v) for v in example.actuated], guess)
        yield _Candidate("the home configuration", home_actuated, home_passive)
        home_pose = numeric(home_actuated, home_passive)[3]
        for branch, actuated, passive in inverted(_pose_values(home_pose.reshape(4, 4).tolist())):
            yield _Candidate(f"the inverse of the home pose, branch {branch}", actuated, passive)
        for example in mechanism.examples:
            if example.parameters or example.pose is None:
                continue
            for branch, actuated, passive in inverted(_pose_values(example.pose)):
                yield _Candidate(f"the inverse of example {example.name!r}, branch {branch}", actuated, passive)

    def newton(actuated: list[float], guess: list[float]) -> list[float] | None:
        return close(numeric, actuated, guess, CLOSED * (1 + length))

    def regular(actuated: list[float], passive: list[float]) -> bool:
        _, matrix, align, pose = numeric(actuated, passive)
        if passive:
            singular = np.linalg.svd(matrix.reshape(len(passive), len(passive)), compute_uv=False)
            if not singular[-1] > REGULAR * singular[0]:
                return False
        if not np.all(align > 0):
            return False
        for symbol, value in zip([*mechanism.actuated, *mechanism.passive], [*actuated, *passive], strict=True):
            low, high = mechanism.limits.get(symbol, (-math.inf, math.inf))
            if not low <= value <= high:
                return False
        if inverse is None or mechanism.forward is None:  # nothing recovers passive values from a pose
            return True
        pose_values = [mpmath.mpf(v) for v in _pose_values(pose.reshape(4, 4).tolist())]
        for signs in branch_signs(mechanism):
            values = inverse(pose_values, signs)
            joints = [values[v] for v in mechanism.actuated]
            if all(isinstance(v, mpmath.mpf) for v in joints) and all(
                _same_angle(float(a), b, v in mechanism.angular, 1e-7 * (1 + length))
                for a, b, v in zip(joints, actuated, mechanism.actuated, strict=True)
            ):
                measures = [evaluate(m, values) for m in mechanism.inverse.validity.values()]  # type: ignore[union-attr]
                if all(isinstance(m, mpmath.mpf) and m > VALIDITY for m in measures):
                    return True
        return False

    tried = 0
    for candidate in candidates():
        tried += 1
        solved = newton(candidate.actuated, candidate.guess)
        passive = None if solved is None else [float(v) for v in solved]
        if passive is None or not regular(candidate.actuated, passive):
            continue
        guess = [float(f"{v:.4g}") for v in passive]
        back = newton(candidate.actuated, guess)
        if back is None or np.abs(np.subtract(back, passive)).max(initial=0.0) > 1e-8 * (1 + length):
            guess = passive
        return {
            "source": candidate.source,
            "actuated": candidate.actuated,
            "passive": passive,
            "guess": guess,
            "verified": True,
        }
    return {
        "source": f"the home configuration (none of {tried} candidates is regular)",
        "actuated": home_actuated,
        "passive": home_passive,
        "guess": home_passive,
        "verified": False,
    }
