"""Checks of a mechanism model before anything is derived from it: every problem found here would
otherwise surface later as a wrong kernel, a NameError in generated code or a C driver reading
past what CasADi wrote. Each raises a GenerationError naming the mechanism and the problem."""

from __future__ import annotations

import math
import warnings

import numpy as np
import sympy as sp

from parakin.solvers.linalg import inverse_condition

from .errors import GenerationError
from .model import POSE_KINDS, POSE_SYMBOLS, Mechanism


def _names(symbols: list[sp.Symbol]) -> list[str]:
    return [str(s) for s in symbols]


def check_variables(m: Mechanism) -> None:
    """Distinct actuated, passive and parameter symbols; home and limits name variables."""
    groups = {"actuated": m.actuated, "passive": m.passive, "parameters": list(m.parameters)}
    seen: dict[sp.Symbol, str] = {}
    for group, symbols in groups.items():
        for symbol in symbols:
            if not isinstance(symbol, sp.Symbol):
                raise GenerationError(f"{m.name}: {group} entry {symbol!r} is not a SymPy symbol")
            if symbol in seen:
                raise GenerationError(f"{m.name}: {symbol} is listed twice (in {seen[symbol]} and in {group})")
            seen[symbol] = group
    variables = set(m.actuated) | set(m.passive)
    for what, keys in (
        ("home", m.home),
        ("limits", m.limits),
        ("angular", m.angular),
        ("dimensionless", m.dimensionless),
    ):
        stray = sorted(str(k) for k in keys if k not in variables)
        if stray:
            raise GenerationError(f"{m.name}: {what} names {stray}, which are not actuated or passive variables")
    for symbol, (low, high) in m.limits.items():
        if not low < high:
            raise GenerationError(f"{m.name}: limits of {symbol} must satisfy low < high, got ({low}, {high})")
    check_home_within_limits(m)


def check_home_within_limits(m: Mechanism) -> None:
    """Every home value within its variable's limits.

    The runtime refuses values outside the limits (``plot``, ``forward_pose_all``, the viewer
    start from the home), so a package whose own home is outside them cannot be used from it.

    Parameters
    ----------
    m : Mechanism
        The mechanism model.

    Raises
    ------
    GenerationError
        Naming the variable, its home value with its unit, and the limits; for an angle whose
        value modulo 2 pi is inside, the value to write instead.
    """
    for symbol, value in m.home.items():
        if symbol not in m.limits:
            continue
        low, high = (float(v) for v in m.limits[symbol])
        home = float(value)
        if low <= home <= high:
            continue
        unit = "rad" if symbol in m.angular else "" if symbol in m.dimensionless else "m"
        hint = ""
        if symbol in m.angular:
            wrapped = math.remainder(home, 2 * math.pi)
            if low <= wrapped <= high:
                hint = f"; the same angle in (-pi, pi], {wrapped:.4f} {unit}, is inside: write that"
        raise GenerationError(
            f"{m.name}: home value {symbol} = {home:.4f}{' ' + unit if unit else ''} is outside its limits "
            f"[{low:.4f}, {high:.4f}]{hint} (the runtime refuses values outside the limits, and so the "
            "package's own home)"
        )


def check_pose_kind(m: Mechanism) -> None:
    """A known pose kind, and rate equations whose twist has that kind's components (a planar
    translation has (vx, vy): a third component would be a motion the platform cannot make)."""
    kind = POSE_KINDS.get(m.pose_kind)
    if kind is None:
        raise GenerationError(f"{m.name}: pose_kind {m.pose_kind!r} is not one of {sorted(POSE_KINDS)}")
    if m.rates is not None and tuple(m.rates.twist) != kind.twist:
        raise GenerationError(
            f"{m.name}: the rate model's twist {list(m.rates.twist)} does not match pose_kind {m.pose_kind!r}, "
            f"whose twist is {list(kind.twist)} (write the rates in those components, or change pose_kind)"
        )
    if m.rates is not None:
        size, count = len(kind.twist), len(m.actuated)
        wrenches = 0 if m.rates.constraints is None else m.rates.constraints.rows
        shapes = {"A": (m.rates.a.shape, (count, size)), "B": (m.rates.b.shape, (count, count))}
        if m.rates.constraints is not None:
            shapes["constraints"] = (m.rates.constraints.shape, (size - count, size))
        for what, (shape, expected) in shapes.items():
            if shape != expected:
                raise GenerationError(
                    f"{m.name}: the rate model's {what} is {shape[0]} x {shape[1]}, expected {expected[0]} x "
                    f"{expected[1]} ({count} actuators, {size} twist components {list(kind.twist)}, {wrenches} "
                    "constraint wrenches: a platform with fewer actuators than twist components gives "
                    "RateModel(constraints=...) one constraint wrench per missing actuator)"
                )


def check_inverse(m: Mechanism) -> None:
    """A closed-form inverse defines every actuated and passive variable."""
    if m.inverse is None:
        return
    defined = {target for target, _ in m.inverse.steps}
    missing = [str(v) for v in m.actuated + m.passive if v not in defined]
    if missing:
        raise GenerationError(f"{m.name}: the closed-form inverse does not define {missing} (add a step for each)")


