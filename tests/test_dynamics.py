"""parakin.dynamics: inverse dynamics of the platform through the generated rate model.

Claims, each against an independent source:
* the closure's second-order kinematics (``platform_acceleration``) equals the analytic
  acceleration of a Stewart platform moved along a closed-form pose trajectory (leg lengths,
  rates and accelerations from the leg vectors d_i = R b_i + p - A_i), and fourth-order central
  differences of ``forward_rate`` along an actuated trajectory for every other kind of platform;
* with massless legs the efforts are the statics (``actuator_forces``) of the d'Alembert wrench of
  the platform, written here about its centre of mass and moved to the origin of {P};
* tau = Y theta for random bodies and states (a batch);
* power balance along a trajectory: tau . q_dot = dK/dt - m g . v_c, dK/dt by central differences
  of the kinetic energy computed from ``forward_rate``.
The engines' checks (MuJoCo, Pinocchio) are in tests/test_mujoco_bridge.py.
"""

import numpy as np
import pytest

import parakin
from parakin.dynamics import (
    INERTIAL_PARAMETERS,
    RigidInertia,
    dynamics_regressor,
    inverse_dynamics,
    platform_acceleration,
    rigid_inertia,
)
from parakin.errors import BadInputError, UnsupportedOperationError

# one mechanism of each platform kind with an A/B rate model, and prs3 with constraint wrenches
KINDS = ["five_bar", "planar_3rpr", "delta", "spm", "stewart", "prs3"]
GRAVITY = np.array([0.3, -9.81, -0.2])  # in the plane of the planar ones too, and off the axes


def home(m: parakin.Mechanism) -> parakin.Configuration:
    return m.forward_pose(m.home_actuated, guess=m.home_passive)


def twist6(m, vector):
    out = np.zeros(vector.shape[:-1] + (6,))
    for column, name in enumerate(m.manifest.capabilities.rates.twist):
        out[..., ("vx", "vy", "vz", "wx", "wy", "wz").index(name)] = vector[..., column]
    return out


def motion(m, rng):
    """A smooth actuated trajectory q(t) = q0 + qd t + qdd t^2 / 2 + j t^3 / 6 from the home."""
    n = len(m.actuated_names)
    scale = np.array([1.0 if v.revolute else 0.1 for v in m.manifest.actuated])
    qd, qdd, jerk = (rng.normal(size=n) * scale * f for f in (0.5, 1.0, 2.0))

    def at(t):
        return (
            m.home_actuated + qd * t + qdd * t**2 / 2 + jerk * t**3 / 6,
            qd + qdd * t + jerk * t**2 / 2,
            qdd + jerk * t,
        )

    return at


def body(rng) -> RigidInertia:
    principal = rng.uniform(0.5, 1.0, 3)
    principal[2] = min(principal[2], principal[0] + principal[1])
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return rigid_inertia(rng.uniform(1, 5), rng.normal(size=3) * 0.05, q @ np.diag(principal) @ q.T * 0.05)


def dalembert(platform, rotation, w, a, alpha, gravity):
    """(F, n_O) in {B}: Newton at the centre, Euler's equations in the body frame
    (I w_b' + w_b x I w_b, w_b = R^T w), the moment moved to the origin of {P}."""
    r = rotation @ platform.centre
    force = platform.mass * (a + np.cross(alpha, r) + np.cross(w, np.cross(w, r)) - gravity)
    w_b, alpha_b = rotation.T @ w, rotation.T @ alpha
    euler = platform.inertia @ alpha_b + np.cross(w_b, platform.inertia @ w_b)
    return np.concatenate([force, rotation @ euler + np.cross(r, force)])


