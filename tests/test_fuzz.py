"""Property-based contract: every input is answered, by a correct, finite result or by a named error.

For every mechanism of ``parakin.available()``, every backend ('numpy', 'casadi', 'compiled') and
every public operation the manifest's capabilities offer (``load`` with parameters and limits,
``inverse_pose``, ``forward_pose``, ``forward_pose_all``, ``count_modes``, ``loop_closure``,
``platform_pose``, ``inverse_rate`` / ``forward_rate`` / ``passive_rates`` (with and without
``damping``), ``rate_jacobians`` / ``leg_jacobians``, ``actuator_forces``, ``singularities``,
``within_limits``, ``tracker(...).solve``) and for the pose helpers of ``parakin.pose``, every input
gets either

* a result: finite (non-finite values only in entries the result flags invalid: a branch that is
  not ``valid``, a mode that is not ``valid``, a Newton solve that is not ``converged``), of the
  caller's batch shape, equal to the single calls of its batch elements, and correct where it can
  be checked (closed loops, reproduced poses, rates consistent both ways); or
* an exception that is an instance of ``parakin.errors.ParakinError``.

Inputs are grouped into classes (``Variant.cls``) with an expectation:

* ``ok``: well-formed input that must give a result (lists, tuples, batches of any rank, empty
  batches (0, n), non-contiguous and read-only arrays, one unbatched guess / state / twist against
  a batch);
* ``raise``: malformed input that must raise a ParakinError (complex values, strings, None, object
  arrays, ragged lists, wrong last axes, out-of-domain options such as a negative tolerance,
  damping=nan or damping=-1, unknown keyword arguments);
* ``flag``: non-finite values (NaN, inf): a ParakinError, or a result that flags the entry invalid
  (a result without such flags must raise);
* ``either``: extreme but well-formed values (huge, tiny, negative lengths, zero parameters,
  2**32 + 3 iterations): a ParakinError or a correct, finite result.

The same inputs must get the same answer on every backend: the same exception class, or results
equal to 1e-8. The operation and input registries below are shared with the before-fix census
(``/work/fuzz/census.py``), which enumerates them deterministically; the tests here draw them with
hypothesis. Mechanisms are never named: operations and sizes come from the manifest.

Profiles: ``PARAKIN_FUZZ=fast`` (the default, the whole file in well under a minute) or
``PARAKIN_FUZZ=thorough`` (ten times the examples).
"""

from __future__ import annotations

import dataclasses
import functools
import os
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import contract_helpers as h
import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, example, given, settings
from hypothesis import strategies as st

import parakin
from parakin import Configuration
from parakin.errors import ParakinError
from parakin.validation import MIN_TOLERANCE

NAMES = parakin.available()
BACKENDS = h.BACKENDS
CASES = [pytest.param(name, backend, id=f"{name}-{backend}") for name in NAMES for backend in BACKENDS]

PROFILE = os.environ.get("PARAKIN_FUZZ", "fast")
SCALE = {"fast": 1, "thorough": 10}.get(PROFILE, 1)

#: relative agreement of a batch with its single calls (same backend) and of the backends
BATCH_AGREEMENT = 1e-10
BACKEND_AGREEMENT = 1e-8
#: a closed loop / a reproduced pose (the contract suite's bound)
CLOSURE = 1e-9

#: outcome categories: the first two answer the contract, the others break it
GOOD = ("ok", "named")
BAD = ("nan", "wrong", "accepted", "named!", "other")
CATEGORY_HELP = {
    "ok": "a finite (or correctly flagged) result",
    "named": "a parakin.errors.ParakinError",
    "nan": "a result with an unflagged NaN / inf (silently wrong)",
    "wrong": "a finite result of the wrong shape, unequal to the single calls, or incorrect",
    "accepted": "a result for an input that must be rejected (or a non-finite entry not flagged)",
    "named!": "a ParakinError for an input that must give a result",
    "other": "an exception that is not a ParakinError",
}


def fuzz_settings(examples: int) -> settings:
    """Deterministic hypothesis settings: ``examples`` x the profile's scale, no deadline, no
    example database (nothing is written into the checkout), no explain phase (failures print
    their own reproducer)."""
    return settings(
        max_examples=examples * SCALE,
        deadline=None,
        derandomize=True,
        database=None,
        phases=(Phase.explicit, Phase.reuse, Phase.generate, Phase.shrink),
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large],
    )


# ---------------------------------------------------------------------------- code literals
def lit(value: Any) -> str:
    """A Python expression (using ``np`` and ``Configuration``) that rebuilds ``value``: the
    reproducers printed by failing tests and by the census."""
    if isinstance(value, Configuration):
        return f"Configuration({lit(value.actuated)}, {lit(value.passive)}, {lit(value.pose)})"
    if isinstance(value, np.ndarray):
        if value.dtype == object:
            return f"np.array({lit(value.tolist())}, dtype=object)"
        if value.size == 0:
            return f"np.zeros({value.shape})" + ("" if value.dtype == float else f".astype({value.dtype.name!r})")
        body = lit(value.tolist())
        if value.ndim == 0:
            return f"np.array({body}, dtype={value.dtype.name!r})"
        return f"np.array({body})" if value.dtype == float else f"np.array({body}, dtype={value.dtype.name!r})"
    if isinstance(value, bool | np.bool_):
        return repr(bool(value))
    if isinstance(value, float | np.floating):
        number = float(value)
        if np.isnan(number):
            return "np.nan"
        if np.isinf(number):
            return "np.inf" if number > 0 else "-np.inf"
        return repr(number)
    if isinstance(value, complex | np.complexfloating):
        return repr(complex(value))
    if isinstance(value, list):
        return "[" + ", ".join(lit(v) for v in value) + "]"
    if isinstance(value, tuple):
        return "(" + ", ".join(lit(v) for v in value) + ("," if len(value) == 1 else "") + ")"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k!r}: {lit(v)}" for k, v in value.items()) + "}"
    return repr(value)


# ---------------------------------------------------------------------------- fixtures
@dataclass(frozen=True)
class Fixture:
    """Inputs of one mechanism, computed once on the NumPy backend and shared by every backend:
    closed, well-conditioned configurations (one, and a batch of five), a Newton guess a few
    steps from the first, actuated values near its own (a tracker's next input), a twist,
    actuated rates and a wrench."""

    name: str
    parameters: dict[str, float]
    state: Configuration
    states: Configuration
    guess: np.ndarray
    moved: np.ndarray
    twist: np.ndarray
    rates: np.ndarray
    wrench: np.ndarray


def has_rates(m) -> bool:
    return m.capabilities.rates is not None or m.capabilities.legs is not None


def has_modes(m) -> bool:
    return m.capabilities.forward is not None or not m.passive_names


