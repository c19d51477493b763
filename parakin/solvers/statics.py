"""Statics from a mechanism's rate model, for every mechanism that has one: the actuator efforts
that hold a platform wrench, the stiffness of the platform on compliant actuators, and the
equilibrium those actuators reach under load.

Conventions (the same for every mechanism):

* Twist: the components ``m.manifest.capabilities.rates.twist`` of an A/B rate model (e.g.
  (vx, vy, vz, wx, wy, wz) = (v of the origin of {P}, w), both in {B}, or (wx, wy, wz) for an
  orienting platform); (v, w) in {B} for a leg-based model (``m.rate_matrix``).
* G, the map twist -> actuated rates: actuated_rates = G twist, G = B^-1 A from
  ``m.rate_jacobians`` (A twist = B actuated_rates) or G = M from ``m.rate_matrix``.
* Wrench: the dual of the twist, component by component, so that its power is w . twist: a force
  f acting at the origin of {P} and a moment n, both in {B}; for an orienting platform only the
  moment about its centre (the origin of {P}; the force goes into the central joint). A force F at
  a platform point p (in {P}) is (F, (R p) x F): ``point_force_wrench``.
* Actuator efforts tau (a force for a prismatic actuator, a torque for a revolute one) are
  positive along increasing actuated values. ``actuator_forces`` returns the efforts that hold
  the platform in static equilibrium against an external wrench w applied to it (massless,
  frictionless): tau . dq + w . twist dt = 0 for every virtual motion, i.e. G^T tau = -w. A
  lower-mobility platform (constraint wrenches C, C twist = 0 for every motion it can make) holds
  w with its actuators and its constraints together: w + A^T phi + C^T lambda = 0, tau = B^T phi
  (``constraint_forces`` gives lambda).
* Compliant actuators: tau = K_q (q_cmd - q), K_q (n_a, n_a) positive (a diagonal given as its
  (n_a,) diagonal): an actuator pushed beyond its command pulls back.

NumPy only; every function uses the mechanism's generated rate Jacobians, never its name.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from parakin.errors import BadInputError, ConvergenceError, UnsupportedOperationError
from parakin.pose import LEG_TWIST, as_array
from parakin.results import Array, Configuration, ForwardPose
from parakin.validation import bounded_vector, stiffness_matrix

if TYPE_CHECKING:
    from parakin.solvers.loaded import LoadedMechanism


Wrench = ArrayLike | Callable[[Configuration], ArrayLike]


def twist_names(m: LoadedMechanism) -> tuple[str, ...]:
    """The twist (and wrench) components of ``m``.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism.

    Returns
    -------
    tuple of str
        ``capabilities.rates.twist`` of an A/B rate model, or the six (v, w) of a leg model.

    Raises
    ------
    UnsupportedOperationError
        The mechanism has no rate model (neither A/B rate Jacobians nor serial legs).

    Examples
    --------
    >>> import parakin
    >>> from parakin.solvers.statics import twist_names
    >>> twist_names(parakin.load("five_bar", backend="numpy"))  # a translating planar platform
    ('vx', 'vy')
    """
    rates = m.manifest.capabilities.rates
    if rates is not None:
        return rates.twist
    if m.manifest.capabilities.legs:
        return LEG_TWIST
    raise UnsupportedOperationError(
        f"{m.name} has no rate model (neither A/B rate Jacobians nor serial legs): statics is not available"
    )


def _rate_model(m: LoadedMechanism, state: Configuration) -> tuple[Array, Array | None, Array | None]:
    """(A, B, C) with A twist = B actuated_rates and C twist = 0 (C None without constraint
    wrenches); B is None for a leg model (A = M, B = I)."""
    twist_names(m)
    if m.manifest.capabilities.rates is not None:
        jacobians = m.rate_jacobians(state)
        constraints = jacobians.get("constraints")
        return (
            np.asarray(jacobians["a"], dtype=float),
            np.asarray(jacobians["b"], dtype=float),
            None if constraints is None else np.asarray(constraints, dtype=float),
        )
    return np.asarray(m.rate_matrix(state), dtype=float), None, None


def actuation_matrix(m: LoadedMechanism, state: Configuration) -> Array:
    """G: actuated_rates = G twist (B^-1 A, or M of ``m.rate_matrix``).

    For a lower-mobility platform G holds on the twists it can make (C twist = 0).

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with a rate model.
    state : Configuration
        A closed configuration (batch allowed).

    Returns
    -------
    numpy.ndarray, shape (..., n_a, n_t)
        G over the twist components ``twist_names(m)``.

    Raises
    ------
    SingularConfigurationError
        B is singular (a serial, type I singularity: an actuator rate is not defined).
    UnsupportedOperationError
        The mechanism has no rate model.

    Examples
    --------
    >>> import parakin
    >>> from parakin.solvers.statics import actuation_matrix
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> state = m.forward_pose(m.home_actuated)
    >>> G = actuation_matrix(m, state)
    >>> (G @ m.forward_rate(state, [0.1, 0.0])).round(9).tolist()  # back to the actuated rates
    [0.1, 0.0]
    """
    a, b, _ = _rate_model(m, state)
    if b is None:
        return a
    return m._solve(
        b, a, "B (inverse Jacobian)", "a serial (type I) singularity: an actuator rate is not defined", columns=True
    )


def _wrench(m: LoadedMechanism, wrench: ArrayLike) -> Array:
    return bounded_vector(wrench, "wrench", twist_names(m))


def actuator_forces(m: LoadedMechanism, state: Configuration, wrench: ArrayLike) -> Array:
    """Actuator efforts tau that hold the platform against the external ``wrench`` applied to it.

    G^T tau = -wrench (see the module docstring), solved as tau = -B^T A^-T wrench (or
    -M^-T wrench).

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with a rate model.
    state : Configuration
        A closed configuration.
    wrench : array_like, shape (..., n_t)
        The external wrench over ``twist_names(m)``: force (N) at the origin of {P}, moment (N m),
        both in {B}.

    Returns
    -------
    numpy.ndarray, shape (..., n_a)
        Efforts (N for prismatic, N m for revolute actuators), positive along increasing actuated
        values (for a linear actuator: a compression, the leg pushing the platform away).

    Raises
    ------
    SingularConfigurationError
        A type II (parallel) singularity: A (or M) is singular and some wrench cannot be held.
    UnsupportedOperationError
        The mechanism has no rate model.
    BadInputError
        A wrench of the wrong length or not finite.

    Examples
    --------
    >>> import numpy as np, parakin
    >>> from parakin.solvers.statics import actuator_forces
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> state = m.forward_pose(m.home_actuated)
    >>> tau = actuator_forces(m, state, [0.0, -10.0])  # 10 N down on the platform
    >>> tau.round(3).tolist()
    [-1.727, 1.727]
    >>> rates = [0.1, 0.0]  # virtual work: tau . rates + wrench . twist = 0
    >>> bool(abs(tau @ rates + np.dot([0.0, -10.0], m.forward_rate(state, rates))) < 1e-12)
    True
    """
    return _holding_intensities(m, state, wrench)[0]


def constraint_forces(m: LoadedMechanism, state: Configuration, wrench: ArrayLike) -> Array:
    """Intensities lambda of the constraint wrenches a lower-mobility platform's legs apply.

    The constraint wrenches C are ``m.rate_jacobians(state)["constraints"]``, one row per wrench;
    the legs apply them while the actuators hold the external ``wrench``:
    wrench + A^T phi + C^T lambda = 0 with tau = B^T phi (``actuator_forces``).

    Parameters
    ----------
    m : Mechanism
        A loaded lower-mobility mechanism.
    state : Configuration
        A closed configuration.
    wrench : array_like, shape (..., 6)
        The external wrench (N at the origin of {P}, N m; in {B}).

    Returns
    -------
    numpy.ndarray, shape (..., n_c)
        One intensity per constraint wrench.

    Raises
    ------
    UnsupportedOperationError
        A platform with no constraint wrenches (its actuators alone hold every wrench).
    SingularConfigurationError
        A type II singularity.

    Examples
    --------
    >>> import parakin
    >>> from parakin.solvers.statics import actuator_forces, constraint_forces
    >>> m = parakin.load("tricept", backend="numpy")
    >>> state = m.forward_pose(m.home_actuated)
    >>> load = [0, 0, -100, 0, 0, 0]  # 100 N down, centred: the three legs share it
    >>> (constraint_forces(m, state, load).round(9) + 0.0).tolist(), actuator_forces(m, state, load).round(2).tolist()
    ([0.0, 0.0, 0.0], [35.9, 35.9, 35.9])
    """
    rates = m.manifest.capabilities.rates
    if rates is None or not rates.constraints:
        raise UnsupportedOperationError(f"{m.name} has no constraint wrenches: its actuators hold every wrench")
    return _holding_intensities(m, state, wrench)[1]


def overall_jacobian(a: Array, constraints: Array | None) -> tuple[Array, str]:
    """[A; C] of a lower-mobility platform (A alone without constraint wrenches), and its name.

    The matrix maps twist -> (A twist, C twist); forward rates and statics solve with it.

    Parameters
    ----------
    a : numpy.ndarray, shape (..., n_a, n_t)
        A of A twist = B actuated_rates.
    constraints : numpy.ndarray, shape (..., n_c, n_t), or None
        The constraint wrenches C, or None.

    Returns
    -------
    tuple of (numpy.ndarray, str)
        The matrix, shape (..., n_a + n_c, n_t), and its name for messages.

    Raises
    ------
    ValueError
        A and C whose batch or column shapes differ (a programming error, not a user input).

    Examples
    --------
    >>> import numpy as np
    >>> from parakin.solvers.statics import overall_jacobian
    >>> matrix, name = overall_jacobian(np.eye(3, 6), np.eye(6)[3:])
    >>> matrix.shape, name
    ((6, 6), '[A; constraints] (overall Jacobian)')
    """
    if constraints is None:
        return a, "A (direct Jacobian)"
    return np.concatenate([a, constraints], axis=-2), "[A; constraints] (overall Jacobian)"


def _holding_intensities(m: LoadedMechanism, state: Configuration, wrench: ArrayLike) -> tuple[Array, Array]:
    """(tau, lambda): the platform's equilibrium w + A^T phi + C^T lambda = 0, tau = B^T phi."""
    w = _wrench(m, wrench)
    a, b, constraints = _rate_model(m, state)
    overall, name = overall_jacobian(a, constraints)
    y = m._solve(
        np.swapaxes(overall, -1, -2), w, "rate matrix M" if b is None else name, "a type II (parallel) singularity"
    )
    count = a.shape[-2]
    phi, reactions = -y[..., :count], -y[..., count:]
    tau = phi if b is None else (np.swapaxes(b, -1, -2) @ phi[..., None])[..., 0]
    return np.asarray(tau, dtype=np.float64), np.asarray(reactions, dtype=np.float64)