def check_closure(m: Mechanism, residual: sp.Matrix, extra: set[sp.Symbol] | None = None) -> None:
    """A square loop closure (one equation per passive unknown) whose free symbols are variables
    and parameters only."""
    if m.passive and residual.rows != len(m.passive):
        raise GenerationError(
            f"{m.name}: the loop closure has {residual.rows} equations for {len(m.passive)} passive unknowns "
            f"{_names(m.passive)}; it must be square (one equation per unknown)"
        )
    allowed = set(m.actuated) | set(m.passive) | set(m.parameters) | (extra or set())
    free = sorted(str(s) for s in residual.free_symbols - allowed)
    if free:
        raise GenerationError(
            f"{m.name}: the loop closure uses {free}, which are neither variables nor parameters "
            "(declare them as parameters with defaults)"
        )


def check_program_symbols(m: Mechanism, name: str, inputs: list[sp.Symbol], steps, outputs) -> None:
    """Every symbol a generated function reads is an input or an earlier step's target."""
    known = set(inputs) | set(POSE_SYMBOLS)
    for target, value in steps:
        free = sorted(str(s) for s in sp.sympify(value).free_symbols - known)
        if free:
            raise GenerationError(f"{m.name}: {name} step {target} uses undefined symbols {free}")
        known.add(target)
    for matrix in outputs:
        free = sorted(str(s) for s in sp.Matrix(matrix).free_symbols - known)
        if free:
            raise GenerationError(f"{m.name}: {name} uses undefined symbols {free}")


#: a default home whose type II distance (``home_type_ii_distance``: sigma_min / sigma_max of
#: d closure / d passive, the measure of ``parakin.singularity``) is below this is near a parallel
#: singularity and the generator warns (``NearSingularHomeWarning``). The shipped homes range
#: down to 0.0077 (planar_3rpr; gough 0.0079, stewart 0.011, the rest above 0.13).
NEAR_SINGULAR_HOME = 1e-3
#: below this the home is singular to double precision: a GenerationError
SINGULAR_HOME = 1e-12


class NearSingularHomeWarning(UserWarning):
    """A mechanism's default home is near a type II (parallel) singularity: its distance
    sigma_min / sigma_max of d closure / d passive is below ``NEAR_SINGULAR_HOME``. The package is
    generated, but the runtime starts from the home (``plot``, the viewer, ``forward_pose`` near
    it): there the actuators barely hold the platform and Newton steps are ill-conditioned. Move
    the home (another pose or branch), or check the layout (angles in degrees where a builder's
    argument says ``_deg``)."""


def home_type_ii_distance(m: Mechanism, jacobian_passive: sp.Matrix) -> float | None:
    """The home's distance to a type II singularity: 1/cond of d closure / d passive evaluated at
    the home and the default parameters (``parakin.solvers.linalg.inverse_condition``).

    Parameters
    ----------
    m : Mechanism
        The mechanism model (its ``home`` and ``parameters``).
    jacobian_passive : sympy.Matrix, shape (n_p, n_p)
        d closure / d passive, symbolic in the variables and parameters.

    Returns
    -------
    float or None
        In [0, 1]; None without passive variables, with a home that does not give every variable
        a value, or where the Jacobian at the home is not a finite real matrix.
    """
    if not m.passive or jacobian_passive.cols == 0:
        return None
    values = {**m.parameters, **m.home}
    if any(v not in values for v in (*m.actuated, *m.passive)):
        return None
    numeric = jacobian_passive.xreplace({s: sp.Float(float(v), 17) for s, v in values.items()})
    try:
        matrix = np.array(numeric.evalf(17).tolist(), dtype=float)
    except TypeError:  # a symbol left, or a complex entry: no number to judge by
        return None
    if not np.isfinite(matrix).all():
        return None
    return float(inverse_condition(matrix))


def check_home_regular(m: Mechanism, jacobian_passive: sp.Matrix) -> float | None:
    """Warn of a default home near a type II singularity, refuse one at it.

    Parameters
    ----------
    m : Mechanism
        The mechanism model.
    jacobian_passive : sympy.Matrix, shape (n_p, n_p)
        d closure / d passive.

    Returns
    -------
    float or None
        The home's type II distance (``home_type_ii_distance``).

    Raises
    ------
    GenerationError
        The distance is below ``SINGULAR_HOME`` (singular to double precision).

    Warns
    -----
    NearSingularHomeWarning
        The distance is below ``NEAR_SINGULAR_HOME``; the message gives it.
    """
    distance = home_type_ii_distance(m, jacobian_passive)
    if distance is None:
        return None
    where = "sigma_min / sigma_max of d closure / d passive at the home"
    if distance < SINGULAR_HOME:
        raise GenerationError(
            f"{m.name}: the default home is at a type II (parallel) singularity ({where} = {distance:.3g}): "
            "the actuators do not hold the platform there; choose another home pose or branch"
        )
    if distance < NEAR_SINGULAR_HOME:
        warnings.warn(
            f"{m.name}: the default home is near a type II (parallel) singularity ({where} = {distance:.3g}, "
            f"below {NEAR_SINGULAR_HOME:g}); choose another home pose or branch, or check the layout "
            "(angles in degrees where a builder's argument says _deg)",
            NearSingularHomeWarning,
            stacklevel=2,
        )
    return distance