def _conditioning(m, c: Configuration) -> float:
    """The scaled closure Jacobian's condition number if ``c`` is closed (Newton stays there) and
    its rate maps are invertible; inf otherwise."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        condition = 1.0
        if m.passive_names:
            fk = m.forward_pose(c.actuated, guess=c.passive, strict=False)
            if not bool(fk.converged):
                return np.inf
            condition = float(h.condition(m, c.actuated, c.passive))
        if has_rates(m):
            try:
                m.forward_rate(c, np.ones(len(m.actuated_names)))
                m.inverse_rate(c, h.feasible_twist(m, c, np.ones(m.manifest.twist_size)))
            except ParakinError:
                return np.inf
    return condition


@functools.cache
def fixture(name: str) -> Fixture:
    m = h.load(name, "numpy")
    rng = np.random.default_rng(h.seed(name, "fuzz fixture"))
    poses, _ = h.sample_poses(m, rng, 40)
    ik = m.inverse_pose(poses, strict=False)
    candidates: list[tuple[float, int, Configuration]] = []
    for i in np.flatnonzero(ik.valid.any(-1)):
        branches = np.flatnonzero(ik.valid[i])
        k = branches[len(candidates) % branches.size]
        candidate = Configuration(ik.actuated[i, k], ik.passive[i, k], ik.pose[i])
        candidates.append((_conditioning(m, candidate), int(i), candidate))
    # the best conditioned six (a geometry near an architecture singularity has no good ones)
    good = [c for condition, _, c in sorted(candidates, key=lambda t: t[:2]) if condition < 1e8][:6]
    assert len(good) == 6, f"{name}: fewer than 6 usable closed configurations near home"
    state, rest = good[0], good[1:]
    states = Configuration(*(np.stack([getattr(c, key) for c in rest]) for key in ("actuated", "passive", "pose")))
    scale = h.variable_scale(m, m.manifest.passive)
    guess = state.passive + 0.05 * scale * rng.normal(size=state.passive.shape)
    moved = state.actuated + 1e-5 * h.variable_scale(m, m.manifest.actuated) * rng.normal(size=state.actuated.shape)
    twist_scale = np.array([h.length_scale(m)] * 3 + [1.0] * 3)[h.twist_components(m)] if has_rates(m) else 1.0
    twist = h.feasible_twist(m, state, rng.normal(size=m.manifest.twist_size) * twist_scale)
    rates = rng.normal(size=len(m.actuated_names)) * h.variable_scale(m, m.manifest.actuated)
    wrench = rng.normal(size=m.manifest.twist_size)
    return Fixture(name, dict(h.usable_parameters(name)), state, states, guess, moved, twist, rates, wrench)


def mechanism(name: str, backend: str):
    return h.load(name, backend)


# ---------------------------------------------------------------------------- operations
@dataclass
class Op:
    """One public operation with one argument fuzzed (``role``); the others are the fixture's.

    ``call(value)`` runs it, ``code`` is its source with ``@V`` for the value's code, ``kind``
    says how to read the result (flags, masks), ``verify(value, result)`` checks a result
    (None: correct, else what is wrong). ``batched``: the batch classes of the role apply (False
    for a tracker, whose batch is fixed at construction)."""

    label: str
    method: str
    role: str
    canonical: Any
    call: Callable[[Any], Any]
    code: str
    kind: str
    verify: Callable[[Any, Any], str | None] | None = None
    batched: bool = True
    unsupported: bool = False
    backend_free: bool = False
    classes: tuple[str, ...] | None = None  # a subset of the role's classes (None: all)
    size: int = 0  # the fuzzed vector's length (array roles)
    pose_kind: str = "transform"
    fixed_batch: tuple[int, ...] | None = None  # the result's batch whatever the input's (a tracker's)
    dimensionless: tuple[int, ...] = ()  # entries of the fuzzed vector that are dimensionless (quaternions)


def _size(m, *arrays) -> float:
    """1 + the largest length among the arrays, in length scales: closure and pose errors of
    huge (finite) inputs are judged relative to it (rounding grows with the values)."""
    largest = max((float(np.abs(np.asarray(a)).max(initial=0.0)) for a in arrays), default=0.0)
    return 1.0 + largest / h.length_scale(m)


def _closure(m, actuated, passive) -> float:
    if not m.passive_names or np.size(passive) == 0:
        return 0.0
    residual = m.loop_closure(actuated, passive)["residual"]
    return float(np.abs(residual).max(initial=0.0))


def verify_inverse(m):
    def check(value, result) -> str | None:
        valid = np.asarray(result.valid)
        if not valid.any():
            return None
        actuated, passive = result.actuated[valid], result.passive[valid]
        target = np.broadcast_to(result.pose[..., None, :, :], valid.shape + (4, 4))[valid]
        size = _size(m, actuated, passive, target[..., :3, 3])
        closure = _closure(m, actuated, passive)
        if not closure < CLOSURE * size:
            return f"a valid branch does not close the loop (residual {closure:.3g}, size {size:.3g})"
        if h.full_dof(m):
            error = float(h.pose_tolerance(m, m.platform_pose(actuated, passive), target).max())
            if not error < CLOSURE * size:
                return f"a valid branch misses the pose by {error:.3g} (size {size:.3g})"
        return None

    return check


def verify_forward(m, tolerance: float = 1e-12):
    def check(value, result) -> str | None:
        converged = np.asarray(result.converged)
        if not converged.any() or tolerance > CLOSURE:
            return None
        actuated, passive = np.asarray(result.actuated)[converged], np.asarray(result.passive)[converged]
        closure = _closure(m, actuated, passive) / _size(m, actuated, passive)
        if not closure <= CLOSURE:
            return f"a converged Newton result does not close the loop (residual {closure:.3g})"
        error = float(h.pose_tolerance(m, m.platform_pose(actuated, passive), np.asarray(result.pose)[converged]).max())
        if not error < CLOSURE:
            return f"a converged result's pose is not platform_pose of its passive values ({error:.3g})"
        return None

    return check


def verify_modes(m):
    def check(value, result) -> str | None:
        valid = np.asarray(result.valid)
        if not valid.any() or not m.passive_names:
            return None
        grid = np.broadcast_to(result.actuated[..., None, :], result.passive.shape[:-1] + result.actuated.shape[-1:])
        closure = _closure(m, grid[valid], result.passive[valid]) / _size(m, grid[valid], result.passive[valid])
        return None if closure < CLOSURE else f"a valid mode does not close the loop (relative residual {closure:.3g})"

    return check


def verify_tracker(m, actuated=None):
    def check(value, result) -> str | None:
        passive, _ = result
        solved = np.asarray(value if actuated is None else actuated, dtype=float)
        tracker_actuated = np.broadcast_to(solved, passive.shape[:-1] + (len(m.actuated_names),))
        closure = _closure(m, tracker_actuated, passive)
        return None if closure <= CLOSURE else f"the tracker's solution does not close the loop ({closure:.3g})"

    return check


def verify_tracker_start(m):
    def check(value, result) -> str | None:
        return verify_tracker(m, value.actuated)(value, result)

    return check


def verify_inverse_rate(m, state: Configuration):
    def check(value, result) -> str | None:
        twist = np.asarray(value, dtype=float)
        if np.asarray(result.actuated).ndim != 1:
            return None
        back = m.forward_rate(state, result.actuated)
        error = float(np.abs(back - twist).max() / (1.0 + np.abs(twist).max()))
        return None if error < 1e-6 else f"forward_rate(inverse_rate(twist)) differs from the twist by {error:.3g}"

    return check


def verify_forward_rate(m, state: Configuration):
    def check(value, result) -> str | None:
        rates = np.asarray(value, dtype=float)
        if np.asarray(result).ndim != 1:
            return None
        back = m.inverse_rate(state, result).actuated
        error = float(np.abs(back - rates).max() / (1.0 + np.abs(rates).max()))
        return None if error < 1e-6 else f"inverse_rate(forward_rate(rates)) differs from the rates by {error:.3g}"

    return check


def verify_rotation(value, result) -> str | None:
    rotation = np.asarray(result)[..., :3, :3]
    if rotation.size == 0:
        return None
    gram = np.einsum("...ji,...jk->...ik", rotation, rotation)
    if not np.abs(gram - np.eye(3)).max() < 1e-9 or not (np.linalg.det(rotation) > 0).all():
        return "not a rotation"
    return None


def verify_euler_round_trip(value, result) -> str | None:
    if verify_rotation(value, result):
        return "not a rigid transform"
    back = parakin.pose_from_xyz_euler(parakin.xyz_euler_from_pose(result))
    error = float(np.abs(back - result).max(initial=0.0))
    return None if error < 1e-9 else f"pose_from_xyz_euler(xyz_euler_from_pose(T)) misses T by {error:.3g}"


def operations(m, fx: Fixture) -> list[Op]:
    """Every public operation of ``m`` with each of its fuzzed arguments (from the capabilities)."""
    s, a, p, pose = fx.state, fx.state.actuated, fx.state.passive, fx.state.pose
    n_a, n_p = len(m.actuated_names), len(m.passive_names)
    S, A, P, T, G = lit(s), lit(a), lit(p), lit(pose), lit(fx.guess)
    TW, R = lit(fx.twist), lit(fx.rates)
    kind = m.manifest.pose_kind
    ops = [
        Op("platform_pose(actuated)", "platform_pose", "actuated", a, lambda v: m.platform_pose(v, p),
           f"m.platform_pose(@V, {P})", "array", size=n_a),
        Op("platform_pose(passive)", "platform_pose", "passive", p, lambda v: m.platform_pose(a, v),
           f"m.platform_pose({A}, @V)", "array", size=n_p),
        Op("loop_closure(actuated)", "loop_closure", "actuated", a, lambda v: m.loop_closure(v, p),
           f"m.loop_closure(@V, {P})", "dict", size=n_a),
        Op("loop_closure(passive)", "loop_closure", "passive", p, lambda v: m.loop_closure(a, v),
           f"m.loop_closure({A}, @V)", "dict", size=n_p),
        Op("singularities(state)", "singularities", "state", s, lambda v: m.singularities(v),
           "m.singularities(@V)", "dict"),
        Op("within_limits(passive)", "within_limits", "passive", p, lambda v: m.within_limits(v),
           "m.within_limits(@V)", "mask", size=n_p),
        Op("forward_pose(actuated)", "forward_pose", "actuated", a, lambda v: m.forward_pose(v, guess=p),
           f"m.forward_pose(@V, guess={P})", "fk", verify_forward(m), size=n_a),
        Op("forward_pose(actuated, strict=False)", "forward_pose", "actuated", a,
           lambda v: m.forward_pose(v, guess=p, strict=False), f"m.forward_pose(@V, guess={P}, strict=False)", "fk",
           verify_forward(m), size=n_a, classes=FLAG_CLASSES + EITHER_CLASSES + ("valid", "batch-2d", "empty")),
        Op("forward_pose(actuated, no guess)", "forward_pose", "actuated", a, lambda v: m.forward_pose(v),
           "m.forward_pose(@V)", "fk", verify_forward(m), size=n_a),
        Op("forward_pose(guess)", "forward_pose", "guess", p, lambda v: m.forward_pose(a, guess=v),
           f"m.forward_pose({A}, guess=@V)", "fk", verify_forward(m), size=n_p,
           dimensionless=tuple(i for i, v in enumerate(m.manifest.passive) if v.kind == "dimensionless")),
    ]  # fmt: skip
    for option, role in (("tolerance", "tolerance"), ("max_iterations", "max_iterations"), ("max_step", "max_step")):
        ops.append(
            Op(f"forward_pose({option}=)", "forward_pose", role, None,
               lambda v, o=option: m.forward_pose(a, guess=fx.guess, **{o: v}),
               f"m.forward_pose({A}, guess={G}, {option}=@V)", "fk",
               verify_forward(m, 1.0) if option == "tolerance" else verify_forward(m))
        )  # fmt: skip
    ops.append(
        Op("forward_pose(**kwargs)", "forward_pose", "kwargs", None, lambda v: m.forward_pose(a, guess=p, **v),
           f"m.forward_pose({A}, guess={P}, **@V)", "fk")
    )  # fmt: skip
    if m.capabilities.inverse is not None:
        ops += [
            Op("inverse_pose(pose)", "inverse_pose", "pose", pose, lambda v: m.inverse_pose(v),
               "m.inverse_pose(@V)", "ik", verify_inverse(m), pose_kind=kind),
            Op("inverse_pose(pose, strict=False)", "inverse_pose", "pose", pose,
               lambda v: m.inverse_pose(v, strict=False), "m.inverse_pose(@V, strict=False)", "ik",
               verify_inverse(m), pose_kind=kind,
               classes=FLAG_CLASSES + EITHER_CLASSES + ("valid", "batch-2d", "empty", "huge-translation")),
            Op("inverse_pose(**kwargs)", "inverse_pose", "kwargs", None, lambda v: m.inverse_pose(pose, **v),
               f"m.inverse_pose({T}, **@V)", "ik"),
        ]  # fmt: skip
    else:
        ops.append(
            Op("inverse_pose(pose) [no capability]", "inverse_pose", "pose", pose, lambda v: m.inverse_pose(v),
               "m.inverse_pose(@V)", "ik", unsupported=True, pose_kind=kind, classes=("valid",))
        )  # fmt: skip
    if has_modes(m):
        ops += [
            Op("forward_pose_all(actuated)", "forward_pose_all", "actuated", a, lambda v: m.forward_pose_all(v),
               "m.forward_pose_all(@V)", "modes", verify_modes(m), size=n_a),
            Op("forward_pose_all(actuated, strict=False)", "forward_pose_all", "actuated", a,
               lambda v: m.forward_pose_all(v, strict=False), "m.forward_pose_all(@V, strict=False)", "modes",
               verify_modes(m), size=n_a, classes=FLAG_CLASSES + EITHER_CLASSES + ("valid", "batch-2d", "empty")),
            Op("count_modes(actuated)", "count_modes", "actuated", a, lambda v: m.count_modes(v),
               "m.count_modes(@V)", "count", size=n_a),
            Op("forward_pose_all(**kwargs)", "forward_pose_all", "kwargs", None,
               lambda v: m.forward_pose_all(a, **v), f"m.forward_pose_all({A}, **@V)", "modes"),
        ]  # fmt: skip
    else:
        ops.append(
            Op("forward_pose_all(actuated) [no capability]", "forward_pose_all", "actuated", a,
               lambda v: m.forward_pose_all(v), "m.forward_pose_all(@V)", "modes", unsupported=True, size=n_a,
               classes=("valid",))
        )  # fmt: skip
    if has_rates(m):
        ops += [
            Op("inverse_rate(twist)", "inverse_rate", "twist", fx.twist, lambda v: m.inverse_rate(s, v),
               f"m.inverse_rate({S}, @V)", "rates", verify_inverse_rate(m, s), size=m.manifest.twist_size),
            Op("inverse_rate(twist, damping=0.01)", "inverse_rate", "twist", fx.twist,
               lambda v: m.inverse_rate(s, v, damping=0.01), f"m.inverse_rate({S}, @V, damping=0.01)", "rates",
               size=m.manifest.twist_size),
            Op("inverse_rate(state)", "inverse_rate", "state", s, lambda v: m.inverse_rate(v, fx.twist),
               f"m.inverse_rate(@V, {TW})", "rates"),
            Op("inverse_rate(damping=)", "inverse_rate", "damping", None,
               lambda v: m.inverse_rate(s, fx.twist, damping=v), f"m.inverse_rate({S}, {TW}, damping=@V)", "rates"),
            Op("inverse_rate(**kwargs)", "inverse_rate", "kwargs", None, lambda v: m.inverse_rate(s, fx.twist, **v),
               f"m.inverse_rate({S}, {TW}, **@V)", "rates"),
            Op("forward_rate(rates)", "forward_rate", "rates", fx.rates, lambda v: m.forward_rate(s, v),
               f"m.forward_rate({S}, @V)", "array", verify_forward_rate(m, s), size=n_a),
            Op("forward_rate(state)", "forward_rate", "state", s, lambda v: m.forward_rate(v, fx.rates),
               f"m.forward_rate(@V, {R})", "array"),
            Op("forward_rate(**kwargs)", "forward_rate", "kwargs", None, lambda v: m.forward_rate(s, fx.rates, **v),
               f"m.forward_rate({S}, {R}, **@V)", "array"),
            Op("actuator_forces(wrench)", "actuator_forces", "wrench", fx.wrench, lambda v: m.actuator_forces(s, v),
               f"m.actuator_forces({S}, @V)", "array", size=m.manifest.twist_size),
        ]  # fmt: skip
        if n_p:
            ops += [
                Op("passive_rates(rates)", "passive_rates", "rates", fx.rates, lambda v: m.passive_rates(s, v),
                   f"m.passive_rates({S}, @V)", "array", size=n_a),
                Op("passive_rates(state)", "passive_rates", "state", s, lambda v: m.passive_rates(v, fx.rates),
                   f"m.passive_rates(@V, {R})", "array"),
            ]  # fmt: skip
    else:
        ops += [
            Op("inverse_rate(twist) [no capability]", "inverse_rate", "twist", fx.twist,
               lambda v: m.inverse_rate(s, v), f"m.inverse_rate({S}, @V)", "rates", unsupported=True,
               size=m.manifest.twist_size, classes=("valid",)),
            Op("forward_rate(rates) [no capability]", "forward_rate", "rates", fx.rates,
               lambda v: m.forward_rate(s, v), f"m.forward_rate({S}, @V)", "array", unsupported=True, size=n_a,
               classes=("valid",)),
        ]  # fmt: skip
    for capability, method in (("rates", "rate_jacobians"), ("legs", "leg_jacobians")):
        present = getattr(m.capabilities, capability) is not None
        ops.append(
            Op(f"{method}(state)" + ("" if present else " [no capability]"), method, "state", s,
               lambda v, f=method: getattr(m, f)(v), f"m.{method}(@V)", "dict", unsupported=not present,
               classes=None if present else ("valid",))
        )  # fmt: skip
    if n_p:
        ops += [
            Op("tracker(state).solve(actuated)", "tracker.solve", "actuated", a,
               lambda v: copy_result(m.tracker(s).solve(v)), f"m.tracker({S}).solve(@V)", "tracker",
               verify_tracker(m), batched=False, size=n_a),
            Op("tracker(start).solve", "tracker.solve", "state", s, lambda v: copy_result(tracker_of(m, v)),
               "m.tracker(@V).solve(@V.actuated)", "tracker", verify_tracker_start(m)),
            Op("tracker(max_iterations=).solve", "tracker.solve", "max_iterations", None,
               lambda v: copy_result(m.tracker(s, max_iterations=v).solve(fx.moved)),
               f"m.tracker({S}, max_iterations=@V).solve({lit(fx.moved)})", "tracker", verify_tracker(m, fx.moved),
               fixed_batch=()),
            Op("tracker(tolerance=).solve", "tracker.solve", "tolerance", None,
               lambda v: copy_result(m.tracker(s, tolerance=v).solve(fx.moved)),
               f"m.tracker({S}, tolerance=@V).solve({lit(fx.moved)})", "tracker", fixed_batch=()),
        ]  # fmt: skip
    return ops


def copy_result(result):
    """The tracker returns views of its buffers: copies."""
    return tuple(np.array(x) for x in result)


def tracker_of(m, start):
    """A tracker from ``start`` solved at the start's actuated values: one unbatched vector when
    every element of a batched start has the same ones (it must broadcast)."""
    tracker = m.tracker(start)
    actuated = start.actuated if isinstance(start, Configuration) else np.zeros(len(m.actuated_names))
    flat = np.asarray(actuated, dtype=float).reshape(-1, len(m.actuated_names))
    if flat.shape[0] > 1 and (flat == flat[0]).all():
        actuated = flat[0]
    return tracker.solve(actuated)


def load_operations(name: str, backend: str, fx: Fixture) -> list[Op]:
    """``parakin.load`` with fuzzed parameters, parameter groups, limits and backends; a loaded
    mechanism is probed (``probe``)."""
    base = dict(fx.parameters)
    B = f", **{lit(base)}" if base else ""

    def loaded(**kwargs):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
            return Probe(parakin.load(name, backend=backend, **{**base, **kwargs}), fx)

    ops = [
        Op("load(parameter=)", "load", "parameter", None, lambda v: loaded(**v),
           f"parakin.load({name!r}, backend={backend!r}{B}, **@V)", "load"),
        Op("load(**kwargs)", "load", "load-kwargs", None, lambda v: loaded(**v),
           f"parakin.load({name!r}, backend={backend!r}{B}, **@V)", "load"),
        Op("load(backend=)", "load", "backend", None, lambda v: Probe(parakin.load(name, backend=v, **base), fx),
           f"parakin.load({name!r}, backend=@V{B})", "load", backend_free=True),
    ]  # fmt: skip
    if parakin.metadata(name).parameter_groups:
        ops.append(
            Op("load(group=)", "load", "group", None, lambda v: loaded(**v),
               f"parakin.load({name!r}, backend={backend!r}{B}, **@V)", "load")
        )  # fmt: skip
    if parakin.metadata(name).passive:
        ops.append(
            Op("load(limits=)", "load", "limits", None, lambda v: loaded(limits=v),
               f"parakin.load({name!r}, backend={backend!r}{B}, limits=@V)", "load")
        )  # fmt: skip
    return ops


class Probe:
    """A loaded mechanism and what its operations answer for the fixture's inputs: each probe
    is (result kind, result or the exception raised)."""

    def __init__(self, m, fx: Fixture) -> None:
        self.m = m
        self.answers: dict[str, tuple[str, Any]] = {}
        calls = {
            "platform_pose": ("array", lambda: m.platform_pose(fx.state.actuated, fx.state.passive)),
            "loop_closure": ("dict", lambda: m.loop_closure(fx.state.actuated, fx.state.passive)),
            "forward_pose": ("fk", lambda: m.forward_pose(fx.state.actuated, guess=fx.state.passive, strict=False)),
            "singularities": ("dict", lambda: m.singularities(fx.state)),
        }
        if m.capabilities.inverse is not None:
            calls["inverse_pose"] = ("ik", lambda: m.inverse_pose(fx.state.pose, strict=False))
        if has_modes(m):
            calls["forward_pose_all"] = ("modes", lambda: m.forward_pose_all(fx.state.actuated, strict=False))
        for key, (kind, call) in calls.items():
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    self.answers[key] = (kind, call())
            except Exception as error:  # noqa: BLE001 - classified by judge
                self.answers[key] = (kind, error)


def pose_helper_operations() -> list[Op]:
    """The public pose helpers of ``parakin`` (backend-free)."""
    angles = (0.3, -0.2, 0.5)
    values = np.array([0.1, -0.2, 0.7, 0.3, -0.2, 0.5])
    pose = parakin.pose_from_xyz_euler(values)
    return [
        Op("euler_zyx_to_rotation(alpha, beta, gamma)", "euler_zyx_to_rotation", "angles", angles,
           lambda v: parakin.euler_zyx_to_rotation(*v), "parakin.euler_zyx_to_rotation(*@V)", "array",
           verify_rotation, backend_free=True, size=3),
        Op("pose_from_xyz_euler(xyz_euler)", "pose_from_xyz_euler", "vector", values,
           lambda v: parakin.pose_from_xyz_euler(v), "parakin.pose_from_xyz_euler(@V)", "array",
           verify_euler_round_trip, backend_free=True, size=6),
        Op("pose_from_xyz_euler_deg(xyz_euler_deg)", "pose_from_xyz_euler_deg", "vector", values,
           lambda v: parakin.pose_from_xyz_euler_deg(v), "parakin.pose_from_xyz_euler_deg(@V)", "array",
           verify_euler_round_trip, backend_free=True, size=6),
        Op("xyz_euler_from_pose(pose)", "xyz_euler_from_pose", "pose", pose,
           lambda v: parakin.xyz_euler_from_pose(v), "parakin.xyz_euler_from_pose(@V)", "array", backend_free=True),
        Op("xyz_euler_deg_from_pose(pose)", "xyz_euler_deg_from_pose", "pose", pose,
           lambda v: parakin.xyz_euler_deg_from_pose(v), "parakin.xyz_euler_deg_from_pose(@V)", "array",
           backend_free=True),
    ]  # fmt: skip


# ---------------------------------------------------------------------------- input classes
@dataclass
class Variant:
    """One input of class ``cls`` with its expectation: ``value`` and the ``code`` that builds
    it; ``batch`` the result's expected leading batch shape (None: not checked); ``rows`` the
    equivalent single inputs of the batch (flat, None: no batch check); ``bad_rows`` the flat
    batch indices holding a non-finite value (they must be flagged)."""

    cls: str
    expect: str
    value: Any
    code: str
    batch: tuple[int, ...] | None = None
    rows: list[Any] | None = None
    bad_rows: tuple[int, ...] = ()


@dataclass(frozen=True)
class Knobs:
    """What is drawn besides the class: the entry made bad, an extreme magnitude, and the seed of
    the random perturbations (``rng`` is a fresh generator from it, so a replay builds the same
    input)."""

    index: int = 0
    magnitude: float = 1e300
    seed: int = 0

    @property
    def rng(self) -> np.random.Generator:
        return np.random.default_rng(self.seed)


#: classes of array-valued arguments (joint values, twists, rates, wrenches, pose vectors)
OK_CLASSES = (
    "valid", "list", "tuple", "batch-1", "batch-2d", "batch-3d", "empty", "empty-3d", "strided", "fortran",
    "read-only-broadcast", "float32", "int",
)  # fmt: skip
FLAG_CLASSES = ("nan", "inf", "-inf", "nan-in-batch")
EITHER_CLASSES = ("huge", "large", "tiny", "negative-length", "object-floats", "complex-zero-imag")
RAISE_CLASSES = (
    "complex", "string", "numeric-strings", "none", "object-none", "object-nested", "ragged", "dict",
    "scalar-0d", "too-long", "too-short", "trailing-1", "empty-1d",
)  # fmt: skip
ARRAY_CLASSES = OK_CLASSES + FLAG_CLASSES + EITHER_CLASSES + RAISE_CLASSES
POSE_CLASSES = (
    "valid", "list", "batch-2d", "batch-3d", "empty", "empty-3d", "strided", "fortran", "read-only-broadcast",
    "short-form", "nan", "inf", "nan-in-batch", "huge-translation", "near-rigid", "object-floats",
    "complex-zero-imag", "complex", "string", "none", "object-none", "ragged", "dict", "not-rigid", "reflection",
    "bad-last-row", "shape-3x4", "shape-4x3", "shape-16", "scalar-0d", "short-form-wrong-kind",
)  # fmt: skip
STATE_CLASSES = (
    "valid", "lists", "batch", "empty", "read-only-broadcast", "forward-pose-result", "nan-actuated",
    "nan-passive", "inf-passive", "huge-passive", "tuple", "none", "dict", "string", "complex-passive",
    "string-actuated", "passive-too-long", "mismatched-batch", "object-none-passive",
)  # fmt: skip
GUESS_EXTRA = ("guess-pose", "guess-configuration", "guess-none", "guess-batch-single-actuated")
#: degenerate Newton guesses (issue 18 item 11): all zeros, every entry huge (within the accepted
#: magnitudes), the dimensionless components (quaternions) all zero
DEGENERATE_GUESSES = ("guess-zeros", "guess-huge-all", "guess-zero-quaternion")
OPTION_CLASSES = {
    "tolerance": {
        "valid": ("ok", 1e-10), "zero": ("either", 0.0), "tiny": ("either", 1e-300), "inf": ("either", np.inf),
        "smallest-documented": ("either", MIN_TOLERANCE), "largest-documented": ("either", 1.0),
        "below-documented": ("raise", MIN_TOLERANCE / 1000),
        "negative": ("raise", -1.0), "nan": ("raise", np.nan), "string": ("raise", "1e-9"),
        "none": ("raise", None), "complex": ("raise", 1e-9j), "array": ("raise", np.array([1e-9, 1e-9])),
    },
    "max_iterations": {
        "valid": ("ok", 50), "numpy-int": ("ok", np.int64(50)), "zero": ("either", 0),
        "2**32+3": ("either", 2**32 + 3), "2**31": ("either", 2**31), "10**30": ("either", 10**30),
        "bool": ("either", True), "negative": ("raise", -1), "float": ("raise", 1.5), "string": ("raise", "30"),
        "none": ("raise", None), "nan": ("raise", np.nan),
    },
    "max_step": {
        "valid": ("ok", 0.5), "inf": ("either", np.inf), "tiny": ("either", 1e-300), "zero": ("raise", 0.0),
        "negative": ("raise", -1.0), "nan": ("raise", np.nan), "string": ("raise", "0.5"), "none": ("raise", None),
    },
    "damping": {
        "none": ("ok", None), "valid": ("ok", 0.01), "zero": ("either", 0.0), "huge": ("either", 1e300),
        "inf": ("either", np.inf), "negative": ("raise", -1.0), "nan": ("raise", np.nan),
        "string": ("raise", "0.1"), "complex": ("raise", 0.1j), "array": ("raise", np.array([0.1, 0.1])),
    },
    "kwargs": {
        "unknown": ("raise", {"foo": 1}), "misspelt": ("raise", {"dampening": 0.1}),
        "damping-where-none": ("raise", {"damping": 0.1}), "tol": ("raise", {"tol": 1e-9}),
    },
    "backend": {
        "unknown": ("raise", "gpu"), "none": ("raise", None), "int": ("raise", 3), "upper-case": ("raise", "NUMPY"),
        "numpy": ("ok", "numpy"),
    },
}  # fmt: skip
LOAD_CLASSES = (
    "default", "numpy-float", "nan", "inf", "-inf", "zero", "negative", "huge", "tiny", "string",
    "numeric-string", "none", "complex", "array-2", "array-1", "list-1",
)  # fmt: skip
GROUP_CLASSES = ("default", "list", "nan", "inf", "wrong-shape", "string", "complex", "none", "scalar")
LIMIT_CLASSES = (
    "valid", "infinite", "nan", "reversed", "string", "scalar", "triple", "list-of-pairs", "unknown-name", "none",
)  # fmt: skip


def classes_of(op: Op) -> tuple[str, ...]:
    """The input classes of an operation's fuzzed argument."""
    if op.role in ("actuated", "passive", "twist", "rates", "wrench", "vector", "guess"):
        names = ARRAY_CLASSES + (GUESS_EXTRA + DEGENERATE_GUESSES if op.role == "guess" else ())
        if not op.dimensionless:
            names = tuple(c for c in names if c != "guess-zero-quaternion")
        if op.size == 0:  # nothing to make non-finite or too short
            names = tuple(
                c for c in names if c not in FLAG_CLASSES + ("huge", "too-short", "ragged", "empty-1d", "scalar-0d")
            )
    elif op.role == "angles":
        names = ("valid", "list", "batch-2d", "broadcast", "empty", "nan", "inf", "huge", "complex", "string",
                 "none", "object-none", "non-broadcasting", "dict")  # fmt: skip
    elif op.role == "pose":
        names = POSE_CLASSES
    elif op.role == "state":
        names = STATE_CLASSES
    elif op.role in OPTION_CLASSES:
        names = tuple(OPTION_CLASSES[op.role])
    elif op.role == "load-kwargs":
        names = ("unknown-parameter", "limits-none", "limits-empty")
    elif op.role == "parameter":
        names = LOAD_CLASSES
    elif op.role == "group":
        names = GROUP_CLASSES
    elif op.role == "limits":
        names = LIMIT_CLASSES
    else:
        raise AssertionError(op.role)
    if op.classes is not None:
        names = tuple(c for c in names if c in op.classes)
    return names


