"""parakin.solvers.statics on every mechanism with a rate model (A/B rate Jacobians or serial legs), found
in ``parakin.available()``, never by name.

Configurations: the platform pose reached from the home configuration perturbed (actuated and
passive values, 0.1 rad or 0.1 x the mechanism's size), then the first valid inverse branch of that
pose away from singularities: 1 / cond above 1e-3 for every matrix the statics inverts (A and B, or
the rate matrix M and each leg's Jacobian, whose serial singularity M shows only in part), unit-free
with lengths in units of the mechanism's size. Nearer a singularity the inverse pose bends on the
scale of the central differences' step, and the reference, not the statics, decides the test (seen:
a sam configuration 0.002 rad from a leg's serial singularity, cond 2e3, where the step 1e-6 moves
the leg's joints by half that distance and dq is off by 5e-7 relative). A geometry that is singular
at every pose (an architecture singularity) is perturbed first (every parameter by 20 %) until it is
not.

Claims: virtual work, tau . dq + w . twist dt = 0 against central differences of the inverse pose
along the twist; stiffness symmetric positive definite and the wrench-displacement relation it
encodes; equilibrium of compliant actuators by Newton and by fixed point.
"""

import warnings

import contract_helpers as h
import numpy as np
import pytest

import parakin
from parakin.pose import wrap_angle
from parakin.solvers import statics

SIX = ("vx", "vy", "vz", "wx", "wy", "wz")


def with_rate_model() -> list[str]:
    names = []
    for name in parakin.available():
        capabilities = parakin.metadata(name).capabilities
        if capabilities.rates is not None or capabilities.legs:
            names.append(name)
    return names


def usable(name: str, rng: np.random.Generator) -> parakin.Mechanism:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        m = parakin.load(name, backend="numpy")
        for _ in range(20):
            if not m.is_architecturally_singular():
                return m
            values = {k: v * (1 + 0.2 * rng.normal()) + 0.2 * rng.normal() for k, v in m.parameters.items()}
            m = parakin.load(name, backend="numpy", **values)
    raise AssertionError(f"{name}: no geometry off the architecture singularity found")


def size(m: parakin.Mechanism) -> float:
    """The mechanism's length scale: the largest prismatic home value (1 without one)."""
    values = [abs(h) for v, h in zip(m.manifest.actuated, m.home_actuated, strict=True) if not v.revolute]
    values += [abs(h) for v, h in zip(m.manifest.passive, m.home_passive, strict=True) if not v.revolute]
    return max(values, default=0.0) or 1.0


def well_conditioned(m: parakin.Mechanism, state: parakin.Configuration) -> bool:
    """1 / cond above 1e-3 for every matrix the statics inverts (the module docstring), with the
    linear twist components and prismatic joints in units of ``size(m)`` so that the bound does not
    depend on the mechanism's metres."""
    length = size(m)
    revolute = {v.name: v.revolute for v in (*m.manifest.actuated, *m.manifest.passive)}
    per_twist = np.array([length if name in SIX[:3] else 1.0 for name in statics.twist_names(m)])
    per_actuated = np.array([1.0 if revolute[name] else length for name in m.actuated_names])
    if m.capabilities.rates:
        jacobians = m.rate_jacobians(state)
        matrices = [jacobians["a"] * per_twist, jacobians["b"] * per_actuated]
    else:
        matrices = [m.rate_matrix(state) * per_twist / per_actuated[:, None]]
        for leg, jacobian in m.leg_jacobians(state).items():
            joints = next(item for item in m.capabilities.legs if item.name == leg).joints
            per_joint = np.array([1.0 if revolute[name] else length for name in joints])
            matrices.append(jacobian * per_joint / per_twist[:, None])
    for matrix in matrices:
        sigma = np.linalg.svd(matrix, compute_uv=False)
        if not sigma[-1] > 1e-3 * sigma[0]:
            return False
    return True