def test_stewart_acceleration_equals_closed_form_motion():
    """Pose p(t) = p0 + u sin(2t + 0.7), R(t) = exp(phi(t) n) R0: v, w, a, alpha and the leg lengths'
    rates and accelerations in closed form; platform_acceleration(l_dot, l_ddot) must return
    (v, w) and (a, alpha) to 1e-10 relative at 8 instants, and the efforts the statics of the
    closed-form motion's d'Alembert wrench to 1e-10."""
    m = parakin.load("stewart", backend="numpy")
    start = home(m)
    base = np.array([[m.parameters[f"base_{c}{i}"] for c in "xyz"] for i in range(1, 7)])
    plat = np.array([[m.parameters[f"platform_{c}{i}"] for c in "xyz"] for i in range(1, 7)])
    p0, r0 = start.pose[:3, 3], start.pose[:3, :3]
    u, n = np.array([0.01, -0.02, 0.015]), np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    nx = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    checked, previous = 0, start
    for t in np.linspace(0.0, 0.7, 8):
        phi, phid, phidd = 0.05 * np.sin(3 * t + 0.4), 0.15 * np.cos(3 * t + 0.4), -0.45 * np.sin(3 * t + 0.4)
        rotation = (np.eye(3) + np.sin(phi) * nx + (1 - np.cos(phi)) * nx @ nx) @ r0
        p, v, a = p0 + u * np.sin(2 * t + 0.7), 2 * u * np.cos(2 * t + 0.7), -4 * u * np.sin(2 * t + 0.7)
        w, alpha = phid * n, phidd * n
        arm = plat @ rotation.T
        d = arm + p - base
        dd = v + np.cross(w, arm)
        ddd = a + np.cross(alpha, arm) + np.cross(w, np.cross(w, arm))
        length = np.linalg.norm(d, axis=1)
        rate = np.sum(d * dd, axis=1) / length
        acceleration = (np.sum(dd * dd, axis=1) + np.sum(d * ddd, axis=1) - rate**2) / length
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = rotation, p
        state = m.forward_pose(length, guess=previous)
        previous = state
        assert np.abs(state.pose - pose).max() < 1e-10
        twist, twist_rate = platform_acceleration(m, state, rate, acceleration)
        expected = np.concatenate([a, alpha])
        assert np.abs(twist - np.concatenate([v, w])).max() <= 1e-10 * np.abs(v).max()
        error = np.abs(twist_rate - expected).max() / np.abs(expected).max()
        assert error <= 1e-10, f"t = {t}: twist rate off by {error:.3g} relative"
        platform = rigid_inertia(10.0, (0.01, -0.02, 0.03), [[0.4, 0.01, 0.02], [0.01, 0.5, -0.03], [0.02, -0.03, 0.6]])
        expected_tau = m.actuator_forces(state, -dalembert(platform, rotation, w, a, alpha, GRAVITY))
        tau = inverse_dynamics(m, state, rate, acceleration, platform_inertia=platform, gravity=GRAVITY).efforts
        assert np.abs(tau - expected_tau).max() <= 1e-10 * np.abs(expected_tau).max()
        checked += 1
    assert checked == 8


@pytest.mark.parametrize("name", KINDS)
def test_acceleration_equals_differences_of_forward_rate(name):
    """t_dot at t = 0.1 along a cubic actuated trajectory vs fourth-order central differences of
    forward_rate(forward_pose(q(t)), q_dot(t)) (step 1e-3: truncation ~1e-12, rounding ~1e-12)."""
    m = parakin.load(name, backend="numpy")
    at = motion(m, np.random.default_rng(11))
    state_0 = home(m)

    def twist(t):
        q, qd, _ = at(t)
        return m.forward_rate(m.forward_pose(q, guess=state_0), qd)

    h, t0 = 1e-3, 0.1
    reference = (8 * (twist(t0 + h) - twist(t0 - h)) - (twist(t0 + 2 * h) - twist(t0 - 2 * h))) / (12 * h)
    q, qd, qdd = at(t0)
    state = m.forward_pose(q, guess=state_0)
    velocity, acceleration = platform_acceleration(m, state, qd, qdd)
    assert np.abs(velocity - twist(t0)).max() < 1e-12 * max(1.0, np.abs(velocity).max())
    error = np.abs(acceleration - reference).max() / np.abs(reference).max()
    assert error < 1e-7, f"{name}: twist rate vs differences of forward_rate: {error:.3g} relative"