def _rows(batch: np.ndarray) -> list[np.ndarray]:
    count = int(np.prod(batch.shape[:-1], dtype=np.int64))
    return list(batch.reshape((count,) + batch.shape[-1:]))


def array_variant(op: Op, m, cls: str, k: Knobs) -> Variant:
    """An input of class ``cls`` for an array argument (canonical value ``op.canonical``)."""
    x = np.asarray(op.canonical, dtype=float)
    n = x.size
    rng = k.rng
    scale = 1e-3 * (1.0 + np.abs(x))

    def batch_of(*shape):
        values = x + scale * rng.normal(size=shape + (n,))
        return values

    def bad_entry(value: float):
        y = x.copy()
        y[k.index % n] = value
        return y

    prismatic = _prismatic(op, m)
    if cls == "valid":
        return Variant(cls, "ok", x, lit(x), (), [x])
    if cls == "list":
        return Variant(cls, "ok", x.tolist(), lit(x.tolist()), (), [x])
    if cls == "tuple":
        return Variant(cls, "ok", tuple(x.tolist()), lit(tuple(x.tolist())), (), [x])
    if cls == "float32":
        y = x.astype(np.float32)
        return Variant(cls, "ok", y, f"{lit(x)}.astype(np.float32)", (), [y.astype(float)])
    if cls == "int":  # other values: a named error (unreachable, no convergence) is an answer too
        y = np.round(x).astype(np.int64)
        return Variant(cls, "either", y, lit(y), (), [y.astype(float)])
    if cls in ("batch-1", "batch-2d", "batch-3d", "strided", "fortran", "read-only-broadcast", "empty", "empty-3d"):
        if not op.batched and cls != "batch-1":
            expect = "either"
        else:
            expect = "ok"
        shapes = {"batch-1": (1,), "batch-2d": (5,), "batch-3d": (2, 3), "empty": (0,), "empty-3d": (2, 0)}
        if cls in shapes:
            values = batch_of(*shapes[cls]) if 0 not in shapes[cls] else np.zeros(shapes[cls] + (n,))
            code = lit(values) if values.size else f"np.zeros({values.shape})"
            return Variant(cls, expect, values, code, values.shape[:-1], _rows(values))
        values = batch_of(5)
        if cls == "strided":
            view = np.repeat(values, 2, axis=-1)[:, ::2]
            return Variant(cls, expect, view, f"np.repeat({lit(values)}, 2, axis=-1)[:, ::2]", (5,), _rows(values))
        if cls == "fortran":
            return Variant(cls, expect, np.asfortranarray(values), f"np.asfortranarray({lit(values)})", (5,),
                           _rows(values))  # fmt: skip
        view = np.broadcast_to(x, (3, n))
        return Variant(cls, expect, view, f"np.broadcast_to({lit(x)}, (3, {n}))", (3,), [x, x, x])
    if cls in ("nan", "inf", "-inf"):
        value = {"nan": np.nan, "inf": np.inf, "-inf": -np.inf}[cls]
        y = bad_entry(value)
        return Variant(cls, "flag", y, lit(y), (), [y], (0,))
    if cls == "nan-in-batch":
        values = batch_of(4)
        values[2, k.index % n] = np.nan
        expect = "flag" if op.batched else "either"
        return Variant(cls, expect, values, lit(values), (4,), _rows(values), (2,))
    if cls == "huge":
        y = bad_entry(k.magnitude if rng.random() < 0.5 else -k.magnitude)
        return Variant(cls, "either", y, lit(y), ())
    if cls == "large":
        return Variant(cls, "either", x * 1e6 + 1e6, lit(x * 1e6 + 1e6), ())
    if cls == "tiny":
        return Variant(cls, "either", x * 1e-300, lit(x * 1e-300), ())
    if cls == "negative-length":
        y = np.where(prismatic, -np.abs(x) - 0.1, x) if prismatic.any() else -np.abs(x) - 0.1
        return Variant(cls, "either", y, lit(y), ())
    if cls == "object-floats":
        y = np.array(x.tolist(), dtype=object)
        return Variant(cls, "either", y, lit(y), (), [x])
    if cls == "complex-zero-imag":
        y = x.astype(complex)
        return Variant(cls, "either", y, f"{lit(x)}.astype(complex)", (), [x])
    if cls == "complex":
        y = x + 0.5j
        return Variant(cls, "raise", y, f"{lit(x)} + 0.5j", ())
    if cls == "string":
        return Variant(cls, "raise", "abc", "'abc'")
    if cls == "numeric-strings":
        y = x.astype(str)
        return Variant(cls, "raise", y, f"{lit(x)}.astype(str)")
    if cls == "none":
        if op.role == "guess":  # the documented default: the assembly mode nearest home
            return Variant(cls, "ok", None, "None", ())
        return Variant(cls, "raise", None, "None")
    if cls == "object-none":
        y = np.array([None] * n, dtype=object)
        return Variant(cls, "raise", y, lit(y))
    if cls == "object-nested":
        y = np.empty(n, dtype=object)
        y[...] = [[1.0, 2.0]] * n if n else []
        return Variant(cls, "raise", y, f"np.array([[1.0, 2.0]] * {n} + [None], dtype=object)[:-1]")
    if cls == "ragged":
        value = [x.tolist(), x.tolist()[:-1]]
        return Variant(cls, "raise", value, lit(value))
    if cls == "dict":
        return Variant(cls, "raise", {"x": 1.0}, "{'x': 1.0}")
    if cls == "scalar-0d":
        return Variant(cls, "raise" if n != 1 else "either", float(x[0]), lit(float(x[0])))
    if cls == "too-long":
        y = np.append(x, 0.25)
        return Variant(cls, "raise", y, lit(y))
    if cls == "too-short":
        return Variant(cls, "raise", x[:-1], lit(x[:-1]))
    if cls == "trailing-1":
        return Variant(cls, "raise", x[:, None], f"{lit(x)}[:, None]")
    if cls == "empty-1d":
        return Variant(cls, "raise", np.zeros(0), "np.zeros(0)")
    if cls == "guess-pose":
        if op.size == 0:  # a serial chain takes only an empty guess
            return Variant(cls, "either", fixture(m.name).state.pose, lit(fixture(m.name).state.pose), ())
        return Variant(cls, "ok", fixture(m.name).state.pose, lit(fixture(m.name).state.pose), ())
    if cls == "guess-configuration":
        state = fixture(m.name).state
        return Variant(cls, "ok", state, lit(state), ())
    if cls == "guess-none":
        return Variant(cls, "ok", None, "None", ())
    if cls == "guess-zeros":
        return Variant(cls, "either", np.zeros(n), f"np.zeros({n})", ())
    if cls == "guess-huge-all":
        y = 1e6 * h.variable_scale(m, m.manifest.passive) if n else np.zeros(0)
        return Variant(cls, "either", y, lit(y), ())
    if cls == "guess-zero-quaternion":
        y = x.copy()
        y[list(op.dimensionless)] = 0.0
        return Variant(cls, "either", y, lit(y), ())
    if cls == "guess-batch-single-actuated":
        values = batch_of(5)
        return Variant(cls, "ok", values, lit(values), (5,))
    raise AssertionError(cls)


