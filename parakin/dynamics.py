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
* Legs with mass (``leg_inertias``): the legs are the tree of serial chains ``parakin.mjcf.to_mjcf``
  writes (``leg_tree``: one body per link of the joint graph, a parallelogram as four bars, the
  loops cut where legs meet the platform), each link body with its own inertia in its frame
  (origin at its first joint, axes those of {B} at the home). At a state the tree's joints are
  placed by Newton from the home (the legs' branches of the home) with the actuated joints at
  their values and the platform at its pose; their rates and accelerations follow from the loop
  closures J qd = 0 and J qdd + J_dot qd = 0 (J_dot qd from each cut point's acceleration at
  qdd = 0), qd = Gamma q_dot with Gamma's actuated rows the identity; a recursive Newton-Euler
  pass over the tree (spatial vectors in {B} about its origin, gravity as the base's
  acceleration -g) gives the joints' efforts tau_tree, and the actuators' are Gamma^T tau_tree
  (tau_tree = S^T tau_a + J^T lambda: the cut forces lambda do no work on closed-chain motions).
  The legs' efforts add to the platform's (its inertia stays ``platform_inertia``, moved as
  above). ``constraint_forces`` is then None: a lower-mobility platform's constraint wrenches
  no longer split the legs' own inertial forces.
* A mechanism without an A/B rate model (a leg-Jacobian model such as sam's serial chains) is
  all tree: the platform is the tree's platform body (its frame {P}), its twist and twist rate
  those of that body, the efforts Gamma^T tau_tree with or without the legs' inertias.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from parakin.errors import BadInputError, ConvergenceError, SingularConfigurationError, UnsupportedOperationError
from parakin.pose import LEG_TWIST, as_array, axis_rotation, skew
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
        origin of the body frame (parallel axes): the vector ``dynamics_regressor`` multiplies.

        Returns
        -------
        ndarray (10,)
            kg, kg m, kg m^2 (``INERTIAL_PARAMETERS``).

        Raises
        ------
        Nothing: a ``RigidInertia`` is valid when built.

        Examples
        --------
        >>> rigid_inertia(2.0, (0.0, 0.0, 0.1)).parameters()[:4]
        array([2. , 0. , 0. , 0.2])
        """
        c = self.centre
        about_origin = self.inertia + self.mass * (float(c @ c) * np.eye(3) - np.outer(c, c))
        entries = [about_origin[i, j] for i, j in _INERTIA_ENTRIES]
        return np.array([self.mass, *(self.mass * c), *entries], dtype=float)

    @classmethod
    def from_parameters(cls, theta: ArrayLike) -> RigidInertia:
        """The body of inertial parameters ``theta`` (10,) (``parameters``'s order).

        Parameters
        ----------
        theta : array_like (10,)
            (m, m c, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz), I about the body frame's origin.

        Returns
        -------
        RigidInertia

        Raises
        ------
        BadInputError
            A wrong shape, a non-positive mass or an inertia that no body has.

        Examples
        --------
        >>> RigidInertia.from_parameters(rigid_inertia(2.0, (0, 0, 0.1)).parameters()).centre
        array([0. , 0. , 0.1])
        """
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

    Examples
    --------
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

    Examples
    --------
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

    Examples
    --------
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
    leg_inertias : None, float or mapping, optional
        None: massless legs. A link mass (kg): every link body of ``leg_tree(m)`` a uniform thin
        rod of that mass (``to_mjcf``'s ``link_mass``: the same robot). A mapping body name ->
        ``RigidInertia`` (in the body's frame) or a mass (a rod); bodies not named are massless
        (``link_inertias``).

    Returns
    -------
    InverseDynamics
        ``efforts`` (..., n_a), ``constraint_forces`` (..., n_c) or None (also with leg
        inertias), ``twist``, ``twist_rate`` (..., n_twist), ``wrench`` (..., 6): the
        platform's, the legs' efforts included in ``efforts`` only.

    Raises
    ------
    BadInputError
        Wrong shapes, non-finite values, an inertia no body has.
    SingularConfigurationError
        At a type II singularity.
    UnsupportedOperationError
        Without an A/B rate model and without a joint graph; with leg inertias (or without an
        A/B rate model), without a joint graph or with a leg the MJCF export does not write.
    ConvergenceError
        With leg inertias: the legs' joints could not be placed at ``state`` (not closed).

    Examples
    --------
    >>> m = parakin.load("five_bar")
    >>> body = rigid_inertia(1.0)
    >>> out = inverse_dynamics(m, m.forward_pose([2.0, 1.0]), [0.3, -0.2], [0.0, 1.0],
    ...                        platform_inertia=body, gravity=(0, -9.81, 0))
    >>> out.efforts.shape
    (2,)
    """
    body = _platform(platform_inertia)
    g = _gravity(gravity)
    if m.manifest.capabilities.rates is None:
        return _tree_inverse_dynamics(m, state, rates, accelerations, body, g, leg_inertias)
    legs = None if leg_inertias is None else _tree_bodies(m, leg_inertias)
    twist, twist_rate = platform_acceleration(m, state, rates, accelerations)
    _, w = _full(m, twist)  # v enters only through the closure's velocity product
    a, alpha = _full(m, twist_rate)
    wrench = _platform_wrench(body, np.asarray(state.rotation, dtype=float), w, a, alpha, g)
    tau, reactions = _efforts(m, state, wrench)
    if legs is not None:
        tau = tau + _legs(m, state, rates, accelerations, g, legs)
        reactions = None
    return InverseDynamics(tau, reactions, twist, twist_rate, wrench)


def _platform_wrench(body: RigidInertia, rotation: Array, w: Array, a: Array, alpha: Array, g: Array) -> Array:
    """(F, n) (..., 6) about the origin O of {P}, in {B}: Newton-Euler of the platform."""
    r = np.einsum("...ij,j->...i", rotation, body.centre)
    inertia = rotation @ body.inertia @ np.swapaxes(rotation, -1, -2)  # about the centre, in {B}
    centre_acceleration = a + np.cross(alpha, r) + np.cross(w, np.cross(w, r))
    force = body.mass * (centre_acceleration - g)
    spin = np.einsum("...ij,...j->...i", inertia, alpha) + np.cross(w, np.einsum("...ij,...j->...i", inertia, w))
    moment = spin + np.cross(r, force)  # about O: the moment about the centre plus r x F
    return np.concatenate([force, moment], axis=-1)


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
    ``INERTIAL_PARAMETERS``; inertia about the origin of {P}); with ``leg_inertias`` given, ten
    more columns per link body of ``leg_tree(m).links`` (each about its own frame's origin):
    theta = (platform's, ``leg_parameters(m, leg_inertias)``).

    Parameters
    ----------
    m, state, rates, accelerations, gravity, leg_inertias
        As for ``inverse_dynamics``.

    Returns
    -------
    ndarray (..., n_a, 10) or (..., n_a, 10 (1 + n_links)) with ``leg_inertias``
        Column k: the efforts per unit of theta_k (units of tau / units of theta_k). Columns of
        parameters the motion cannot excite (a planar platform's out-of-plane inertia) are zero:
        identify only the base parameters (a column basis of Y stacked over samples).

    Raises
    ------
    As ``inverse_dynamics``.

    Examples
    --------
    >>> m = parakin.load("five_bar")
    >>> y = dynamics_regressor(m, m.forward_pose([2.0, 1.0]), [0.3, -0.2], [0.0, 1.0], gravity=(0, -9.81, 0))
    >>> y.shape
    (2, 10)
    """
    g = _gravity(gravity)
    if leg_inertias is not None:
        link_inertias(m, leg_inertias)  # its values do not enter Y: only checked
    if m.manifest.capabilities.rates is None:
        return _tree_regressor_samples(m, state, rates, accelerations, g, leg_inertias is not None)
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
    platform = np.asarray(np.swapaxes(tau, -1, -2), dtype=np.float64)
    if leg_inertias is None:
        return platform
    legs = _legs(m, state, rates, accelerations, g, None)
    return np.concatenate([platform, legs], axis=-1)


# ------------------------------------------------------------------------ legs with mass
#: Newton's tolerance on the tree's loop gaps (m, relative to the mechanism's size) and its steps
TREE_TOLERANCE = 1e-13
TREE_ITERATIONS = 60
#: the residual (relative to the size) accepted once Newton's steps vanish: the platform's pose
#: and the actuated values of a state agree to the solver's precision, not exactly
TREE_ACCEPT = 1e-9


@dataclass(frozen=True)
class _Primitive:
    """One joint of a body in its order: a hinge or slide (one dof along ``axis``, in the body's
    frame as turned by the joints before it) or a ball (three dofs: the angular velocity in the
    frame after it). ``actuated``: the index of its actuated variable (-1: passive); ``ref``: that
    variable's value at the home (the joint turns by value - ref); ``held``: set from the
    platform's pose (the free platform's joints), not solved for."""

    kind: str
    axis: Array
    dof: int
    actuated: int
    ref: float
    held: bool


@dataclass(frozen=True)
class _TreeBody:
    """A body of the tree: its parent's index (-1: the world), its frame at the home relative to
    the parent's (``offset_rotation``, ``offset``), its joints, and whether it is the platform."""

    name: str
    parent: int
    offset_rotation: Array
    offset: Array
    primitives: tuple[_Primitive, ...]
    platform: bool


@dataclass(frozen=True)
class LegTree:
    """The tree of the legs' serial chains (the bodies ``parakin.mjcf.to_mjcf`` writes, without
    payload): ``bodies`` parents first, ``nv`` dofs, ``connects`` the loop cuts as pairs (body,
    local point) that coincide when the loops are closed, ``home_rods`` each link's default
    inertia per kg (a uniform thin rod along its segment, in its frame), ``rotates`` whether the
    platform's orientation is part of its pose (a point platform's is not), ``size`` the
    mechanism's size (m)."""

    bodies: tuple[_TreeBody, ...]
    nv: int
    connects: tuple[tuple[tuple[int, Array], tuple[int, Array]], ...]
    home_rods: dict[str, RigidInertia]
    rotates: bool
    size: float
    support: Array  # (n_bodies, nv) bool: the dofs between the world and each body

    @property
    def links(self) -> tuple[str, ...]:
        """The names of the link bodies (every body but the platform), in the tree's order."""
        return tuple(b.name for b in self.bodies if not b.platform)

    def platform_index(self) -> int:
        return next(i for i, b in enumerate(self.bodies) if b.platform)


_TREES: dict[tuple[Any, ...], LegTree] = {}


def leg_tree(m: Mechanism) -> LegTree:
    """The tree of ``m``'s legs as ``parakin.mjcf.to_mjcf`` builds it from the joint graph, laid
    out at the home (cached per package and parameters).

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism whose package carries its joint graph.

    Returns
    -------
    LegTree

    Raises
    ------
    UnsupportedOperationError
        No joint graph, or a leg the export does not write (``parakin.mjcf.to_mjcf``: a planar
        joint at the platform, a serial chain of other joints than R and P).
    ConvergenceError, SingularConfigurationError
        The manifest's home does not close at the mechanism's parameters.

    Examples
    --------
    >>> leg_tree(parakin.load("five_bar")).links
    ('leg1_link1', 'leg1_link2', 'leg2_link1', 'leg2_link2')
    """
    from parakin import mjcf

    key = (str(m.package.path), tuple(np.asarray(m.params, dtype=float).tolist()), m.manifest.joints)
    with _PRODUCTS_LOCK:
        if key in _TREES:
            return _TREES[key]
    graph = m.manifest.joints
    if graph is None:
        raise UnsupportedOperationError(
            f"{m.name}: leg inertias need the mechanism's bodies and joints (the manifest's 'joints' field), which "
            "its package does not carry; regenerate it, or pass leg_inertias=None (massless legs)"
        )
    try:
        model, _, geometry = mjcf._build(m, graph, None, 1.0, 0.0, 1.0, 0.0)
    except (ConvergenceError, SingularConfigurationError) as error:
        raise type(error)(
            f"{m.name}: leg inertias need the legs laid out at the manifest's home, which does not close at these "
            f"parameters ({error.__cause__ or error}); load the mechanism with parameters whose home closes"
        ) from error
    order = _parents_first(model.bodies)
    actuated_index = {name: i for i, name in enumerate(m.actuated_names)}
    bodies: list[_TreeBody] = []
    new_index: dict[str, int] = {}
    frames: dict[str, tuple[Array, Array]] = {}
    rods: dict[str, RigidInertia] = {}
    nv = 0
    for i in order:
        body = model.bodies[i]
        rotation, origin = np.asarray(body.rotation, dtype=float), np.asarray(body.position, dtype=float)
        frames[body.name] = (rotation, origin)
        if body.parent is None:
            parent, parent_rotation, parent_origin = -1, np.eye(3), np.zeros(3)
        else:
            parent = new_index[body.parent]
            parent_rotation, parent_origin = frames[body.parent]
        primitives: list[_Primitive] = []
        for joint in body.joints:
            held = joint.kind == "free"
            if joint.kind in ("hinge", "slide"):
                assert joint.axis is not None
                slot = actuated_index[joint.name] if joint.actuated else -1
                axis = rotation.T @ np.asarray(joint.axis, dtype=float)
                primitives.append(_Primitive(joint.kind, axis, nv, slot, float(joint.ref), False))
                nv += 1
                continue
            if joint.kind == "free":  # three slides along {B}'s axes, then a ball
                for e in np.eye(3):
                    primitives.append(_Primitive("slide", rotation.T @ e, nv, -1, 0.0, held))
                    nv += 1
            primitives.append(_Primitive("ball", np.zeros(3), nv, -1, 0.0, held))
            nv += 3
        platform = body.name == "platform"
        bodies.append(
            _TreeBody(
                body.name, parent, parent_rotation.T @ rotation, parent_rotation.T @ (origin - parent_origin),
                tuple(primitives), platform,
            )
        )  # fmt: skip
        new_index[body.name] = len(bodies) - 1
        if not platform and body.centre is not None and body.inertia is not None:
            rods[body.name] = RigidInertia(
                float(body.mass), rotation.T @ (body.centre - origin), rotation.T @ body.inertia @ rotation
            )
    sites = {name: (body.name, point) for body in model.bodies for name, point in body.sites}
    connects = []
    for _, first, second in model.connects:
        pair = []
        for site in (first, second):
            owner, point = sites[site]
            rotation, origin = frames[owner]
            pair.append((new_index[owner], rotation.T @ (np.asarray(point, dtype=float) - origin)))
        connects.append((pair[0], pair[1]))
    support = np.zeros((len(bodies), nv), dtype=bool)
    for i, node in enumerate(bodies):
        if node.parent >= 0:
            support[i] = support[node.parent]
        for primitive in node.primitives:
            support[i, primitive.dof : primitive.dof + (3 if primitive.kind == "ball" else 1)] = True
    twist = m.manifest.capabilities.rates.twist if m.manifest.capabilities.rates is not None else LEG_TWIST
    points = [np.zeros(3), geometry.origin] + [np.asarray(b.position, dtype=float) for b in model.bodies]
    size = max(float(np.linalg.norm(p)) for p in points) or 1.0
    tree = LegTree(tuple(bodies), nv, tuple(connects), rods, any(n.startswith("w") for n in twist), size, support)
    with _PRODUCTS_LOCK:
        _TREES[key] = tree
    return tree


def _parents_first(bodies: Any) -> list[int]:
    names = {b.name: i for i, b in enumerate(bodies)}
    placed: list[int] = []
    seen: set[str] = set()

    def visit(i: int) -> None:
        body = bodies[i]
        if body.name in seen:
            return
        if body.parent is not None:
            visit(names[body.parent])
        seen.add(body.name)
        placed.append(i)

    for i in range(len(bodies)):
        visit(i)
    return placed


def _cross(a: Array, b: Array) -> Array:
    """a x b of two 3-vectors (numpy's cross costs ~20x more on one pair)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _exp(vector: Array) -> Array:
    angle = float(np.linalg.norm(vector))
    return np.eye(3) if angle == 0 else axis_rotation(vector / angle, angle)


@dataclass
class _TreeState:
    """Joint values of a tree: ``scalars`` (nv,) (hinge angles from the home, slide travels;
    the entries of balls unused) and ``balls`` dof -> rotation (3, 3)."""

    scalars: Array
    balls: dict[int, Array]

    def copy(self) -> _TreeState:
        return _TreeState(self.scalars.copy(), {k: v.copy() for k, v in self.balls.items()})


def _home_state(tree: LegTree) -> _TreeState:
    balls = {p.dof: np.eye(3) for b in tree.bodies for p in b.primitives if p.kind == "ball"}
    return _TreeState(np.zeros(tree.nv), balls)


def _placements(tree: LegTree, q: _TreeState) -> tuple[list[tuple[Array, Array]], Array]:
    """Each body's frame (rotation, origin) in {B}, and the dofs' motion axes S (6, nv) as
    Plucker vectors (w; v at the origin of {B}) in {B}."""
    frames: list[tuple[Array, Array]] = []
    axes = np.zeros((6, tree.nv))
    for body in tree.bodies:
        if body.parent < 0:
            rotation, origin = body.offset_rotation.copy(), body.offset.copy()
        else:
            parent_rotation, parent_origin = frames[body.parent]
            rotation, origin = parent_rotation @ body.offset_rotation, parent_rotation @ body.offset + parent_origin
        for p in body.primitives:
            if p.kind == "hinge":
                u = rotation @ p.axis
                axes[:3, p.dof], axes[3:, p.dof] = u, _cross(origin, u)
                rotation = rotation @ axis_rotation(p.axis, q.scalars[p.dof])
            elif p.kind == "slide":
                u = rotation @ p.axis
                axes[3:, p.dof] = u
                origin = origin + q.scalars[p.dof] * u
            else:
                rotation = rotation @ q.balls[p.dof]
                for k in range(3):
                    axes[:3, p.dof + k], axes[3:, p.dof + k] = rotation[:, k], _cross(origin, rotation[:, k])
        frames.append((rotation, origin))
    return frames, axes


def _cross_motion(v: Array, u: Array) -> Array:
    """v x u for motion vectors (w; v0)."""
    return np.concatenate([_cross(v[:3], u[:3]), _cross(v[:3], u[3:]) + _cross(v[3:], u[:3])])


def _cross_force(v: Array, f: Array) -> Array:
    """v x* f for a motion vector v = (w; v0) and a force f = (n0; F)."""
    return np.concatenate([_cross(v[:3], f[:3]) + _cross(v[3:], f[3:]), _cross(v[:3], f[3:])])


def _motion(tree: LegTree, axes: Array, qd: Array, qdd: Array, base: Array) -> tuple[list[Array], list[Array]]:
    """Each body's spatial velocity V and acceleration A (Plucker, at the origin of {B}):
    A = A_parent + S qdd + V_before x S qd joint by joint; ``base`` the world's acceleration
    (-g for gravity)."""
    velocities: list[Array] = []
    accelerations: list[Array] = []
    for body in tree.bodies:
        v = velocities[body.parent].copy() if body.parent >= 0 else np.zeros(6)
        a = accelerations[body.parent].copy() if body.parent >= 0 else base.copy()
        for p in body.primitives:
            span = slice(p.dof, p.dof + (3 if p.kind == "ball" else 1))
            moved = axes[:, span] @ qd[span]
            a = a + axes[:, span] @ qdd[span] + _cross_motion(v, moved)
            v = v + moved
        velocities.append(v)
        accelerations.append(a)
    return velocities, accelerations


def _point_jacobian(tree: LegTree, axes: Array, body: int, point: Array) -> Array:
    """d x / d qd (3, nv) of the point ``point`` (in {B}) fixed to ``body``: v0 + w x point."""
    masked = np.where(tree.support[body], axes, 0.0)
    return np.asarray(masked[3:] - skew(point) @ masked[:3])


def _point_acceleration(v: Array, a: Array, point: Array) -> Array:
    """The acceleration of a point of a body of spatial velocity v and acceleration a."""
    velocity = v[3:] + _cross(v[:3], point)
    return np.asarray(a[3:] + _cross(a[:3], point) + _cross(v[:3], velocity))


def _closure(
    tree: LegTree, frames: list[tuple[Array, Array]], axes: Array
) -> tuple[Array, Array, list[tuple[Array, Array]]]:
    """The loop gaps (3 k,), their Jacobian (3 k, nv) and the cut points in {B}."""
    gaps, rows, points = [], [], []
    for (b1, x1), (b2, x2) in tree.connects:
        p1 = frames[b1][0] @ x1 + frames[b1][1]
        p2 = frames[b2][0] @ x2 + frames[b2][1]
        gaps.append(p1 - p2)
        rows.append(_point_jacobian(tree, axes, b1, p1) - _point_jacobian(tree, axes, b2, p2))
        points.append((p1, p2))
    return np.concatenate(gaps), np.concatenate(rows), points


def _assemble(tree: LegTree, actuated: Array, pose: Array, start: _TreeState) -> _TreeState | None:
    """The tree's joint values at a closed configuration: the actuated joints at ``actuated``, a
    free platform at ``pose`` (4, 4), every other joint by Gauss-Newton from ``start`` so that the
    loops close (and a platform ending a leg reaches ``pose``). None if Newton does not converge."""
    q = start.copy()
    platform = tree.platform_index()
    solved = np.ones(tree.nv, dtype=bool)
    free = False
    for body in tree.bodies:
        for p in body.primitives:
            if p.actuated >= 0:
                q.scalars[p.dof] = actuated[p.actuated] - p.ref
                solved[p.dof] = False
            elif p.held:
                free = True
                if p.kind == "ball":
                    q.balls[p.dof] = body.offset_rotation.T @ pose[:3, :3]
                    solved[p.dof : p.dof + 3] = False
                else:
                    solved[p.dof] = False
    if free:  # the slides along {B}'s axes from the home origin
        body = tree.bodies[platform]
        slides = [p for p in body.primitives if p.kind == "slide"]
        travel = pose[:3, 3] - body.offset
        for p, e in zip(slides, np.eye(3), strict=True):
            q.scalars[p.dof] = float(travel @ e)
    tolerance = TREE_TOLERANCE * tree.size
    for _ in range(TREE_ITERATIONS):
        frames, axes = _placements(tree, q)
        gaps, jacobian, _ = _closure(tree, frames, axes)
        rows, blocks = [gaps], [jacobian]
        if not free:
            rotation, origin = frames[platform]
            rows.append(origin - pose[:3, 3])
            blocks.append(_point_jacobian(tree, axes, platform, origin))
            if tree.rotates:
                turn = rotation @ pose[:3, :3].T
                rows.append(0.5 * np.array([turn[2, 1] - turn[1, 2], turn[0, 2] - turn[2, 0], turn[1, 0] - turn[0, 1]]))
                blocks.append(np.where(tree.support[platform], axes, 0.0)[:3])
        value = np.concatenate(rows)
        if float(np.abs(value).max(initial=0.0)) <= tolerance:
            return q
        if not np.isfinite(value).all():
            return None
        step = np.linalg.lstsq(np.concatenate(blocks)[:, solved], -value, rcond=None)[0]
        largest = float(np.abs(step).max(initial=0.0))
        if largest <= TREE_TOLERANCE and float(np.abs(value).max()) <= TREE_ACCEPT * tree.size:
            return q  # least squares converged: a state known to ~1e-13 leaves that residual
        if largest > 0.5:
            step *= 0.5 / largest
        full = np.zeros(tree.nv)
        full[solved] = step
        for dof in q.balls:  # a ball turns by the step's angular velocity in its own frame
            q.balls[dof] = q.balls[dof] @ _exp(full[dof : dof + 3])
            full[dof : dof + 3] = 0.0
        q.scalars = q.scalars + full
    return None


@dataclass(frozen=True)
class _TreeMotion:
    """The tree at one sample: frames, axes S, the closed-chain basis Gamma (nv, n_a) with
    qd = Gamma q_dot_a, qd and qdd, each body's V and A (gravity in A)."""

    frames: list[tuple[Array, Array]]
    axes: Array
    gamma: Array
    qd: Array
    qdd: Array
    velocities: list[Array]
    accelerations: list[Array]


def _tree_motion(
    tree: LegTree, m: Mechanism, q: _TreeState, rates: Array, accelerations: Array, gravity: Array
) -> _TreeMotion:
    """Rates and accelerations of every joint from the actuated ones and the loop closures
    (J qd = 0, J qdd + J_dot qd = 0), then every body's motion."""
    frames, axes = _placements(tree, q)
    _, jacobian, points = _closure(tree, frames, axes)
    actuated = np.zeros(len(m.actuated_names), dtype=np.intp)
    for body in tree.bodies:
        for p in body.primitives:
            if p.actuated >= 0:
                actuated[p.actuated] = p.dof
    passive = np.setdiff1d(np.arange(tree.nv), actuated)
    columns = jacobian[:, passive]
    sigma = np.linalg.svd(columns, compute_uv=False)
    if sigma.size and not sigma[-1] > 1e-10 * max(float(sigma[0]), 1e-300):
        raise SingularConfigurationError(
            f"{m.name}: the legs' loop Jacobian has rank < {passive.size} in its passive joints (smallest singular "
            f"value {sigma[-1]:.3g} of {sigma[0]:.3g}): the actuated values do not determine the legs here"
        )
    gamma = np.zeros((tree.nv, actuated.size))
    gamma[actuated] = np.eye(actuated.size)
    gamma[passive] = np.linalg.lstsq(columns, -jacobian[:, actuated], rcond=None)[0]
    qd = gamma @ rates
    velocities, bias = _motion(tree, axes, qd, np.zeros(tree.nv), np.zeros(6))
    drift = np.concatenate(
        [
            _point_acceleration(velocities[b1], bias[b1], p1) - _point_acceleration(velocities[b2], bias[b2], p2)
            for ((b1, _), (b2, _)), (p1, p2) in zip(tree.connects, points, strict=True)
        ]
    )
    qdd = np.zeros(tree.nv)
    qdd[actuated] = accelerations
    qdd[passive] = np.linalg.lstsq(columns, -jacobian[:, actuated] @ accelerations - drift, rcond=None)[0]
    velocities, body_accelerations = _motion(tree, axes, qd, qdd, np.concatenate([np.zeros(3), -gravity]))
    return _TreeMotion(frames, axes, gamma, qd, qdd, velocities, body_accelerations)


def _spatial_inertia_times(mass: float, centre: Array, inertia: Array, motion: Array) -> Array:
    """I_b (w; v0) for a body of ``mass``, centre ``centre`` and inertia about it ``inertia``
    ({B}): (I_c w + c x m v_c; m v_c), v_c = v0 + w x c."""
    w, v = motion[:3], motion[3:]
    velocity = mass * (v + _cross(w, centre))
    return np.concatenate([inertia @ w + _cross(centre, velocity), velocity])


def _tree_efforts(tree: LegTree, motion: _TreeMotion, bodies: list[RigidInertia | None]) -> Array:
    """Recursive Newton-Euler: each body's force f = I A + V x* I V (in {B}, about its origin),
    summed over each subtree, projected on the joints' axes; the actuated efforts Gamma^T tau."""
    forces = [np.zeros(6) for _ in tree.bodies]
    for i, body in enumerate(bodies):
        if body is None:
            continue
        rotation, origin = motion.frames[i]
        centre = rotation @ body.centre + origin
        inertia = rotation @ body.inertia @ rotation.T
        v, a = motion.velocities[i], motion.accelerations[i]
        momentum = _spatial_inertia_times(body.mass, centre, inertia, v)
        forces[i] = _spatial_inertia_times(body.mass, centre, inertia, a) + _cross_force(v, momentum)
    generalised = np.zeros(tree.nv)
    for i in range(len(tree.bodies) - 1, -1, -1):  # children after their parents: leaves first
        node = tree.bodies[i]
        for p in node.primitives:
            span = slice(p.dof, p.dof + (3 if p.kind == "ball" else 1))
            generalised[span] = motion.axes[:, span].T @ forces[i]
        if node.parent >= 0:
            forces[node.parent] = forces[node.parent] + forces[i]
    return np.asarray(motion.gamma.T @ generalised, dtype=np.float64)


def _local_inertia_times(theta: Array, w: Array, v: Array) -> tuple[Array, Array]:
    """I (w; v) in a body's frame at its origin for inertial parameters theta (10,) (mass m,
    first moment h = m c, inertia I_O about the origin): (I_O w + h x v; m v - h x w)."""
    tensor = np.zeros((3, 3))
    for value, (i, j) in zip(theta[4:], _INERTIA_ENTRIES, strict=True):
        tensor[i, j] = tensor[j, i] = value
    first = theta[1:4]
    return tensor @ w + _cross(first, v), theta[0] * v - _cross(first, w)


def _body_regressor(motion: _TreeMotion, index: int) -> Array:
    """(6, 10): the force f = I A + V x* I V of body ``index`` (in {B}, about the origin of {B})
    per unit of each of its ten inertial parameters (in its frame, about its origin)."""
    rotation, origin = motion.frames[index]
    v, a = motion.velocities[index], motion.accelerations[index]
    # in the body's frame, at its origin
    w_l, alpha_l = rotation.T @ v[:3], rotation.T @ a[:3]
    v_l = rotation.T @ (v[3:] + _cross(v[:3], origin))
    a_l = rotation.T @ (a[3:] + _cross(a[:3], origin))
    out = np.zeros((6, 10))
    for k in range(10):
        theta = np.zeros(10)
        theta[k] = 1.0
        n_v, f_v = _local_inertia_times(theta, w_l, v_l)
        n_a, f_a = _local_inertia_times(theta, alpha_l, a_l)
        moment = n_a + _cross(w_l, n_v) + _cross(v_l, f_v)
        force = f_a + _cross(w_l, f_v)
        world_force = rotation @ force
        out[:3, k] = rotation @ moment + _cross(origin, world_force)
        out[3:, k] = world_force
    return out


def _tree_regressor(tree: LegTree, motion: _TreeMotion, chosen: list[int]) -> Array:
    """(n_a, 10 len(chosen)): Gamma^T J_b^T of each chosen body's force per inertial parameter."""
    blocks = []
    for i in chosen:
        masked = np.where(tree.support[i], motion.axes, 0.0)
        blocks.append(motion.gamma.T @ masked.T @ _body_regressor(motion, i))
    return np.concatenate(blocks, axis=1) if blocks else np.zeros((motion.gamma.shape[1], 0))


def link_inertias(m: Mechanism, leg_inertias: object) -> dict[str, RigidInertia | None]:
    """Every link body's inertia (None: massless) from the forms ``inverse_dynamics`` accepts.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with a joint graph.
    leg_inertias : float or mapping
        A mass (kg): every link a uniform thin rod of that mass along its segment (a body of no
        length: a point with a 1 cm radius of gyration), the meaning of ``to_mjcf``'s
        ``link_mass``; or a mapping body name -> ``RigidInertia`` (in the body's frame: origin at
        its first joint, axes those of {B} at the home, as ``to_mjcf`` writes it) or a mass (that
        body a rod of that mass); bodies not named are massless. ``to_mjcf``'s ``link_mass``
        takes the same forms.

    Returns
    -------
    dict
        Body name -> RigidInertia or None, in ``leg_tree(m).links`` order.

    Raises
    ------
    BadInputError
        A negative or non-finite mass, a body name the tree lacks (the names listed), a value of
        another kind.
    UnsupportedOperationError
        As ``leg_tree``.

    Examples
    --------
    >>> link_inertias(parakin.load("five_bar"), 0.5)["leg1_link1"].mass
    0.5
    """
    tree = leg_tree(m)
    links = tree.links

    def rod(name: str, mass: object) -> RigidInertia | None:
        value = float(mass) if isinstance(mass, int | float) and not isinstance(mass, bool) else float("nan")
        if not (np.isfinite(value) and value >= 0):
            raise BadInputError(f"the mass of {name} must be a finite number >= 0 (kg), got {mass!r}")
        if value == 0:
            return None
        base = tree.home_rods[name]
        return RigidInertia(value, base.centre.copy(), base.inertia * value)

    if isinstance(leg_inertias, Mapping):
        unknown = sorted(set(map(str, leg_inertias)) - set(links))
        if unknown:
            raise BadInputError(
                f"leg_inertias names {unknown}, which are not link bodies of {m.name} (bodies: {list(links)})"
            )
        out: dict[str, RigidInertia | None] = dict.fromkeys(links)
        for name, value in leg_inertias.items():
            if isinstance(value, RigidInertia):
                out[name] = value
            elif isinstance(value, int | float) and not isinstance(value, bool):
                out[name] = rod(name, value)
            else:
                raise BadInputError(f"the inertia of {name} must be a mass (kg) or a RigidInertia, got {value!r}")
        return out
    if isinstance(leg_inertias, int | float) and not isinstance(leg_inertias, bool):
        return {name: rod(name, leg_inertias) for name in links}
    raise BadInputError(
        f"leg_inertias must be None (massless legs), a link mass in kg or a mapping body name -> RigidInertia, "
        f"got {type(leg_inertias).__name__}"
    )


def leg_parameters(m: Mechanism, leg_inertias: object) -> Array:
    """theta_legs (10 n_links,): each link body's ten inertial parameters (``RigidInertia.parameters``,
    zero for a massless one) in ``leg_tree(m).links`` order: the columns ``dynamics_regressor``
    adds after the platform's ten with ``leg_inertias``.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with a joint graph.
    leg_inertias : float or mapping
        As ``link_inertias``.

    Returns
    -------
    ndarray (10 n_links,)
        (m, m c, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz) per link, in its frame, I about its origin.

    Raises
    ------
    BadInputError, UnsupportedOperationError
        As ``link_inertias``.

    Examples
    --------
    >>> leg_parameters(parakin.load("five_bar"), 1.0).shape
    (40,)
    """
    bodies = link_inertias(m, leg_inertias)
    return np.concatenate([np.zeros(10) if b is None else b.parameters() for b in bodies.values()])


def _samples(
    m: Mechanism, state: Configuration, rates: ArrayLike, accelerations: ArrayLike
) -> tuple[tuple[int, ...], Array, Array, Array, Array]:
    qd = bounded_vector(rates, "rates", m.actuated_names)
    qdd = bounded_vector(accelerations, "accelerations", m.actuated_names)
    actuated, pose = np.asarray(state.actuated, dtype=float), np.asarray(state.pose, dtype=float)
    shape = np.broadcast_shapes(actuated.shape[:-1], pose.shape[:-2], qd.shape[:-1], qdd.shape[:-1])
    n = len(m.actuated_names)

    def flat(x: Array, tail: tuple[int, ...]) -> Array:
        return np.broadcast_to(x, shape + tail).reshape((-1, *tail))

    return shape, flat(actuated, (n,)), flat(pose, (4, 4)), flat(qd, (n,)), flat(qdd, (n,))


def _tree_states(m: Mechanism, tree: LegTree, actuated: Array, poses: Array) -> list[_TreeState]:
    """The tree's joint values at each sample: Newton from the home (the legs' branches of the
    home), else from the sample before; ConvergenceError if neither closes the loops."""
    home = _home_state(tree)
    out: list[_TreeState] = []
    for k in range(actuated.shape[0]):
        q = _assemble(tree, actuated[k], poses[k], home)
        if q is None and out:
            q = _assemble(tree, actuated[k], poses[k], out[-1])
        if q is None:
            raise ConvergenceError(
                f"{m.name}: the legs' joints could not be placed at the actuated values {actuated[k].tolist()} and "
                "this platform pose (Newton from the home did not close the loops): is it a closed configuration?",
            )
        out.append(q)
    return out


def _legs(
    m: Mechanism, state: Configuration, rates: ArrayLike, accelerations: ArrayLike, gravity: Array,
    bodies: list[RigidInertia | None] | None,
) -> Array:  # fmt: skip
    """The legs' efforts (..., n_a) (``bodies`` per tree body), or with ``bodies`` None their
    regressor (..., n_a, 10 n_links)."""
    tree = leg_tree(m)
    shape, actuated, poses, qd, qdd = _samples(m, state, rates, accelerations)
    links = [i for i, body in enumerate(tree.bodies) if not body.platform]
    out = []
    for k, q in enumerate(_tree_states(m, tree, actuated, poses)):
        motion = _tree_motion(tree, m, q, qd[k], qdd[k], gravity)
        out.append(_tree_efforts(tree, motion, bodies) if bodies is not None else _tree_regressor(tree, motion, links))
    n = len(m.actuated_names)
    tail = (n,) if bodies is not None else (n, 10 * len(links))
    return np.asarray(out, dtype=float).reshape(shape + tail)


def _tree_bodies(m: Mechanism, leg_inertias: object) -> list[RigidInertia | None]:
    named = link_inertias(m, leg_inertias)
    return [None if body.platform else named[body.name] for body in leg_tree(m).bodies]


# ----------------------------------------------------- a mechanism without an A/B rate model
def _whole_tree(m: Mechanism) -> LegTree:
    """The tree of a mechanism without an A/B rate model, which carries its platform too."""
    try:
        return leg_tree(m)
    except UnsupportedOperationError as error:
        raise UnsupportedOperationError(
            f"{m.name} has no A/B rate model (rate_jacobians), and its legs cannot be made a tree either ({error}): "
            "inverse dynamics needs one of them"
        ) from error


def _tree_inverse_dynamics(
    m: Mechanism, state: Configuration, rates: ArrayLike, accelerations: ArrayLike, body: RigidInertia, g: Array,
    leg_inertias: object,
) -> InverseDynamics:  # fmt: skip
    """``inverse_dynamics`` on the tree alone (the platform one of its bodies, in {P}): the
    efforts Gamma^T tau_tree, the platform's twist and its rate from the tree's closure."""
    tree = _whole_tree(m)
    legs = None if leg_inertias is None else _tree_bodies(m, leg_inertias)
    bodies = [body if node.platform else (None if legs is None else legs[i]) for i, node in enumerate(tree.bodies)]
    shape, actuated, poses, qd, qdd = _samples(m, state, rates, accelerations)
    platform = tree.platform_index()
    efforts, twists, rates_of_twist = [], [], []
    for k, q in enumerate(_tree_states(m, tree, actuated, poses)):
        motion = _tree_motion(tree, m, q, qd[k], qdd[k], g)
        efforts.append(_tree_efforts(tree, motion, bodies))
        v, a = motion.velocities[platform], motion.accelerations[platform]
        origin = poses[k][:3, 3]
        velocity = v[3:] + _cross(v[:3], origin)  # of the origin of {P}
        acceleration = a[3:] + g + _cross(a[:3], origin) + _cross(v[:3], velocity)  # gravity taken out of A
        twists.append(np.concatenate([velocity, v[:3]]))
        rates_of_twist.append(np.concatenate([acceleration, a[:3]]))
    n = len(m.actuated_names)
    twist = np.asarray(twists, dtype=float).reshape(shape + (6,))
    twist_rate = np.asarray(rates_of_twist, dtype=float).reshape(shape + (6,))
    rotation = poses[:, :3, :3].reshape(shape + (3, 3))
    wrench = _platform_wrench(body, rotation, twist[..., 3:], twist_rate[..., :3], twist_rate[..., 3:], g)
    return InverseDynamics(np.asarray(efforts, dtype=float).reshape(shape + (n,)), None, twist, twist_rate, wrench)


def _tree_regressor_samples(
    m: Mechanism, state: Configuration, rates: ArrayLike, accelerations: ArrayLike, g: Array, legs: bool
) -> Array:
    """``dynamics_regressor`` on the tree alone: the platform body's ten columns, then each
    link's with ``legs``."""
    tree = _whole_tree(m)
    chosen = [tree.platform_index()] + ([i for i, node in enumerate(tree.bodies) if not node.platform] if legs else [])
    shape, actuated, poses, qd, qdd = _samples(m, state, rates, accelerations)
    out = [
        _tree_regressor(tree, _tree_motion(tree, m, q, qd[k], qdd[k], g), chosen)
        for k, q in enumerate(_tree_states(m, tree, actuated, poses))
    ]
    return np.asarray(out, dtype=float).reshape(shape + (len(m.actuated_names), 10 * len(chosen)))


__all__ = [
    "INERTIAL_PARAMETERS",
    "LegTree",
    "STANDARD_GRAVITY",
    "InverseDynamics",
    "RigidInertia",
    "dynamics_regressor",
    "inverse_dynamics",
    "leg_parameters",
    "leg_tree",
    "link_inertias",
    "platform_acceleration",
    "rigid_inertia",
    "velocity_product",
]