@pytest.mark.parametrize("name", KINDS)
def test_massless_legs_equal_statics_of_dalembert_wrench(name):
    """Efforts = actuator_forces(state, -(F, n_O)) with F = m (a_c - g), n_c = I_c alpha + w x I_c w
    (about the centre), n_O = n_c + r x F, to 1e-10 relative; for prs3 also the constraint forces."""
    m = parakin.load(name, backend="numpy")
    rng = np.random.default_rng(5)
    at, platform = motion(m, rng), body(rng)
    q, qd, qdd = at(0.05)
    state = m.forward_pose(q, guess=home(m))
    out = inverse_dynamics(m, state, qd, qdd, platform_inertia=platform, gravity=GRAVITY)
    twist, twist_rate = platform_acceleration(m, state, qd, qdd)
    (_, w), (a, alpha) = np.split(twist6(m, twist), 2), np.split(twist6(m, twist_rate), 2)
    six = dalembert(platform, state.rotation, w, a, alpha, GRAVITY)
    kept = [("vx", "vy", "vz", "wx", "wy", "wz").index(c) for c in m.manifest.capabilities.rates.twist]
    expected = m.actuator_forces(state, -six[kept])
    error = np.abs(out.efforts - expected).max() / np.abs(expected).max()
    assert error <= 1e-10, f"{name}: {error:.3g}"
    if m.manifest.capabilities.rates.constraints:
        reactions = m.constraint_forces(state, -six[kept])
        assert np.abs(out.constraint_forces - reactions).max() <= 1e-10 * np.abs(reactions).max()
    else:
        assert out.constraint_forces is None


@pytest.mark.parametrize("name", KINDS)
def test_regressor_times_parameters_equals_efforts(name):
    """Y theta = tau to 1e-12 relative over a batch of 6 states and 6 random bodies; a batch (of
    the regressor and of the efforts) equals each input alone."""
    m = parakin.load(name, backend="numpy")
    rng = np.random.default_rng(7)
    at = motion(m, rng)
    samples = [at(t) for t in np.linspace(0.0, 0.1, 6)]
    states = [m.forward_pose(s[0], guess=home(m)) for s in samples]
    batch = parakin.Configuration(
        np.stack([s.actuated for s in states]),
        np.stack([s.passive for s in states]),
        np.stack([s.pose for s in states]),
    )
    qd, qdd = np.stack([s[1] for s in samples]), np.stack([s[2] for s in samples])
    y = dynamics_regressor(m, batch, qd, qdd, gravity=GRAVITY)
    assert y.shape == (6, len(m.actuated_names), len(INERTIAL_PARAMETERS))
    common = body(rng)
    batched = inverse_dynamics(m, batch, qd, qdd, platform_inertia=common, gravity=GRAVITY).efforts
    assert batched.shape == (6, len(m.actuated_names))
    checked = 0
    for k in range(6):
        alone = inverse_dynamics(m, states[k], qd[k], qdd[k], platform_inertia=common, gravity=GRAVITY).efforts
        assert np.abs(batched[k] - alone).max() <= 1e-13 * np.abs(alone).max()
        platform = body(rng)
        tau = inverse_dynamics(m, states[k], qd[k], qdd[k], platform_inertia=platform, gravity=GRAVITY).efforts
        assert np.abs(y[k] @ platform.parameters() - tau).max() <= 1e-12 * np.abs(tau).max()
        alone = dynamics_regressor(m, states[k], qd[k], qdd[k], gravity=GRAVITY)
        assert np.abs(alone - y[k]).max() <= 1e-13 * np.abs(y[k]).max()
        checked += 1
    assert checked == 6
    # theta round trip through the parameters
    platform = body(rng)
    back = RigidInertia.from_parameters(platform.parameters())
    assert np.allclose(back.inertia, platform.inertia, atol=1e-15) and np.allclose(back.centre, platform.centre)


@pytest.mark.parametrize("name", ["five_bar", "planar_3rpr", "spm", "stewart", "prs3"])
def test_power_balance_along_a_trajectory(name):
    """tau . q_dot = dK/dt - m g . v_c at 8 instants, dK/dt by fourth-order central differences
    (step 1e-4) of K = m |v_c|^2 / 2 + w . I w / 2 from forward_rate: 1e-6 relative."""
    m = parakin.load(name, backend="numpy")
    rng = np.random.default_rng(3)
    at, platform = motion(m, rng), body(rng)
    guess = home(m)

    def energy(t, near):
        q, qd, _ = at(t)
        state = m.forward_pose(q, guess=near)
        v, w = np.split(twist6(m, m.forward_rate(state, qd)), 2)
        r = state.rotation @ platform.centre
        v_c = v + np.cross(w, r)
        inertia = state.rotation @ platform.inertia @ state.rotation.T
        return 0.5 * platform.mass * v_c @ v_c + 0.5 * w @ inertia @ w, v_c

    checked = 0
    for t in np.linspace(0.0, 0.14, 8):
        q, qd, qdd = at(t)
        state = guess = m.forward_pose(q, guess=guess)
        h = 1e-4
        k = [energy(t + s * h, state)[0] for s in (-2, -1, 1, 2)]
        kinetic_rate = (8 * (k[2] - k[1]) - (k[3] - k[0])) / (12 * h)
        gravity_power = -platform.mass * GRAVITY @ energy(t, state)[1]
        tau = inverse_dynamics(m, state, qd, qdd, platform_inertia=platform, gravity=GRAVITY).efforts
        power = tau @ qd
        scale = np.linalg.norm(tau) * np.linalg.norm(qd)
        assert abs(power - (kinetic_rate + gravity_power)) <= 1e-6 * scale, (
            f"{name} t = {t}: tau . qdot = {power:.12g} W, dK/dt - m g . v_c = {kinetic_rate + gravity_power:.12g} W"
        )
        checked += 1
    assert checked == 8