def _prismatic(op: Op, m) -> np.ndarray:
    if m is None:
        return np.zeros(op.size, dtype=bool)
    variables = {"actuated": m.manifest.actuated, "passive": m.manifest.passive, "guess": m.manifest.passive}
    if op.role in variables and len(variables[op.role]) == op.size:
        return np.array([not v.revolute for v in variables[op.role]], dtype=bool)
    return np.zeros(op.size, dtype=bool)


def pose_variant(op: Op, m, cls: str, k: Knobs) -> Variant:
    T = np.asarray(op.canonical, dtype=float)
    rng = k.rng
    kind = op.pose_kind

    def near(count: int) -> np.ndarray:
        if m is None:
            values = np.tile([0.1, -0.2, 0.7, 0.3, -0.2, 0.5], (count, 1)) + 0.01 * rng.normal(size=(count, 6))
            return parakin.pose_from_xyz_euler(values)
        return np.stack([h.perturb_pose(m, T, rng, 0.01) for _ in range(count)])

    if cls == "valid":
        return Variant(cls, "ok", T, lit(T), (), [T])
    if cls == "list":
        return Variant(cls, "ok", T.tolist(), lit(T.tolist()), (), [T])
    if cls in ("batch-2d", "batch-3d", "empty", "empty-3d"):
        shape = {"batch-2d": (5,), "batch-3d": (2, 3), "empty": (0,), "empty-3d": (2, 0)}[cls]
        count = int(np.prod(shape))
        values = near(count).reshape(shape + (4, 4)) if count else np.zeros(shape + (4, 4))
        return Variant(cls, "ok", values, lit(values), shape, list(values.reshape(-1, 4, 4)))
    if cls in ("strided", "fortran", "read-only-broadcast"):
        values = near(5)
        if cls == "strided":
            view = np.repeat(values, 2, axis=-1)[..., ::2]
            return Variant(cls, "ok", view, f"np.repeat({lit(values)}, 2, axis=-1)[..., ::2]", (5,), list(values))
        if cls == "fortran":
            return Variant(cls, "ok", np.asfortranarray(values), f"np.asfortranarray({lit(values)})", (5,),
                           list(values))  # fmt: skip
        return Variant(cls, "ok", np.broadcast_to(T, (3, 4, 4)), f"np.broadcast_to({lit(T)}, (3, 4, 4))", (3,),
                       [T, T, T])  # fmt: skip
    if cls == "short-form":
        if kind == "rotation":
            short = T[:3, :3]
        elif kind == "planar":
            short = np.array([T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])])
        elif kind == "translation":
            short = T[:3, 3]
        else:
            short = T[:3, :3]  # a transform has no short form: (3, 3) must be rejected
            return Variant(cls, "raise", short, lit(short))
        return Variant(cls, "ok", short, lit(short), (), [T])
    if cls == "short-form-wrong-kind":
        # the short form of another pose kind: (3,) for a transform / rotation, (3, 3) otherwise
        short = T[:3, 3].copy() if kind in ("transform", "rotation") else T[:3, :3].copy()
        return Variant(cls, "raise", short, lit(short))
    if cls in ("nan", "inf"):
        y = T.copy()
        y[(k.index % 3), (k.index // 3) % 4] = np.nan if cls == "nan" else np.inf
        return Variant(cls, "flag", y, lit(y), (), [y], (0,))
    if cls == "nan-in-batch":
        values = near(4)
        values[2, 0, 3] = np.nan
        return Variant(cls, "flag", values, lit(values), (4,), list(values), (2,))
    if cls == "huge-translation":
        y = T.copy()
        y[:3, 3] = k.magnitude
        return Variant(cls, "either", y, lit(y), ())
    if cls == "near-rigid":
        y = T.copy()
        y[:3, :3] *= 1 + 1e-8
        return Variant(cls, "either", y, lit(y), ())
    if cls == "object-floats":
        y = np.array(T.tolist(), dtype=object)
        return Variant(cls, "either", y, lit(y), (), [T])
    if cls == "complex-zero-imag":
        return Variant(cls, "either", T.astype(complex), f"{lit(T)}.astype(complex)", (), [T])
    if cls == "complex":
        return Variant(cls, "raise", T + 0.5j, f"{lit(T)} + 0.5j")
    if cls == "string":
        return Variant(cls, "raise", "eye", "'eye'")
    if cls == "none":
        return Variant(cls, "raise", None, "None")
    if cls == "object-none":
        y = np.full((4, 4), None, dtype=object)
        return Variant(cls, "raise", y, lit(y))
    if cls == "ragged":
        value = [row.tolist() for row in T[:3]] + [[0.0, 0.0, 1.0]]
        return Variant(cls, "raise", value, lit(value))
    if cls == "dict":
        return Variant(cls, "raise", {"R": np.eye(3).tolist()}, "{'R': np.eye(3).tolist()}")
    if cls == "not-rigid":
        y = T.copy()
        y[:3, :3] *= 2.0
        return Variant(cls, "raise", y, lit(y))
    if cls == "reflection":
        y = T.copy()
        y[:3, 2] *= -1.0
        return Variant(cls, "raise", y, lit(y))
    if cls == "bad-last-row":
        y = T.copy()
        y[3, 0] = 1.0
        return Variant(cls, "raise", y, lit(y))
    if cls == "shape-3x4":
        return Variant(cls, "raise", T[:3], lit(T[:3]))
    if cls == "shape-4x3":
        return Variant(cls, "raise", T[:, :3], lit(T[:, :3]))
    if cls == "shape-16":
        return Variant(cls, "raise", T.ravel(), lit(T.ravel()))
    if cls == "scalar-0d":
        return Variant(cls, "raise", 1.0, "1.0")
    raise AssertionError(cls)


def state_variant(op: Op, m, cls: str, k: Knobs) -> Variant:
    fx = fixture(m.name)
    s, many = fx.state, fx.states
    a, p, T = s.actuated, s.passive, s.pose

    def config(actuated, passive, pose=T) -> Configuration:
        return Configuration(actuated, passive, pose)

    def lit3(actuated, passive, pose=T) -> str:
        return f"Configuration({lit(actuated)}, {lit(passive)}, {lit(pose)})"

    if cls == "valid":
        return Variant(cls, "ok", s, lit(s), (), [s])
    if cls == "lists":
        c = config(a.tolist(), p.tolist(), T.tolist())
        return Variant(cls, "ok", c, lit3(a.tolist(), p.tolist(), T.tolist()), (), [s])
    if cls == "batch":
        rows = [config(many.actuated[i], many.passive[i], many.pose[i]) for i in range(5)]
        return Variant(cls, "ok", many, lit(many), (5,), rows)
    if cls == "empty":
        c = config(np.zeros((0, a.size)), np.zeros((0, p.size)), np.zeros((0, 4, 4)))
        return Variant(cls, "ok", c, lit(c), (0,), [])
    if cls == "read-only-broadcast":
        c = config(np.broadcast_to(a, (3, a.size)), np.broadcast_to(p, (3, p.size)), np.broadcast_to(T, (3, 4, 4)))
        code = f"Configuration(np.broadcast_to({lit(a)}, (3, {a.size})), np.broadcast_to({lit(p)}, (3, {p.size})), np.broadcast_to({lit(T)}, (3, 4, 4)))"
        return Variant(cls, "ok", c, code, (3,), [s, s, s])
    if cls == "forward-pose-result":
        m_numpy = h.load(m.name, "numpy")
        result = m_numpy.forward_pose(a, guess=p if p.size else None, strict=False)
        c = Configuration(result.actuated, result.passive, result.pose)
        return Variant(cls, "ok", result, f"m.forward_pose({lit(a)}, guess={lit(p)}, strict=False)", (), [c])
    if cls == "nan-actuated":
        y = a.copy()
        y[k.index % a.size] = np.nan
        return Variant(cls, "flag", config(y, p), lit3(y, p), (), None, (0,))
    if cls in ("nan-passive", "inf-passive"):
        if not p.size:
            y = a.copy()
            y[k.index % a.size] = np.inf
            return Variant(cls, "flag", config(y, p), lit3(y, p), (), None, (0,))
        y = p.copy()
        y[k.index % p.size] = np.nan if cls == "nan-passive" else np.inf
        return Variant(cls, "flag", config(a, y), lit3(a, y), (), None, (0,))
    if cls == "huge-passive":
        y = (p if p.size else a) + k.magnitude
        c = config(a, y) if p.size else config(y, p)
        return Variant(cls, "either", c, lit(c), ())
    if cls == "tuple":
        return Variant(cls, "raise", (a, p, T), f"({lit(a)}, {lit(p)}, {lit(T)})")
    if cls == "none":
        return Variant(cls, "raise", None, "None")
    if cls == "dict":
        value = {"actuated": a, "passive": p, "pose": T}
        return Variant(cls, "raise", value, lit(value))
    if cls == "string":
        return Variant(cls, "raise", "home", "'home'")
    if cls == "complex-passive":
        target = p if p.size else a
        y = target + 0.5j
        c = config(a, y) if p.size else config(y, p)
        if p.size:
            code = f"Configuration({lit(a)}, {lit(p)} + 0.5j, {lit(T)})"
        else:
            code = f"Configuration({lit(a)} + 0.5j, {lit(p)}, {lit(T)})"
        return Variant(cls, "raise", c, code)
    if cls == "string-actuated":
        return Variant(cls, "raise", config("abc", p), f"Configuration('abc', {lit(p)}, {lit(T)})")
    if cls == "passive-too-long":
        y = np.append(p, 0.25)
        return Variant(cls, "raise", config(a, y), lit3(a, y))
    if cls == "mismatched-batch":
        c = config(np.tile(a, (5, 1)), np.tile(p, (4, 1)), np.tile(T, (5, 1, 1)))
        code = f"Configuration(np.tile({lit(a)}, (5, 1)), np.tile({lit(p)}, (4, 1)), np.tile({lit(T)}, (5, 1, 1)))"
        return Variant(cls, "raise", c, code)
    if cls == "object-none-passive":
        y = np.array([None] * max(p.size, 1), dtype=object)
        return Variant(cls, "raise", config(a, y), lit3(a, y))
    raise AssertionError(cls)


def angles_variant(op: Op, cls: str, k: Knobs) -> Variant:
    angles = op.canonical
    if cls == "valid":
        return Variant(cls, "ok", angles, lit(angles), (), [angles])
    if cls == "list":
        value = tuple([v] for v in angles)
        rows = [angles]
        return Variant(cls, "ok", value, lit(value), (1,), rows)
    if cls == "batch-2d":
        values = np.array(angles) + 0.1 * k.rng.normal(size=(5, 3))
        value = tuple(values.T)
        return Variant(cls, "ok", value, f"{lit(values)}.T", (5,), [tuple(r) for r in values])
    if cls == "broadcast":
        values = np.array(angles)[None] + 0.1 * k.rng.normal(size=(4, 3))
        value = (values[:, 0], angles[1], angles[2])
        return Variant(cls, "ok", value, lit(value), (4,), [(r, angles[1], angles[2]) for r in values[:, 0]])
    if cls == "empty":
        value = (np.zeros(0), np.zeros(0), np.zeros(0))
        return Variant(cls, "ok", value, lit(value), (0,), [])
    if cls in ("nan", "inf"):
        value = list(angles)
        value[k.index % 3] = np.nan if cls == "nan" else np.inf
        return Variant(cls, "flag", tuple(value), lit(tuple(value)), (), None, (0,))
    if cls == "huge":
        value = (k.magnitude, angles[1], angles[2])
        return Variant(cls, "either", value, lit(value), ())
    if cls == "complex":
        value = (angles[0] + 0.5j, angles[1], angles[2])
        return Variant(cls, "raise", value, lit(value))
    if cls == "string":
        value = ("abc", angles[1], angles[2])
        return Variant(cls, "raise", value, lit(value))
    if cls == "none":
        value = (None, angles[1], angles[2])
        return Variant(cls, "raise", value, lit(value))
    if cls == "object-none":
        value = (np.array([None], dtype=object), angles[1], angles[2])
        return Variant(cls, "raise", value, lit(value))
    if cls == "non-broadcasting":
        value = (np.zeros(2), np.zeros(3), 0.0)
        return Variant(cls, "raise", value, lit(value))
    if cls == "dict":
        return Variant(cls, "raise", ({"a": 1.0}, angles[1], angles[2]), lit(({"a": 1.0}, angles[1], angles[2])))
    raise AssertionError(cls)


def load_variant(op: Op, name: str, cls: str, k: Knobs) -> Variant:
    info = parakin.metadata(name)
    if op.role == "parameter":
        parameter = info.parameters[k.index % len(info.parameters)]
        default = dict(h.usable_parameters(name)).get(parameter.name, parameter.default)
        values = {
            "default": ("ok", default), "numpy-float": ("ok", np.float64(default)), "nan": ("raise", np.nan),
            "inf": ("raise", np.inf), "-inf": ("raise", -np.inf), "zero": ("either", 0.0),
            "negative": ("either", -abs(default) - 0.1), "huge": ("either", k.magnitude), "tiny": ("either", 1e-300),
            "string": ("raise", "abc"), "numeric-string": ("raise", str(default)), "none": ("raise", None),
            "complex": ("raise", complex(default, 1.0)), "array-2": ("raise", np.array([default, default])),
            "array-1": ("raise", np.array([default])), "list-1": ("raise", [default]),
        }  # fmt: skip
        expect, value = values[cls]
        return Variant(cls, expect, {parameter.name: value}, lit({parameter.name: value}))
    if op.role == "group":
        group = info.parameter_groups[k.index % len(info.parameter_groups)]
        defaults = {**info.parameter_defaults, **dict(h.usable_parameters(name))}
        array = np.array([defaults[s] for s in group.symbols], dtype=float).reshape(group.shape)
        bad = array.copy()
        bad.flat[k.index % bad.size] = np.nan if cls == "nan" else np.inf
        values = {
            "default": ("ok", array), "list": ("ok", array.tolist()), "nan": ("raise", bad), "inf": ("raise", bad),
            "wrong-shape": ("raise", array.ravel()[:-1]), "string": ("raise", "abc"),
            "complex": ("raise", array + 0.5j), "none": ("raise", None), "scalar": ("raise", 1.0),
        }  # fmt: skip
        expect, value = values[cls]
        shown = f"{lit(array)} + 0.5j" if cls == "complex" else lit(value)
        return Variant(cls, expect, {group.name: value}, "{" + repr(group.name) + ": " + shown + "}")
    if op.role == "limits":
        variable = info.passive[k.index % len(info.passive)]
        home = variable.home or 0.0
        values = {
            "valid": ("ok", {variable.name: (home - 10.0, home + 10.0)}),
            "infinite": ("ok", {variable.name: (-np.inf, np.inf)}),
            "nan": ("raise", {variable.name: (np.nan, home + 1.0)}),
            "reversed": ("raise", {variable.name: (home + 1.0, home - 1.0)}),
            "string": ("raise", {variable.name: "ab"}),
            "scalar": ("raise", {variable.name: 5.0}),
            "triple": ("raise", {variable.name: (0.0, 1.0, 2.0)}),
            "list-of-pairs": ("raise", [(variable.name, (home - 1.0, home + 1.0))]),
            "unknown-name": ("raise", {"no_such_joint": (0.0, 1.0)}),
            "none": ("ok", None),
        }
        expect, value = values[cls]
        return Variant(cls, expect, value, lit(value))
    if op.role == "load-kwargs":
        values = {
            "unknown-parameter": ("raise", {"no_such_parameter": 1.0}),
            "limits-none": ("ok", {"limits": None}),
            "limits-empty": ("ok", {"limits": {}}),
        }
        expect, value = values[cls]
        return Variant(cls, expect, value, lit(value))
    raise AssertionError(op.role)


def make_variant(op: Op, m, cls: str, k: Knobs, name: str | None = None) -> Variant:
    """An input of class ``cls`` for ``op`` (``m``: the mechanism whose fixture it uses)."""
    if op.unsupported:
        variant = (pose_variant if op.role == "pose" else state_variant if op.role == "state" else array_variant)(
            op, m, cls, k
        )
        return dataclasses.replace(variant, expect="raise", rows=None, batch=None)
    if op.role in ("actuated", "passive", "twist", "rates", "wrench", "vector", "guess"):
        return array_variant(op, m, cls, k)
    if op.role == "pose":
        return pose_variant(op, m, cls, k)
    if op.role == "state":
        return state_variant(op, m, cls, k)
    if op.role == "angles":
        return angles_variant(op, cls, k)
    if op.role in OPTION_CLASSES:
        expect, value = OPTION_CLASSES[op.role][cls]
        if op.role == "kwargs" and cls == "damping-where-none":
            expect = "raise" if op.method != "inverse_rate" else "ok"
        return Variant(cls, expect, value, lit(value), ())
    return load_variant(op, name or (m.name if m is not None else ""), cls, k)


# ---------------------------------------------------------------------------- judging answers
IGNORED_FIELDS = {
    "branches",
    "branch_names",
    "outcomes",
    "branch_count",
    "method",
    "root_count",
    "root_count_proven",
    "pose_kind",
}
#: fields left out of the backend comparison (diagnostics that legitimately differ)
NOT_COMPARED = {"iterations", "conditioning", "outcome", "root_kind", "root", "real", "near_roots", "at_infinity",
                "real_roots", "status", "input_independent", "min_conditioning", "path_certified", "retracked"}  # fmt: skip


def parts(result: Any) -> dict[str, np.ndarray]:
    """The arrays of a result by name (dataclass fields, dict items, tuple items, an array)."""
    if dataclasses.is_dataclass(result) and not isinstance(result, type):
        out: dict[str, np.ndarray] = {}
        for f in dataclasses.fields(result):
            if f.name in IGNORED_FIELDS:
                continue
            value = getattr(result, f.name)
            if value is None:  # a field this kind of result does not have (e.g. an elimination's certificate)
                continue
            if isinstance(value, dict):
                out.update({f"{f.name}.{key}": np.asarray(v) for key, v in value.items()})
            else:
                out[f.name] = np.asarray(value)
        return out
    if isinstance(result, dict):
        return {str(key): np.asarray(value) for key, value in result.items()}
    if isinstance(result, tuple):
        return {str(i): np.asarray(value) for i, value in enumerate(result)}
    return {"value": np.asarray(result)}


def entry_masks(result: Any) -> dict[str, np.ndarray]:
    """Per field, where its entries are documented as meaningless (invalid branches / modes)."""
    if isinstance(result, parakin.InversePose):
        invalid = ~np.asarray(result.valid)
        return {"actuated": invalid, "passive": invalid}
    if isinstance(result, parakin.AssemblyModes):
        invalid = ~np.asarray(result.valid)
        masks = {key: invalid for key in ("poses", "passive", "residual", "root", "conditioning")}
        masks["root"] = invalid | (np.asarray(result.root_kind) < 0)  # root_kind -1: no root (a serial chain)
        return masks
    return {}


def row_flags(kind: str, result: Any) -> np.ndarray | None:
    """Per batch element: whether the result flags it (not converged, no valid branch or mode,
    not within limits); None for results without flags."""
    if kind == "fk":
        return ~np.asarray(result.converged)
    if kind == "ik":
        return ~np.asarray(result.valid).any(-1)
    if kind == "modes":
        return ~np.asarray(result.valid).any(-1)
    if kind == "count":
        return np.asarray(result["count"]) == 0
    if kind == "mask":
        return ~np.asarray(result)
    return None


def result_batch(kind: str, result: Any) -> tuple[int, ...] | None:
    """The leading batch shape of a result, read from a field that has one."""
    if kind == "fk":
        return np.shape(result.converged)
    if kind in ("ik", "modes"):
        return np.shape(result.valid)[:-1]
    if kind == "count":
        return np.shape(result["count"])
    if kind == "mask":
        return np.shape(result)
    return None


def _flat(array: np.ndarray, batch: tuple[int, ...]) -> np.ndarray:
    count = int(np.prod(batch, dtype=np.int64))
    return array.reshape((count,) + array.shape[len(batch) :])


def hidden_non_finite(kind: str, result: Any, batch: tuple[int, ...] | None) -> str | None:
    """The first field with a non-finite value where the result does not flag it invalid."""
    masks = entry_masks(result)
    flags = row_flags(kind, result)
    for name, array in parts(result).items():
        if array.dtype.kind not in "fc" or array.size == 0:
            continue
        bad = ~np.isfinite(array)
        if name in masks:
            mask = masks[name]
            bad = bad & ~mask.reshape(mask.shape + (1,) * (bad.ndim - mask.ndim))
        if flags is not None and batch is not None and bad.shape[: len(batch)] == tuple(batch):
            rows = _flat(bad, batch)
            rows = rows & ~_flat(np.asarray(flags), batch).reshape((-1,) + (1,) * (rows.ndim - 1))
            bad = rows
        if bad.any():
            return name
    return None


def canonical_parts(kind: str, result: Any, compare_all: bool = True) -> dict[str, np.ndarray]:
    """Float arrays of a result with its meaningless entries zeroed (invalid branches, invalid
    modes, Newton solves that did not converge): what two equal answers share."""
    masks = entry_masks(result)
    out = {}
    for name, array in parts(result).items():
        if not compare_all and name in NOT_COMPARED:
            continue
        value = np.array(array, dtype=float) if array.dtype.kind in "biuf" else None
        if value is None:
            continue
        if name in masks:
            mask = masks[name]
            value = np.where(mask.reshape(mask.shape + (1,) * (value.ndim - mask.ndim)), 0.0, value)
        if kind == "fk" and name not in ("converged", "actuated"):
            failed = ~np.asarray(result.converged)
            value = np.where(failed.reshape(failed.shape + (1,) * (value.ndim - failed.ndim)), 0.0, value)
        out[name] = value
    return out


def differ(a: dict[str, np.ndarray], b: dict[str, np.ndarray], tolerance: float) -> str | None:
    """None when two canonical results agree (same fields, shapes, NaN pattern, values to
    ``tolerance`` relative to each field's size), else which field differs and how."""
    if set(a) != set(b):
        return f"fields {sorted(set(a) ^ set(b))}"
    for name in a:
        x, y = a[name], b[name]
        if x.shape != y.shape:
            return f"{name}: shape {x.shape} vs {y.shape}"
        if not (np.isnan(x) == np.isnan(y)).all():
            return f"{name}: NaN pattern"
        finite = np.isfinite(x) & np.isfinite(y)
        if not (np.isinf(x) == np.isinf(y)).all() or not (x[~finite & ~np.isnan(x)] == y[~finite & ~np.isnan(y)]).all():
            return f"{name}: inf pattern"
        scale = 1.0 + np.abs(y[finite]).max(initial=0.0)
        error = np.abs(x[finite] - y[finite]).max(initial=0.0)
        if error > tolerance * scale:
            return f"{name}: differs by {error:.3g} (scale {scale:.3g})"
    return None


@dataclass
class Answer:
    """What a call gave: a result, or an exception."""

    result: Any = None
    error: BaseException | None = None

    @property
    def signature(self) -> str:
        return "result" if self.error is None else type(self.error).__name__


def answer(call: Callable[[], Any]) -> Answer:
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            return Answer(result=call())
    except Exception as error:  # noqa: BLE001 - every exception is classified
        return Answer(error=error)


@dataclass
class Verdict:
    category: str  # one of GOOD + BAD
    detail: str  # exception type and message head, or what is wrong with the result

    @property
    def good(self) -> bool:
        return self.category in GOOD


def judge_error(expect: str, error: BaseException) -> Verdict:
    head = f"{type(error).__name__}: {str(error).splitlines()[0][:160] if str(error) else ''}"
    if isinstance(error, ParakinError):
        return Verdict("named!" if expect == "ok" else "named", head)
    return Verdict("other", head)


def judge(op: Op, variant: Variant, got: Answer, single: Callable[[Any], Answer] | None = None) -> Verdict:
    """Whether an answer keeps the contract for this input (``single`` answers the batch's rows
    one by one, for the batch == single calls check)."""
    if got.error is not None:
        batched = variant.batch is not None and variant.batch != ()
        if batched and variant.rows and variant.expect == "ok" and isinstance(got.error, ParakinError) and single:
            # a batch may fail like one of its elements does
            if any(isinstance(single(row).error, ParakinError) for row in variant.rows[:6]):
                return Verdict("named", judge_error("either", got.error).detail)
        return judge_error(variant.expect, got.error)
    result = got.result
    if op.kind == "load":
        return judge_probe(variant, result)
    if variant.expect == "raise":
        return Verdict("accepted", f"returned {describe(result)}")
    batch = variant.batch
    if op.fixed_batch is not None:
        batch = op.fixed_batch
    if batch is not None:
        for name, array in parts(result).items():
            if array.shape[: len(batch)] != tuple(batch):
                return Verdict("wrong", f"field {name} has shape {array.shape}, batch {batch} expected")
    flags = row_flags(op.kind, result)
    if variant.expect == "flag":
        if flags is None:
            hidden = hidden_non_finite(op.kind, result, batch)
            if hidden:
                return Verdict("nan", f"non-finite {hidden} returned for a non-finite input")
            return Verdict("accepted", f"a non-finite input answered with finite {describe(result)}")
        flat = np.asarray(flags).reshape(-1)
        if batch is not None and flat.size == int(np.prod(batch, dtype=np.int64)):
            unflagged = [r for r in variant.bad_rows if not flat[r]]
            if unflagged:
                return Verdict("accepted", f"non-finite input at batch row {unflagged[0]} not flagged invalid")
    hidden = hidden_non_finite(op.kind, result, batch)
    if hidden:
        return Verdict("nan", f"unflagged non-finite values in {hidden}")
    if variant.rows is not None and single is not None and batch is not None:
        mismatch = compare_rows(op, variant, result, batch, single, flags)
        if mismatch:
            return Verdict("wrong", mismatch)
    if op.verify is not None:
        try:
            with warnings.catch_warnings(), np.errstate(all="ignore"):
                warnings.simplefilter("ignore")
                problem = op.verify(variant.value, result)
        except Exception as error:  # noqa: BLE001 - a result the checks cannot read is wrong
            problem = f"checking the result raised {type(error).__name__}: {error}"
        if problem:
            return Verdict("wrong", problem)
    return Verdict("ok", f"returned {describe(result)}")


def compare_rows(op: Op, variant: Variant, result: Any, batch, single, flags) -> str | None:
    """A batch result against the single calls of its elements."""
    count = int(np.prod(batch, dtype=np.int64))
    rows = variant.rows
    if rows is None or len(rows) != count:
        return None
    ours = canonical_parts(op.kind, result)
    for index, row in enumerate(rows[:6]):
        if index in variant.bad_rows:
            continue
        reference = single(row)
        if reference.error is not None:
            if variant.expect == "ok":
                return f"batch row {index}: the single call raises {type(reference.error).__name__}"
            continue
        theirs = canonical_parts(op.kind, reference.result)
        mine = {key: _flat(value, batch)[index] for key, value in ours.items()}
        theirs = {key: value for key, value in theirs.items() if key in mine}
        problem = differ(mine, theirs, BATCH_AGREEMENT)
        if problem:
            return f"batch row {index} differs from its single call: {problem}"
    return None


def judge_probe(variant: Variant, probe: Probe) -> Verdict:
    """A loaded mechanism: every probe answers a finite result or a named error."""
    if variant.expect == "raise":
        return Verdict("accepted", "parakin.load returned a mechanism")
    for key, (kind, got) in probe.answers.items():
        if isinstance(got, BaseException):
            if not isinstance(got, ParakinError):
                return Verdict("other", f"{key} of the loaded mechanism: {judge_error('either', got).detail}")
            continue
        hidden = hidden_non_finite(kind, got, result_batch(kind, got) or ())
        if hidden:
            return Verdict("nan", f"{key} of the loaded mechanism returned non-finite {hidden}")
    return Verdict("ok", "loaded; probes answered")


def describe(result: Any) -> str:
    if isinstance(result, Probe):
        return "a mechanism"
    if isinstance(result, np.ndarray):
        return f"an array {result.shape}"
    return type(result).__name__


def agreement(op: Op, answers: dict[str, Answer]) -> str | None:
    """None when every backend gives the same exception class, or results equal to 1e-8."""
    signatures = {backend: got.signature for backend, got in answers.items()}
    if len(set(signatures.values())) > 1:
        return ", ".join(f"{backend}: {s}" for backend, s in signatures.items())
    if next(iter(signatures.values())) != "result" or op.kind == "load":
        return None
    canonical = {backend: canonical_parts(op.kind, got.result, compare_all=False) for backend, got in answers.items()}
    backends = list(canonical)
    for other in backends[1:]:
        problem = differ(canonical[other], canonical[backends[0]], BACKEND_AGREEMENT)
        if problem:
            return f"{other} vs {backends[0]}: {problem}"
    return None


def reproducer(name: str | None, backend: str | None, op: Op, variant: Variant) -> str:
    """A short script that shows the answer."""
    lines = ["import numpy as np", "import parakin", "from parakin import Configuration"]
    if name is not None and op.kind != "load" and not op.backend_free:
        parameters = dict(h.usable_parameters(name))
        extra = f", **{lit(parameters)}" if parameters else ""
        lines.append(f"m = parakin.load({name!r}, backend={backend!r}{extra})")
    if op.label == "tracker(start).solve":
        lines.append(f"start = {variant.code}")
        code = "m.tracker(start).solve(start.actuated)"
        if variant.cls == "read-only-broadcast":
            code = "m.tracker(start).solve(start.actuated[0])"
    else:
        code = op.code.replace("@V", variant.code)
    lines.append(f"print({code})")
    return "\n".join(lines)


def run_case(name: str | None, backend: str, op: Op, variant: Variant) -> tuple[Answer, Verdict]:
    """Call ``op`` with ``variant`` and judge the answer."""
    got = answer(lambda: op.call(variant.value))
    verdict = judge(op, variant, got, single=lambda row: answer(lambda: op.call(row)))
    return got, verdict


def report(name, backend, op: Op, variant: Variant, verdict: Verdict) -> str:
    return (
        f"{op.label} on {name}/{backend}, input class {variant.cls!r} (expect {variant.expect}): "
        f"{verdict.category} ({CATEGORY_HELP[verdict.category]}): {verdict.detail}\n"
        f"reproducer:\n{reproducer(name, backend, op, variant)}"
    )


# ---------------------------------------------------------------------------- hypothesis tests
@functools.cache
def ops_of(name: str, backend: str) -> list[Op]:
    return operations(mechanism(name, backend), fixture(name))


def op_named(name: str, backend: str, label: str) -> Op:
    return {op.label: op for op in ops_of(name, backend)}[label]


@functools.cache
def cases_of(name: str, expectations: tuple[str, ...], roles: tuple[str, ...]) -> dict[str, tuple[str, ...]]:
    """Per operation label: its input classes whose expectation is one of ``expectations``
    (read on the NumPy backend; every backend has the same operations)."""
    m = mechanism(name, "numpy")
    cases: dict[str, tuple[str, ...]] = {}
    for op in ops_of(name, "numpy"):
        if op.role not in roles:
            continue
        classes = tuple(c for c in classes_of(op) if make_variant(op, m, c, Knobs()).expect in expectations)
        if classes:
            cases[op.label] = classes
    return cases


knobs_strategy = st.builds(
    Knobs, index=st.integers(0, 11), magnitude=st.floats(1e10, 1e308), seed=st.integers(0, 2**16)
)


def contract_property(name: str, expectations: tuple[str, ...], roles: tuple[str, ...], examples: int, minimum: int):
    """Check the contract on inputs of ``expectations`` for every operation of ``name`` whose fuzzed
    argument has one of ``roles``: one explicit example per operation (backends in turn, so every
    operation is checked at least once whatever hypothesis draws), then ``examples`` drawn ones
    (operation, class, backend, knobs); at least ``minimum`` more than the explicit ones run."""
    cases = cases_of(name, expectations, roles)
    if not cases:
        pytest.skip(f"{name}: no operation takes such inputs")
    labels = sorted(cases)
    checked = []

    @fuzz_settings(examples)
    @given(
        label=st.sampled_from(labels),
        pick=st.integers(0, 1000),
        backend=st.sampled_from(BACKENDS),
        k=knobs_strategy,
    )
    def property_holds(label, pick, backend, k):
        classes = cases[label]
        cls = classes[pick % len(classes)]
        op = op_named(name, backend, label)
        variant = make_variant(op, mechanism(name, backend), cls, k)
        _, verdict = run_case(name, backend, op, variant)
        assert verdict.good, report(name, backend, op, variant, verdict)
        checked.append(label)

    for i, label in enumerate(labels):
        property_holds = example(label=label, pick=i, backend=BACKENDS[i % len(BACKENDS)], k=Knobs(i))(property_holds)
    property_holds()
    assert len(checked) >= len(labels) + minimum * SCALE, f"only {len(checked)} examples checked"


@pytest.fixture(scope="module", autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        yield


ARRAY_ROLES = ("actuated", "passive", "twist", "rates", "wrench", "guess", "pose", "state")
OPTION_ROLES = ("tolerance", "max_iterations", "max_step", "damping")


@pytest.mark.parametrize("name", NAMES)
def test_malformed_inputs_raise_named_errors(name):
    """Complex values, strings, None, object arrays, ragged lists, dicts, wrong last axes, 0-d
    values, states that are not Configurations, poses that are not rigid: a ParakinError, on
    every operation and backend."""
    contract_property(name, ("raise",), ARRAY_ROLES, 60, 40)


@pytest.mark.parametrize("name", NAMES)
def test_non_finite_inputs_raise_or_are_flagged(name):
    """NaN / inf entries (single inputs and one bad element of a batch): a ParakinError, or a
    result that flags that element invalid (results without flags must raise)."""
    contract_property(name, ("flag",), ARRAY_ROLES, 40, 25)


@pytest.mark.parametrize("name", NAMES)
def test_extreme_values_give_finite_results_or_named_errors(name):
    """Huge, tiny and negative-length values, object arrays of floats, complex arrays with a zero
    imaginary part, integer values: a ParakinError or a finite, correct result."""
    contract_property(name, ("either",), ARRAY_ROLES, 40, 25)


@pytest.mark.parametrize("name", NAMES)
def test_valid_inputs_of_every_layout_give_results_equal_to_single_calls(name):
    """Lists, tuples, 1-d / 2-d / 3-d batches, empty batches (0, n) and (2, 0, n), strided,
    Fortran-ordered and read-only arrays, float32 values, one unbatched guess / state / twist
    against a batch: a result of the batch shape equal to the single calls (empty batches give
    empty results, never an error), finite and correct."""
    contract_property(name, ("ok",), ARRAY_ROLES, 40, 25)


@pytest.mark.parametrize("name", NAMES)
def test_solver_options_are_validated(name):
    """tolerance, max_iterations, max_step (forward_pose, tracker) and damping (inverse_rate):
    valid values give correct results; out-of-domain values (negative or NaN tolerance,
    non-integer or negative max_iterations, max_step <= 0, damping < 0 or NaN, strings, None)
    raise a ParakinError; extreme ones (2**32 + 3 iterations, inf tolerance, damping 1e300)
    answer either way."""
    contract_property(name, ("ok", "raise", "either"), OPTION_ROLES, 30, 20)


@pytest.mark.parametrize("name", NAMES)
def test_unknown_keyword_arguments_are_refused_naming_the_keyword(name):
    """A misspelt or unknown keyword argument (tol=, foo=, damping= where there is none) is a
    call the method's signature does not allow: a TypeError naming the keyword, as every Python
    library answers it, and a parakin error (UnknownKeywordError, a BadInputError) suggesting the
    closest keyword; the keywords ``load`` collects as parameters raise a BadInputError naming the
    keyword."""
    checked = 0
    for backend in ("numpy", "compiled"):
        for op in (op for op in ops_of(name, backend) if op.role == "kwargs"):
            for keyword in ("tol", "foo", "dampening"):
                with pytest.raises(TypeError, match=keyword) as raised:
                    op.call({keyword: 1.0})
                assert isinstance(raised.value, parakin.UnknownKeywordError), (op, raised.value)
                checked += 1
    assert checked >= 6
    with pytest.raises(parakin.BadInputError, match="no_such_parameter"):
        parakin.load(name, no_such_parameter=1.0)


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_operations_without_their_capability_raise_unsupported(name, backend):
    """Every operation the manifest's capabilities lack raises UnsupportedOperationError (a
    ParakinError), whatever the input."""
    m = mechanism(name, backend)
    ops = [op for op in ops_of(name, backend) if op.unsupported]
    if not ops:
        pytest.skip(f"{name} has every capability the fuzzed operations need")
    failures = []
    for op in ops:
        variant = make_variant(op, m, "valid", Knobs())
        got, verdict = run_case(name, backend, op, variant)
        if not isinstance(got.error, parakin.UnsupportedOperationError):
            failures.append(report(name, backend, op, variant, verdict))
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize("name", NAMES)
def test_load_parameters_limits_and_backends(name):
    """parakin.load (on every backend) with a NaN / inf / string / None / complex / array
    parameter, a bad parameter group, bad limits or an unknown backend raises a ParakinError;
    zero, negative, huge or tiny parameters either raise one or give a mechanism whose
    operations answer finite results or named errors."""
    fx = fixture(name)
    labels = [op.label for op in load_operations(name, "numpy", fx)]
    checked = []

    @fuzz_settings(30)
    @given(
        label=st.sampled_from(labels), pick=st.integers(0, 1000), backend=st.sampled_from(BACKENDS), k=knobs_strategy
    )
    def property_holds(label, pick, backend, k):
        op = {o.label: o for o in load_operations(name, backend, fx)}[label]
        classes = classes_of(op)
        variant = make_variant(op, None, classes[pick % len(classes)], k, name=name)
        _, verdict = run_case(name, backend, op, variant)
        assert verdict.good, report(name, backend, op, variant, verdict)
        checked.append(label)

    for i, label in enumerate(labels):
        property_holds = example(label=label, pick=i, backend=BACKENDS[i % len(BACKENDS)], k=Knobs(i))(property_holds)
    property_holds()
    assert len(checked) >= len(labels) + 20 * SCALE, f"only {len(checked)} examples checked"


def test_pose_helpers_answer_rotations_or_named_errors():
    """euler_zyx_to_rotation, pose_from_xyz_euler(_deg), xyz_euler(_deg)_from_pose: rigid
    results for valid input (any batch shape, empty included), a ParakinError for NaN / inf,
    strings, None, complex values, object arrays and shapes that do not broadcast."""
    ops = {op.label: op for op in pose_helper_operations()}
    pairs = [(label, cls) for label, op in ops.items() for cls in classes_of(op)]
    checked = []

    @fuzz_settings(40)
    @given(pair=st.sampled_from(pairs), k=knobs_strategy)
    def property_holds(pair, k):
        label, cls = pair
        op = ops[label]
        variant = make_variant(op, None, cls, k)
        _, verdict = run_case(None, "-", op, variant)
        assert verdict.good, report(None, "-", op, variant, verdict)
        checked.append(pair)

    for pair in pairs:  # every helper with every class: cheap
        property_holds = example(pair=pair, k=Knobs())(property_holds)
    property_holds()
    assert len(checked) >= len(pairs) + 25 * SCALE, f"only {len(checked)} examples checked"


def _backends_agree(name: str, examples: int, minimum: int) -> None:
    """The same input (valid, malformed, non-finite or extreme, on any operation) gives the same
    exception class on numpy, casadi and compiled, or results equal to 1e-8: every operation once,
    then ``examples`` drawn inputs, at least ``minimum`` of them checked."""
    mechanisms = {backend: mechanism(name, backend) for backend in BACKENDS}
    cases = cases_of(name, ("ok", "raise", "flag", "either"), ARRAY_ROLES + OPTION_ROLES)
    labels = sorted(cases)
    checked = []

    @fuzz_settings(examples)
    @given(label=st.sampled_from(labels), pick=st.integers(0, 1000), k=knobs_strategy)
    def property_holds(label, pick, k):
        cls = cases[label][pick % len(cases[label])]
        answers, variant = {}, None
        for backend, m in mechanisms.items():
            op = op_named(name, backend, label)
            variant = make_variant(op, m, cls, k)
            answers[backend] = answer(lambda op=op, variant=variant: op.call(variant.value))
        op = op_named(name, "numpy", label)
        problem = agreement(op, answers)
        assert problem is None, (
            f"{label} on {name}, input class {cls!r}: backends disagree: {problem}\n"
            f"reproducer (change the backend):\n{reproducer(name, 'numpy', op, variant)}"
        )
        checked.append(label)

    for i, label in enumerate(labels):
        property_holds = example(label=label, pick=i, k=Knobs(i))(property_holds)
    property_holds()
    assert len(checked) >= len(labels) + minimum * SCALE, f"only {len(checked)} examples checked"


#: degenerate solver inputs per operation (issue 18 item 11): guesses at the origin, far away or
#: with a zero quaternion, tolerances at both ends of the documented range [MIN_TOLERANCE, 1] and
#: below it, no iterations
DEGENERATE_SOLVER_INPUTS = {
    "forward_pose(guess)": (*DEGENERATE_GUESSES, "huge", "tiny"),
    "forward_pose(tolerance=)": ("smallest-documented", "largest-documented", "below-documented"),
    "forward_pose(max_iterations=)": ("zero",),
    "tracker(tolerance=).solve": ("smallest-documented", "largest-documented", "below-documented"),
    "tracker(max_iterations=).solve": ("zero",),
}


def _claims_non_finite(error: BaseException | None) -> bool:
    """A BadInputError that says the input is not finite (only true of a NaN / inf input)."""
    text = str(error).lower()
    return isinstance(error, parakin.BadInputError) and ("non-finite" in text or "not finite" in text)


@pytest.mark.parametrize("name", NAMES)
def test_backends_agree_on_degenerate_solver_inputs(name):
    """Every degenerate guess, both ends of the tolerance range and max_iterations=0, on every
    operation that takes them: the same outcome on numpy, casadi and compiled (the same exception
    class, or results equal to 1e-8), each keeping the contract, and no finite input called
    non-finite. Enumerated, not drawn: every case runs."""
    mechanisms = {backend: mechanism(name, backend) for backend in BACKENDS}
    failures, checked = [], 0
    for label, classes in DEGENERATE_SOLVER_INPUTS.items():
        if label not in {op.label for op in ops_of(name, "numpy")}:
            continue
        for cls in (c for c in classes if c in classes_of(op_named(name, "numpy", label))):
            for k in (Knobs(0, 1e10), Knobs(5, 1e300)) if cls in ("huge", "tiny") else (Knobs(),):
                answers, variant = {}, None
                for backend, m in mechanisms.items():
                    op = op_named(name, backend, label)
                    variant = make_variant(op, m, cls, k)
                    answers[backend] = got = answer(lambda op=op, variant=variant: op.call(variant.value))
                    verdict = judge(op, variant, got)
                    finite = np.isfinite(np.asarray(variant.value, dtype=float)).all()
                    if finite and _claims_non_finite(got.error):
                        verdict = Verdict("other", f"a finite input called non-finite: {verdict.detail}")
                    if not verdict.good:
                        failures.append(report(name, backend, op, variant, verdict))
                problem = agreement(op_named(name, "numpy", label), answers)
                if problem:
                    failures.append(
                        f"{label} on {name}, input class {cls!r}: backends disagree: {problem}\n"
                        f"reproducer (change the backend):\n{reproducer(name, 'numpy', op, variant)}"
                    )
                checked += 1
    assert checked >= 4 if mechanisms["numpy"].passive_names else checked >= 0
    assert not failures, "\n\n".join(failures)


@pytest.mark.parametrize("name", NAMES)
def test_backends_give_the_same_answer_on_every_operation(name):
    """Every operation once and 9 drawn inputs (the next test draws 30)."""
    _backends_agree(name, 9, 6)


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_backends_give_the_same_answer(name):
    _backends_agree(name, 30, 20)