def _actuator_stiffness(m: LoadedMechanism, actuator_stiffness: ArrayLike) -> Array:
    """K_q (n_a, n_a), validated (``validation.stiffness_matrix``: positive diagonal, or symmetric
    positive definite)."""
    return stiffness_matrix(actuator_stiffness, "actuator_stiffness", len(m.actuated_names))


def stiffness(m: LoadedMechanism, state: Configuration, actuator_stiffness: ArrayLike) -> Array:
    """Platform stiffness K = G^T K_q G on actuators of stiffness K_q.

    K gives the extra external wrench that holds the platform displaced by a small motion twist
    dt: dw = K twist dt. Symmetric, and positive definite when K_q is and G has full rank. The
    geometric stiffness of preloaded actuators (dG/dx^T tau) is neglected. For a lower-mobility
    platform K holds for the twists it can make (C twist = 0; rank n_a): the constraint wrenches
    hold the other directions rigidly.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with a rate model.
    state : Configuration
        A closed configuration.
    actuator_stiffness : array_like, shape (n_a,) or (n_a, n_a)
        K_q (N/m or N m/rad): a positive diagonal, or a symmetric positive definite matrix.

    Returns
    -------
    numpy.ndarray, shape (..., n_t, n_t)
        K over ``twist_names(m)``.

    Raises
    ------
    BadInputError
        A stiffness that is not positive (definite) or of the wrong shape.
    SingularConfigurationError
        A serial singularity (G is not defined).

    Examples
    --------
    >>> import numpy as np, parakin
    >>> from parakin.solvers.statics import actuation_matrix, stiffness
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> state = m.forward_pose(m.home_actuated)
    >>> K = stiffness(m, state, [1000.0, 1000.0])
    >>> G = actuation_matrix(m, state)  # equal actuators: K = 1000 G^T G
    >>> bool(np.allclose(K, 1000.0 * G.T @ G))
    True
    """
    k = _actuator_stiffness(m, actuator_stiffness)
    g = actuation_matrix(m, state)
    return np.asarray(np.swapaxes(g, -1, -2) @ k @ g, dtype=np.float64)


