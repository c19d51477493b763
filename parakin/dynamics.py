"""Inverse dynamics of a parallel mechanism from its generated rate model: the platform's
Newton-Euler wrench mapped onto the actuators, and its linear regressor over the platform's ten
inertial parameters. Free functions over a loaded mechanism (Pinocchio style: ``rnea(model, data,
q, v, a)`` here is ``inverse_dynamics(m, state, rates, accelerations, platform_inertia=...)``).

Conventions (those of ``parakin.solvers.statics``, SI units and radians):

* The generalised coordinates are the actuated values: ``rates`` are the actuated rates q_dot
  (..., n_a) and ``accelerations`` the actuated accelerations q_ddot (..., n_a) at the closed
  configuration ``state`` (from a solver: ``m.forward_pose``, ``m.inverse_pose(...).branch(k)``).
* Twist t = (v, w): v the velocity of the origin O of {P}, w the angular velocity, both in {B},
  restricted to the mechanism's twist components ``m.manifest.capabilities.rates.twist`` (the
  others are zero: a planar, translational or orienting platform). Its time derivative
  t_dot = (a, alpha) is the acceleration of O and the angular acceleration, in {B}.
* The rate model A t = B q_dot (and C t = 0 for a lower-mobility platform, C its constraint
  wrenches) differentiated along the motion: A t_dot + B' = B q_ddot, the velocity product
  B' = (dA/dt) t - (dB/dt) q_dot (and C t_dot + (dC/dt) t = 0), where d/dt is the derivative of
  the generated ``rate_jacobians`` kernel along (q_dot, p_dot), p_dot = ``m.passive_rates``. It
  is computed by forward-mode automatic differentiation of the kernel's generated CasADi
  expression (exact to rounding; no finite differences), once per package.
* Platform inertia: mass m (kg), centre c (m, in {P}) and inertia I_c about the centre (kg m^2,
  axes of {P}): ``RigidInertia``. Its ten inertial parameters, in Pinocchio's order, are
  theta = (m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz) with I = I_c + m (|c|^2 1 -
  c c^T) the inertia about O, in {P}.
* Newton-Euler about O (r = R c, h = R m c, I_O = R I R^T, g gravity in {B}):
  F = m (a - g) + alpha x h + w x (w x h),  n = I_O alpha + w x (I_O w) + h x (a - g):
  the wrench the actuators (and constraints) must apply. The efforts are those that hold the
  d'Alembert wrench -(F, n) (``actuator_forces``): G^T tau = (F, n) on the twist components,
  G = B^-1 A; a lower-mobility platform's constraint wrenches take the rest
  (``InverseDynamics.constraint_forces``).
* Legs are massless here; their inertias need the mechanism's joint graph (``leg_inertias``
  raises UnsupportedOperationError until then).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from parakin.errors import BadInputError, UnsupportedOperationError
from parakin.pose import LEG_TWIST, as_array
from parakin.results import Array, Configuration
from parakin.solvers.statics import actuator_forces, constraint_forces, overall_jacobian, twist_names
from parakin.validation import bounded_vector

if TYPE_CHECKING:
    from parakin.solvers.loaded import LoadedMechanism as Mechanism

#: standard gravity in {B} (m/s^2), z up
STANDARD_GRAVITY = (0.0, 0.0, -9.80665)
#: the names of the ten inertial parameters (Pinocchio's order; inertia about the origin of {P})
INERTIAL_PARAMETERS = ("m", "mcx", "mcy", "mcz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz")
#: a rotational inertia's eigenvalues must satisfy the triangle inequality to this relative slack
_TRIANGLE_SLACK = 1e-9
# (row, col) of each inertia parameter in the symmetric 3x3 tensor
_INERTIA_ENTRIES = ((0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2))


@dataclass(frozen=True)
class RigidInertia:
    """A rigid body's mass ``mass`` (kg), centre of mass ``centre`` (3,) (m, in the body frame)
    and rotational inertia ``inertia`` (3, 3) about the centre (kg m^2, body axes). Build it with
    ``rigid_inertia`` (validated) or ``RigidInertia.from_parameters``."""

    mass: float
    centre: Array
    inertia: Array

    def parameters(self) -> Array:
        """theta (10,): (m, m c, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz) with I the inertia about the
        origin of the body frame (parallel axes): the vector ``dynamics_regressor`` multiplies."""
        c = self.centre
        about_origin = self.inertia + self.mass * (float(c @ c) * np.eye(3) - np.outer(c, c))
        entries = [about_origin[i, j] for i, j in _INERTIA_ENTRIES]
        return np.array([self.mass, *(self.mass * c), *entries], dtype=float)

    @classmethod
    def from_parameters(cls, theta: ArrayLike) -> RigidInertia:
        """The body of inertial parameters ``theta`` (10,) (``parameters``'s order); BadInputError
        for a non-positive mass or an inertia that no body has."""
        values = as_array(theta, "theta", (10,))
        if values.shape != (10,):
            raise BadInputError(f"theta must have shape (10,) {INERTIAL_PARAMETERS}, got {values.shape}")
        mass = float(values[0])
        if not mass > 0:
            raise BadInputError(f"theta[0] (mass) = {mass:g} kg: a body's mass must be > 0")
        centre = values[1:4] / mass
        about_origin = np.zeros((3, 3))
        for value, (i, j) in zip(values[4:], _INERTIA_ENTRIES, strict=True):
            about_origin[i, j] = about_origin[j, i] = value
        inertia = about_origin - mass * (float(centre @ centre) * np.eye(3) - np.outer(centre, centre))
        return rigid_inertia(mass, centre, inertia)


def rigid_inertia(mass: float, centre: ArrayLike = (0.0, 0.0, 0.0), inertia: ArrayLike | None = None) -> RigidInertia:
    """A validated ``RigidInertia``.

    Parameters
    ----------
    mass : float
        Mass (kg), > 0.
    centre : array_like (3,)
        Centre of mass in the body frame (m); default the origin.
    inertia : array_like (3,) or (3, 3), optional
        Rotational inertia about the centre in the body axes (kg m^2): a symmetric positive
        semi-definite matrix whose principal moments satisfy the triangle inequality (a point
        mass: zero), or its diagonal (3,). Default zero (a point mass).

    Returns
    -------
    RigidInertia

    Raises
    ------
    BadInputError
        A non-positive or non-finite mass, a centre that is not 3 finite numbers, an inertia that
        is not symmetric, has a negative principal moment or violates the triangle inequality.

    Example
    -------
    >>> body = rigid_inertia(10.0, (0, 0, 0.02), (0.1, 0.1, 0.18))
    >>> body.parameters()[:4]
    array([10. ,  0. ,  0. ,  0.2])
    """
    mass_value = float(np.asarray(mass, dtype=float)) if np.ndim(mass) == 0 else float("nan")
    if not (np.isfinite(mass_value) and mass_value > 0):
        raise BadInputError(f"mass = {mass!r}: a body's mass must be a finite number > 0 (kg)")
    c = bounded_vector(centre, "centre", ("x", "y", "z"))
    if c.shape != (3,):
        raise BadInputError(f"centre must have shape (3,), got {c.shape}")
    if inertia is None:
        tensor = np.zeros((3, 3))
    else:
        given = as_array(inertia, "inertia", ())
        if given.shape == (3,):
            tensor = np.diag(given)
        elif given.shape == (3, 3):
            tensor = given.copy()
        else:
            raise BadInputError(f"inertia must have shape (3,) or (3, 3) (kg m^2), got {given.shape}")
    scale = max(float(np.abs(tensor).max()), 1e-300)
    asymmetry = float(np.abs(tensor - tensor.T).max())
    if asymmetry > 1e-10 * scale:
        raise BadInputError(f"inertia is not symmetric: |I - I^T| = {asymmetry:.3g} kg m^2")
    tensor = (tensor + tensor.T) / 2
    moments = np.linalg.eigvalsh(tensor)
    if moments[0] < -1e-12 * scale:
        raise BadInputError(f"inertia has a negative principal moment {moments[0]:.6g} kg m^2")
    if moments[2] > moments[0] + moments[1] + _TRIANGLE_SLACK * scale:
        raise BadInputError(
            f"inertia's principal moments {moments[0]:.6g}, {moments[1]:.6g}, {moments[2]:.6g} kg m^2 violate the "
            "triangle inequality (I3 <= I1 + I2): no rigid body has them"
        )
    return RigidInertia(mass_value, c, tensor)


@dataclass(frozen=True)
class InverseDynamics:
    """What ``inverse_dynamics`` returns, arrays with the inputs' batch shape (...):

    ``efforts`` (..., n_a): actuator efforts tau (N for a linear actuator, N m for a revolute one),
    positive along increasing actuated values; ``constraint_forces`` (..., n_c) the intensities of
    a lower-mobility platform's constraint wrenches (None without them); ``twist`` and
    ``twist_rate`` (..., n_twist): the platform's twist and its time derivative (a, alpha);
    ``wrench`` (..., 6): (F, n) the actuators and legs apply to the platform, about the origin of
    {P}, in {B} (all six components, also those the twist lacks)."""

    efforts: Array
    constraint_forces: Array | None
    twist: Array
    twist_rate: Array
    wrench: Array


# ------------------------------------------------------------------------------- the closure
_PRODUCTS: dict[str, Any] = {}
_PRODUCTS_LOCK = threading.Lock()


def _velocity_product_function(m: Mechanism) -> Any:
    """The CasADi Function (actuated, passive, params, twist, actuated_rates, passive_rates) ->
    (A; C)' t - (B; 0)' q_dot: the derivative of the generated ``rate_jacobians`` along the
    motion, by forward-mode automatic differentiation of its generated expression."""
    source = m.package.path / "casadi_functions.py"
    try:
        stamp = source.stat()
    except OSError as error:
        raise UnsupportedOperationError(
            f"{m.name}: inverse dynamics needs the package's {source.name}: {error}"
        ) from error
    key = f"{m.package.path}:{stamp.st_mtime_ns}:{stamp.st_size}"  # a regenerated package is rebuilt
    with _PRODUCTS_LOCK:
        if key in _PRODUCTS:
            return _PRODUCTS[key]
    try:
        import casadi
    except ImportError as error:  # pragma: no cover - casadi is a runtime dependency
        raise UnsupportedOperationError(f"inverse dynamics needs the casadi module: {error}") from error
    builder = m.package.casadi_builders["rate_jacobians"]()
    n_a, n_p, n_k = len(m.actuated_names), len(m.passive_names), len(m.params)
    n_t = len(twist_names(m))
    q, p, k = casadi.SX.sym("q", n_a), casadi.SX.sym("p", n_p), casadi.SX.sym("k", n_k)
    t, qd, pd = casadi.SX.sym("t", n_t), casadi.SX.sym("qd", n_a), casadi.SX.sym("pd", n_p)
    outputs = builder.call({"actuated": q, "passive": p, "params": k})
    relation = outputs["a"] @ t - outputs["b"] @ qd
    if "constraints" in outputs:
        relation = casadi.vertcat(relation, outputs["constraints"] @ t)
    product = casadi.jtimes(relation, casadi.vertcat(q, p), casadi.vertcat(qd, pd))
    function = casadi.Function(
        f"{m.name}_velocity_product",
        [q, p, k, t, qd, pd],
        [product],
        ["actuated", "passive", "params", "twist", "actuated_rates", "passive_rates"],
        ["product"],
    )
    with _PRODUCTS_LOCK:
        _PRODUCTS[key] = function
    return function


def velocity_product(m: Mechanism, state: Configuration, twist: ArrayLike, actuated_rates: ArrayLike) -> Array:
    """The velocity product term of the rate model's derivative: (dA/dt) t - (dB/dt) q_dot (and
    (dC/dt) t for a lower-mobility platform, stacked below), so that A t_dot = B q_ddot - it.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with an A/B rate model.
    state : Configuration (...)
        A closed configuration.
    twist : array_like (..., n_twist)
        The platform twist at ``state`` (``m.forward_rate(state, actuated_rates)``).
    actuated_rates : array_like (..., n_a)
        q_dot (m/s or rad/s).

    Returns
    -------
    ndarray (..., n_a + n_c)
        In the units of A t (m/s^2 for the distance rows of a Stewart platform).

    Raises
    ------
    UnsupportedOperationError
        ``m`` has no A/B rate model (a leg-Jacobian model such as ``sam``).
    SingularConfigurationError
        The loop-closure Jacobian is singular (the passive rates are not defined).

    Example
    -------
    >>> m = parakin.load("five_bar")
    >>> state = m.forward_pose([2.0, 1.0])
    >>> qd = np.array([0.3, -0.2])
    >>> velocity_product(m, state, m.forward_rate(state, qd), qd).shape
    (2,)
    """
    _require_rates(m)
    names = twist_names(m)
    t = bounded_vector(twist, "twist", names)
    qd = bounded_vector(actuated_rates, "actuated_rates", m.actuated_names)
    theta, passive = np.asarray(state.actuated, dtype=float), np.asarray(state.passive, dtype=float)
    pd = m.passive_rates(state, qd)
    inputs = [theta, passive, np.broadcast_to(m.params, theta.shape[:-1] + m.params.shape), t, qd, pd]
    shape = np.broadcast_shapes(*(x.shape[:-1] for x in inputs))
    count = int(np.prod(shape, dtype=np.int64))
    function = _velocity_product_function(m)
    size = function.size_out(0)[0]
    if count == 0:
        return np.zeros(shape + (size,))
    columns = [np.broadcast_to(x, shape + x.shape[-1:]).reshape(count, -1).T for x in inputs]
    mapped = function if count == 1 else function.map(count)
    out = np.asarray(mapped.call(columns)[0], dtype=float).reshape(size, count).T
    return out.reshape(shape + (size,))


def _require_rates(m: Mechanism) -> None:
    if m.manifest.capabilities.rates is None:
        raise UnsupportedOperationError(
            f"{m.name} has no A/B rate model (rate_jacobians): inverse dynamics needs one (a leg-Jacobian model "
            "needs the time derivative of its leg Jacobians, not yet available)"
        )


def platform_acceleration(
    m: Mechanism, state: Configuration, rates: ArrayLike, accelerations: ArrayLike
) -> tuple[Array, Array]:
    """The platform's twist and its time derivative from the actuated rates and accelerations:
    t = [A; C]^-1 [B q_dot; 0] and t_dot = [A; C]^-1 ([B q_ddot; 0] - velocity product).

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with an A/B rate model.
    state : Configuration (...)
        A closed configuration.
    rates, accelerations : array_like (..., n_a)
        q_dot (m/s, rad/s) and q_ddot (m/s^2, rad/s^2).

    Returns
    -------
    (twist, twist_rate) : ndarray (..., n_twist) each
        (v, w) and (a, alpha) of the origin of {P}, in {B}.

    Raises
    ------
    SingularConfigurationError
        At a type II singularity ([A; C] singular).
    UnsupportedOperationError
        Without an A/B rate model.

    Example
    -------
    >>> m = parakin.load("five_bar")
    >>> t, t_dot = platform_acceleration(m, m.forward_pose([2.0, 1.0]), [0.3, -0.2], [0.0, 1.0])
    """
    _require_rates(m)
    qd = bounded_vector(rates, "rates", m.actuated_names)
    qdd = bounded_vector(accelerations, "accelerations", m.actuated_names)
    jacobians = m.rate_jacobians(state)
    overall, name = overall_jacobian(jacobians["a"], jacobians.get("constraints"))
    extra = overall.shape[-2] - jacobians["b"].shape[-2]

    def padded(vector: Array) -> Array:
        return np.concatenate([vector, np.zeros(vector.shape[:-1] + (extra,))], axis=-1)

    twist = m._solve(overall, padded((jacobians["b"] @ qd[..., None])[..., 0]), name, "a type II singularity")
    product = velocity_product(m, state, twist, qd)
    right = padded((jacobians["b"] @ qdd[..., None])[..., 0]) - product
    twist_rate = m._solve(overall, right, name, "a type II singularity")
    return twist, twist_rate


def _full(m: Mechanism, vector: Array) -> tuple[Array, Array]:
    """A twist-component vector (..., n_twist) as its linear and angular parts (..., 3) each."""
    names = twist_names(m)
    full = np.zeros(vector.shape[:-1] + (6,))
    for column, name in enumerate(names):
        full[..., LEG_TWIST.index(name)] = vector[..., column]
    return full[..., :3], full[..., 3:]


def _gravity(gravity: ArrayLike) -> Array:
    g = bounded_vector(gravity, "gravity", ("gx", "gy", "gz"))
    if g.shape != (3,):
        raise BadInputError(f"gravity must be one vector (3,) in {{B}} (m/s^2), got shape {g.shape}")
    return g


def _platform(platform_inertia: RigidInertia | ArrayLike) -> RigidInertia:
    if isinstance(platform_inertia, RigidInertia):
        return platform_inertia
    return RigidInertia.from_parameters(platform_inertia)


def _no_legs(m: Mechanism, leg_inertias: object) -> None:
    if leg_inertias is not None:
        raise UnsupportedOperationError(
            f"{m.name}: leg inertias need the mechanism's bodies and joints (the joint graph), which its package "
            "does not describe yet; pass leg_inertias=None (massless legs)"
        )


def _efforts(m: Mechanism, state: Configuration, wrench: Array) -> tuple[Array, Array | None]:
    """Efforts (and constraint intensities) that apply ``wrench`` (..., 6) to the platform."""
    names = twist_names(m)
    external = -wrench[..., [LEG_TWIST.index(name) for name in names]]
    tau = actuator_forces(m, state, external)
    rates = m.manifest.capabilities.rates
    reactions = constraint_forces(m, state, external) if rates is not None and rates.constraints else None
    return tau, reactions


def inverse_dynamics(
    m: Mechanism,
    state: Configuration,
    rates: ArrayLike,
    accelerations: ArrayLike,
    *,
    platform_inertia: RigidInertia | ArrayLike,
    gravity: ArrayLike = STANDARD_GRAVITY,
    leg_inertias: object = None,
) -> InverseDynamics:
    """Actuator efforts that move the platform with the actuated rates and accelerations given
    (massless, frictionless legs): the platform's Newton-Euler wrench about the origin of {P},
    held through the rate model (see the module docstring).

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with an A/B rate model.
    state : Configuration (...)
        A closed configuration (``m.forward_pose``, an inverse branch, a mode).
    rates : array_like (..., n_a)
        Actuated rates q_dot (m/s, rad/s).
    accelerations : array_like (..., n_a)
        Actuated accelerations q_ddot (m/s^2, rad/s^2).
    platform_inertia : RigidInertia or array_like (10,)
        The platform's mass, centre and inertia in {P} (``rigid_inertia``), or its ten inertial
        parameters (``RigidInertia.parameters``).
    gravity : array_like (3,)
        Gravity in {B} (m/s^2); default ``STANDARD_GRAVITY`` (z up). For a planar mechanism give
        it in the plane of motion to see it.
    leg_inertias : None
        Legs are massless (only None is accepted until the joint graph describes the legs).

    Returns
    -------
    InverseDynamics
        ``efforts`` (..., n_a), ``constraint_forces`` (..., n_c) or None, ``twist``,
        ``twist_rate`` (..., n_twist), ``wrench`` (..., 6).

    Raises
    ------
    BadInputError
        Wrong shapes, non-finite values, an inertia no body has.
    SingularConfigurationError
        At a type II singularity.
    UnsupportedOperationError
        Without an A/B rate model, or with leg inertias.

    Example
    -------
    >>> m = parakin.load("five_bar")
    >>> body = rigid_inertia(1.0)
    >>> out = inverse_dynamics(m, m.forward_pose([2.0, 1.0]), [0.3, -0.2], [0.0, 1.0],
    ...                        platform_inertia=body, gravity=(0, -9.81, 0))
    >>> out.efforts.shape
    (2,)
    """
    _no_legs(m, leg_inertias)
    body = _platform(platform_inertia)
    g = _gravity(gravity)
    twist, twist_rate = platform_acceleration(m, state, rates, accelerations)
    _, w = _full(m, twist)  # v enters only through the closure's velocity product
    a, alpha = _full(m, twist_rate)
    rotation = np.asarray(state.rotation, dtype=float)
    r = np.einsum("...ij,j->...i", rotation, body.centre)
    inertia = rotation @ body.inertia @ np.swapaxes(rotation, -1, -2)  # about the centre, in {B}
    centre_acceleration = a + np.cross(alpha, r) + np.cross(w, np.cross(w, r))
    force = body.mass * (centre_acceleration - g)
    spin = np.einsum("...ij,...j->...i", inertia, alpha) + np.cross(w, np.einsum("...ij,...j->...i", inertia, w))
    moment = spin + np.cross(r, force)  # about O: the moment about the centre plus r x F
    wrench = np.concatenate([force, moment], axis=-1)
    tau, reactions = _efforts(m, state, wrench)
    return InverseDynamics(tau, reactions, twist, twist_rate, wrench)


def dynamics_regressor(
    m: Mechanism,
    state: Configuration,
    rates: ArrayLike,
    accelerations: ArrayLike,
    *,
    gravity: ArrayLike = STANDARD_GRAVITY,
    leg_inertias: object = None,
) -> Array:
    """Y (..., n_a, 10) with tau = Y theta for every platform: the efforts of ``inverse_dynamics``
    are linear in the platform's ten inertial parameters theta (``RigidInertia.parameters``,
    ``INERTIAL_PARAMETERS``; inertia about the origin of {P}).

    Parameters
    ----------
    m, state, rates, accelerations, gravity, leg_inertias
        As for ``inverse_dynamics``.

    Returns
    -------
    ndarray (..., n_a, 10)
        Column k: the efforts per unit of theta_k (units of tau / units of theta_k). Columns of
        parameters the motion cannot excite (a planar platform's out-of-plane inertia) are zero:
        identify only the base parameters (a column basis of Y stacked over samples).

    Raises
    ------
    As ``inverse_dynamics``.

    Example
    -------
    >>> m = parakin.load("five_bar")
    >>> y = dynamics_regressor(m, m.forward_pose([2.0, 1.0]), [0.3, -0.2], [0.0, 1.0], gravity=(0, -9.81, 0))
    >>> y.shape
    (2, 10)
    """
    _no_legs(m, leg_inertias)
    g = _gravity(gravity)
    twist, twist_rate = platform_acceleration(m, state, rates, accelerations)
    _, w = _full(m, twist)
    a, alpha = _full(m, twist_rate)
    rotation = np.asarray(state.rotation, dtype=float)
    batch = np.broadcast_shapes(a.shape[:-1], rotation.shape[:-2])
    columns = np.zeros(batch + (10, 6))
    columns[..., 0, :3] = a - g  # mass
    for j in range(3):  # first moments m c_j: h = R e_j
        h = np.broadcast_to(rotation[..., :, j], batch + (3,))
        columns[..., 1 + j, :3] = np.cross(alpha, h) + np.cross(w, np.cross(w, h))
        columns[..., 1 + j, 3:] = np.cross(h, a - g)
    for index, (i, j) in enumerate(_INERTIA_ENTRIES):  # I_O = R E R^T, E the symmetric unit entry
        unit = np.zeros((3, 3))
        unit[i, j] = unit[j, i] = 1.0
        tensor = rotation @ unit @ np.swapaxes(rotation, -1, -2)
        columns[..., 4 + index, 3:] = np.einsum("...ij,...j->...i", tensor, alpha) + np.cross(
            w, np.einsum("...ij,...j->...i", tensor, w)
        )
    state_each = Configuration(
        np.asarray(state.actuated, dtype=float)[..., None, :],
        np.asarray(state.passive, dtype=float)[..., None, :],
        np.asarray(state.pose, dtype=float)[..., None, :, :],
    )
    tau, _ = _efforts(m, state_each, columns)
    return np.asarray(np.swapaxes(tau, -1, -2), dtype=np.float64)


__all__ = [
    "INERTIAL_PARAMETERS",
    "STANDARD_GRAVITY",
    "InverseDynamics",
    "RigidInertia",
    "dynamics_regressor",
    "inverse_dynamics",
    "platform_acceleration",
    "rigid_inertia",
    "velocity_product",
]