def configurations(m: parakin.Mechanism, rng: np.random.Generator, count: int = 6) -> list[tuple[int, object]]:
    """(branch index, configuration) pairs, as described in the module docstring: the pose of the
    perturbed home configuration by Newton (forward pose from home) or, where that fails, by the
    first leg's chain, then its inverse branches."""
    found: list[tuple[int, object]] = []
    revolute_a = np.array([v.revolute for v in m.manifest.actuated])
    revolute_p = np.array([v.revolute for v in m.manifest.passive])
    actuated_scale = np.where(revolute_a, 1.0, size(m))
    passive_scale = np.where(revolute_p, 1.0, size(m))
    for attempt in range(200):
        actuated = m.home_actuated + 0.1 * actuated_scale * rng.normal(size=m.home_actuated.shape)
        passive = m.home_passive + 0.1 * passive_scale * rng.normal(size=m.home_passive.shape)
        low, high = (np.array([v.limits[k] for v in m.manifest.actuated]) for k in (0, 1))
        if not ((actuated >= low) & (actuated <= high)).all():
            continue  # outside an actuator's stroke: refused by every solver
        if attempt % 2 == 0:
            solved = m.forward_pose(actuated, m.home_passive, strict=False)
            if not solved.converged:
                continue
            pose = solved.pose
        try:
            if attempt % 2:
                pose = m.platform_pose(actuated, passive)
            branches = m.inverse_pose(pose, strict=False)
        except parakin.InconsistentInputError:
            continue  # joint values that do not close need not give a rigid pose: refused
        for k in np.nonzero(branches.valid)[0]:
            state = branches.branch(int(k))
            # its own pose: an inverse that reads part of the pose (a 3-PRS reads height and
            # tilt) reaches a pose of its own, and the motions below start there
            state = parakin.Configuration(state.actuated, state.passive, m.platform_pose(state.actuated, state.passive))
            if well_conditioned(m, state):
                found.append((int(k), state))
                break
        if len(found) == count:
            return found
    raise AssertionError(f"{m.name}: only {len(found)} well-conditioned configurations found")


def move(pose: np.ndarray, twist6: np.ndarray, s: float) -> np.ndarray:
    """The pose after the motion twist6 * s: p + v s, exp([w] s) R (w in {B})."""
    w = twist6[3:] * s
    angle = np.linalg.norm(w)
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]) / max(angle, 1e-300)
    rotation = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    out = pose.copy()
    out[:3, 3] += twist6[:3] * s
    out[:3, :3] = rotation @ pose[:3, :3]
    return out