def point_force_wrench(m: LoadedMechanism, state: Configuration, force: ArrayLike, point: ArrayLike) -> Array:
    """The wrench of a force applied at a platform point.

    The force and its moment (R p) x F about the origin of {P}, in the mechanism's twist
    components (an orienting platform keeps the moment only).

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with a rate model.
    state : Configuration
        The configuration (its rotation R turns ``point`` into {B}).
    force : array_like, shape (..., 3)
        F in {B} (N).
    point : array_like, shape (..., 3)
        p in {P} (m).

    Returns
    -------
    numpy.ndarray, shape (..., n_t)
        The wrench over ``twist_names(m)`` (N, N m).

    Raises
    ------
    BadInputError
        A force or point not finite, or of the wrong length.
    UnsupportedOperationError
        A twist component other than vx ... wz, or no rate model.

    Examples
    --------
    >>> import parakin
    >>> from parakin.solvers.statics import point_force_wrench
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> state = m.forward_pose(m.home_actuated)
    >>> point_force_wrench(m, state, [0.0, -10.0, 0.0], [0.0, 0.0, 0.0]).tolist()  # (fx, fy)
    [0.0, -10.0]
    """
    f = bounded_vector(force, "force", ("fx", "fy", "fz"))
    p = bounded_vector(point, "point", ("x", "y", "z"))
    arm = np.einsum("...ij,...j->...i", state.rotation, p)
    moment = np.cross(arm, f)
    full = np.concatenate(np.broadcast_arrays(f, moment), axis=-1)
    index = []
    for name in twist_names(m):
        if name not in LEG_TWIST:
            raise UnsupportedOperationError(f"{m.name}: twist component {name!r} is not one of {LEG_TWIST}")
        index.append(LEG_TWIST.index(name))
    return np.asarray(full[..., index], dtype=np.float64)