def test_bad_inputs_are_named_errors():
    m = parakin.load("five_bar", backend="numpy")
    state = home(m)
    with pytest.raises(BadInputError, match="leg_inertias must be"):
        inverse_dynamics(m, state, [0, 0], [0, 0], platform_inertia=rigid_inertia(1.0), leg_inertias=[1.0])
    with pytest.raises(BadInputError, match="not link bodies of five_bar"):
        inverse_dynamics(m, state, [0, 0], [0, 0], platform_inertia=rigid_inertia(1.0), leg_inertias={"leg9": 1.0})
    with pytest.raises(BadInputError, match="mass of leg1_link1"):
        inverse_dynamics(m, state, [0, 0], [0, 0], platform_inertia=rigid_inertia(1.0), leg_inertias={"leg1_link1": -1})
    with pytest.raises(BadInputError, match="mass"):
        rigid_inertia(-1.0)
    with pytest.raises(BadInputError, match="triangle"):
        rigid_inertia(1.0, inertia=(1.0, 1.0, 3.0))
    with pytest.raises(BadInputError, match="symmetric"):
        rigid_inertia(1.0, inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(BadInputError, match="mass"):
        RigidInertia.from_parameters([0.0] * 10)
    with pytest.raises(BadInputError, match="accelerations"):
        inverse_dynamics(m, state, [0, 0], [0, np.nan], platform_inertia=rigid_inertia(1.0))
    with pytest.raises(BadInputError, match="gravity"):
        inverse_dynamics(m, state, [0, 0], [0, 0], platform_inertia=rigid_inertia(1.0), gravity=[0, 1])
    # no A/B rate model and no joint graph to make a tree of (sam's legs are a tree: tests/test_dynamics_legs.py)
    sphere = parakin.load("sphere2r", backend="numpy")
    n = len(sphere.actuated_names)
    with pytest.raises(UnsupportedOperationError, match="no A/B rate model.*inverse dynamics needs one of them"):
        inverse_dynamics(sphere, home(sphere), np.zeros(n), np.zeros(n), platform_inertia=rigid_inertia(1.0))


def test_mechanism_methods_are_the_free_functions():
    """``m.inverse_dynamics`` and ``m.dynamics_regressor`` give the free functions' values, and
    ``parakin.mujoco`` is the bridge module."""
    import parakin.mujoco_bridge
    from parakin import dynamics

    m = parakin.load("five_bar", backend="numpy")
    state = m.forward_pose(m.home_actuated)
    inertia = dynamics.rigid_inertia(0.7, [0.01, -0.02, 0.0], np.diag([1e-3, 2e-3, 3e-3]))
    rates, accelerations = np.array([0.3, -0.2]), np.array([1.5, 0.4])
    method = m.inverse_dynamics(state, rates, accelerations, platform_inertia=inertia)
    free = dynamics.inverse_dynamics(m, state, rates, accelerations, platform_inertia=inertia)
    np.testing.assert_array_equal(method.efforts, free.efforts)
    regressor = m.dynamics_regressor(state, rates, accelerations)
    np.testing.assert_allclose(regressor @ inertia.parameters(), method.efforts, rtol=1e-12, atol=1e-15)
    assert parakin.mujoco is parakin.mujoco_bridge


def test_the_reference_examples_run():
    """Every Example of parakin.dynamics runs and prints what it shows (``import numpy as np``
    and ``import parakin`` assumed, as the API page says)."""
    import doctest

    from parakin import dynamics

    result = doctest.testmod(
        dynamics, extraglobs={"np": np, "parakin": parakin}, optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    )
    assert result.failed == 0 and result.attempted >= 15, result