def actuated_change(m: parakin.Mechanism, branch: int, state, twist: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """dq / dt along ``twist`` (the mechanism's components) by central differences of the inverse pose."""
    twist6 = np.zeros(6)
    for value, name in zip(twist, statics.twist_names(m), strict=True):
        twist6[SIX.index(name)] = value
    ends = [m.inverse_pose(move(state.pose, twist6, s), strict=False).actuated[branch] for s in (h, -h)]
    difference = ends[0] - ends[1]
    revolute = np.array([v.revolute for v in m.manifest.actuated])
    return np.where(revolute, wrap_angle(difference), difference) / (2 * h)


@pytest.fixture(scope="module", params=with_rate_model())
def case(request):
    rng = np.random.default_rng(sum(map(ord, request.param)))
    m = usable(request.param, rng)
    return m, configurations(m, rng), rng


def test_some_mechanisms_have_a_rate_model():
    assert len(with_rate_model()) >= 2


def test_actuator_forces_are_virtual_work(case):
    """tau . dq + w . twist dt = 0 for random wrenches w and motions: tau from
    ``statics.actuator_forces``, dq from central differences of the inverse pose (same branch)."""
    m, states, rng = case
    n = len(statics.twist_names(m))
    worst = 0.0
    for branch, state in states:
        for _ in range(3):
            wrench, twist = rng.normal(size=n), h.feasible_twist(m, state, rng.normal(size=n))
            tau = statics.actuator_forces(m, state, wrench)
            dq = actuated_change(m, branch, state, twist)
            scale = np.abs(tau) @ np.abs(dq) + np.abs(wrench) @ np.abs(twist)
            worst = max(worst, abs(tau @ dq + wrench @ twist) / scale)
            # G^T tau = -w with G = d(actuated)/d(twist)
            g = statics.actuation_matrix(m, state)
            assert np.abs(g @ twist - dq).max() < 1e-6 * (1 + np.abs(dq).max())
    assert worst < 1e-7, f"{m.name}: virtual work off by {worst:.3g} (relative)"


def test_actuator_forces_batch_and_point_force(case):
    """A batch of configurations and wrenches gives the rows one by one; a force at a platform
    point is the wrench (F, (R p) x F) in the mechanism's twist components."""
    m, states, rng = case
    n = len(statics.twist_names(m))
    stacked = parakin.Configuration(
        np.stack([s.actuated for _, s in states]),
        np.stack([s.passive for _, s in states]),
        np.stack([s.pose for _, s in states]),
    )
    wrenches = rng.normal(size=(len(states), n))
    batch = statics.actuator_forces(m, stacked, wrenches)
    for row, (_, state) in enumerate(states):
        assert np.abs(batch[row] - statics.actuator_forces(m, state, wrenches[row])).max() < 1e-9 * (
            1 + np.abs(batch[row]).max()
        )
    _, state = states[0]
    force, point = rng.normal(size=3), rng.normal(size=3)
    full = np.concatenate([force, np.cross(state.rotation @ point, force)])
    expected = [full[SIX.index(name)] for name in statics.twist_names(m)]
    assert np.abs(statics.point_force_wrench(m, state, force, point) - expected).max() < 1e-12


def test_stiffness_is_symmetric_positive_definite_and_maps_motion_to_wrench(case):
    """K = G^T K_q G: symmetric positive definite for positive actuator stiffnesses (on the
    motions a lower-mobility platform can make), and the extra wrench K twist dt is held by the
    actuator efforts -K_q dq (the springs' response to dq)."""
    m, states, rng = case
    n_a = len(m.actuated_names)
    for branch, state in states:
        k_q = np.exp(rng.normal(size=n_a)) * 1e4
        stiffness = statics.stiffness(m, state, k_q)
        assert np.abs(stiffness - stiffness.T).max() <= 1e-12 * np.abs(stiffness).max()
        # positive definite on the motions the platform can make (all, but for a lower-mobility one)
        basis = np.linalg.svd(np.stack([h.feasible_twist(m, state, e) for e in np.eye(len(stiffness))]).T)[0]
        basis = basis[:, :n_a] if m.capabilities.rates is not None and m.capabilities.rates.constraints else basis
        assert np.linalg.eigvalsh(basis.T @ (0.5 * (stiffness + stiffness.T)) @ basis).min() > 0
        twist = h.feasible_twist(m, state, rng.normal(size=stiffness.shape[0]))
        dq = actuated_change(m, branch, state, twist)
        tau = statics.actuator_forces(m, state, stiffness @ twist)
        assert np.abs(tau + k_q * dq).max() < 1e-6 * np.abs(k_q * dq).max()
    # a full (n_a, n_a) actuator stiffness is accepted as such
    full = np.diag(k_q)
    assert np.abs(statics.stiffness(m, state, full) - stiffness).max() <= 1e-12 * np.abs(stiffness).max()


def test_equilibrium_of_compliant_actuators(case):
    """K_q (q_cmd - q) = actuator_forces(q) at the pose reached with q: Newton and fixed point agree;
    without load q = q_cmd; too few iterations raise ConvergenceError with the residual."""
    m, states, rng = case
    n = len(statics.twist_names(m))
    _, state = states[0]
    wrench = rng.normal(size=n)
    # K_q = c I moves the platform by G^+ K_q^-1 tau: c makes that ~1e-4 (m or rad)
    tau = statics.actuator_forces(m, state, wrench)
    motion = np.linalg.lstsq(statics.actuation_matrix(m, state), tau, rcond=None)[0]
    k_q = np.full(len(m.actuated_names), 1e4 * np.abs(motion).max())
    newton = statics.equilibrium(m, state.actuated, wrench, k_q, guess=state)
    fixed = statics.equilibrium(m, state.actuated, wrench, k_q, guess=state, method="fixed_point")
    for result in (newton, fixed):
        reached = result.configuration
        # rounding of q alone leaves |K_q| |q| eps in the efforts
        bound = 1e-12 * (k_q.max() * np.abs(state.actuated).max() + np.abs(result.forces).max())
        assert result.residual < bound
        assert np.abs(k_q * (state.actuated - reached.actuated) - result.forces).max() < bound
        assert np.abs(result.forces - statics.actuator_forces(m, reached, wrench)).max() < 1e-9
        assert np.abs(m.loop_closure(reached.actuated, reached.passive)["residual"]).max(initial=0) < 1e-10
        assert 0 < np.abs(reached.actuated - state.actuated).max() < 1e-2
    assert newton.iterations <= fixed.iterations
    assert np.abs(newton.configuration.actuated - fixed.configuration.actuated).max() < 1e-10
    unloaded = statics.equilibrium(m, state.actuated, np.zeros(n), k_q, guess=state)
    assert unloaded.iterations == 1 and np.abs(unloaded.configuration.actuated - state.actuated).max() == 0
    with pytest.raises(parakin.ConvergenceError) as error:
        statics.equilibrium(m, state.actuated, wrench, k_q, guess=state, max_iterations=1)
    assert error.value.residual is not None and error.value.residual > 0


def test_mechanisms_without_a_rate_model_say_so():
    for name in parakin.available():
        capabilities = parakin.metadata(name).capabilities
        if capabilities.rates is None and not capabilities.legs:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
                m = parakin.load(name, backend="numpy")
            state = m.forward_pose(m.home_actuated)
            with pytest.raises(parakin.UnsupportedOperationError, match="rate model"):
                statics.actuator_forces(m, state, np.zeros(3))