# ---------------------------------------------------------------------------------- equilibrium
@dataclass(frozen=True)
class Equilibrium:
    """The platform on compliant actuators under load: ``configuration`` is the pose reached
    with the loaded actuated values q (``configuration.actuated``), ``forces`` the actuator
    efforts tau = K_q (q_cmd - q) that hold the wrench there, ``residual`` the max-norm of
    K_q (q_cmd - q) - actuator_forces(q) (effort units), ``history`` the size of each update of
    q (max-norm, actuated units) and ``iterations`` their number."""

    configuration: ForwardPose
    forces: Array
    residual: float
    iterations: int
    history: tuple[float, ...]


def equilibrium(
    m: LoadedMechanism,
    commanded_actuated: ArrayLike,
    wrench: Wrench,
    actuator_stiffness: ArrayLike,
    guess: Configuration | ArrayLike | None = None,
    method: str = "newton",
    tolerance: float = 1e-12,
    max_iterations: int = 50,
    step: float = 1e-7,
) -> Equilibrium:
    """Static equilibrium of compliant actuators commanded to ``commanded_actuated`` under a wrench.

    Solves for the actuated values q with K_q (q_cmd - q) = actuator_forces(m, state(q), wrench),
    state(q) = ``m.forward_pose(q)`` tracked from ``guess``.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with a rate model.
    commanded_actuated : array_like, shape (n_a,)
        q_cmd (m or rad).
    wrench : array_like, shape (n_t,), or callable
        The external wrench (N, N m), or a function of the configuration for a load that moves
        with the platform (e.g. ``lambda c: point_force_wrench(m, c, force, point)``).
    actuator_stiffness : array_like, shape (n_a,) or (n_a, n_a)
        K_q (N/m or N m/rad).
    guess : Configuration or array_like or None
        Where the forward pose is tracked from (a configuration, passive values or a pose; None:
        ``forward_pose``'s default assembly mode).
    method : {"newton", "fixed_point"}
        'newton': Newton on q - q_cmd + K_q^-1 tau(q), central differences of step
        ``step`` x (1 + |q_j|) through the forward pose; 'fixed_point': successive approximation
        q <- q_cmd - K_q^-1 tau(q) (converges when the actuators are stiff enough).
    tolerance : float
        Stop when an update of q is below this (m or rad, max-norm).
    max_iterations : int
        The most updates.
    step : float
        The relative finite-difference step of 'newton'.

    Returns
    -------
    Equilibrium
        ``configuration`` reached, actuator ``forces``, ``residual``, ``iterations``, ``history``.

    Raises
    ------
    BadInputError
        An unknown ``method``, a batch of commands, or a stiffness that is not positive.
    ConvergenceError
        No update below ``tolerance`` within ``max_iterations`` (the residual is in the error).
    SingularConfigurationError
        The equilibrium is not isolated, or a singularity on the way.

    Examples
    --------
    >>> import parakin
    >>> from parakin.solvers.statics import equilibrium
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> held = equilibrium(m, m.home_actuated, [0.0, -10.0], [1000.0, 1000.0])
    >>> held.forces.round(3).tolist()  # a little more than the rigid -1.727, 1.727
    [-1.735, 1.735]
    >>> ((m.home_actuated - held.configuration.actuated) * 1000.0).round(3).tolist()  # K_q (q_cmd - q)
    [-1.735, 1.735]
    """
    if method not in ("newton", "fixed_point"):
        raise BadInputError(f"method must be 'newton' or 'fixed_point', got {method!r}")
    command = as_array(commanded_actuated, "commanded_actuated", (len(m.actuated_names),))
    if command.ndim != 1:
        raise BadInputError(f"equilibrium takes one commanded input (n_a,), got shape {command.shape}")
    k = _actuator_stiffness(m, actuator_stiffness)
    compliance = m._solve(
        k, np.eye(k.shape[-1]), "actuator stiffness matrix", "every actuator needs a stiffness", columns=True
    )
    load: Callable[[Configuration], Any] = wrench if callable(wrench) else (lambda _state: wrench)

    def forces(q: Array, start: Any) -> tuple[Array, ForwardPose]:
        state = m.forward_pose(q, guess=start)
        return actuator_forces(m, state, load(state)), state

    def gap(q: Array, start: Any) -> tuple[Array, Array, ForwardPose]:
        tau, state = forces(q, start)
        return q - command + compliance @ tau, tau, state

    q = command.copy()
    start: Any = guess
    history: list[float] = []
    for _ in range(max_iterations):
        value, _, state = gap(q, start)
        start = state
        if method == "fixed_point":
            update = -value
        else:
            columns = []
            for j in range(q.size):
                h = step * (1.0 + abs(q[j]))
                e = np.zeros(q.size)
                e[j] = h
                columns.append((gap(q + e, state)[0] - gap(q - e, state)[0]) / (2 * h))
            update = -m._solve(
                np.column_stack(columns), value, "equilibrium Jacobian", "the compliant equilibrium is not isolated"
            )
        q = q + update
        history.append(float(np.abs(update).max()))
        if not np.isfinite(history[-1]) or history[-1] < tolerance:
            break
    tau, state = forces(q, start)
    residual = float(np.abs(k @ (command - q) - tau).max())
    if not history or not history[-1] < tolerance:
        last = history[-1] if history else float("nan")
        raise ConvergenceError(
            f"equilibrium ({method}) did not converge in {max_iterations} iterations: last update {last:.3g} "
            f"> tolerance {tolerance:g}, residual {residual:.3g}",
            residual=residual,
        )
    return Equilibrium(state, tau, residual, len(history), tuple(history))


__all__ = [
    "Equilibrium",
    "actuation_matrix",
    "actuator_forces",
    "constraint_forces",
    "equilibrium",
    "point_force_wrench",
    "stiffness",
    "twist_names",
]
