"""The mechanism contract: what every generated package must satisfy, on every backend.

Parametrised over ``parakin.available()`` x backends ('numpy', 'casadi', 'compiled') and driven
by the typed manifest only (pose kind, variables with kind and home, capabilities, kernels and
their shapes, examples, tolerances), so a mechanism file dropped into ``mechanisms/`` is tested
here without a test written for it. Each test checks computed values against an independent
source: a round trip through another solver, central finite differences, or another backend.

A mechanism whose default geometry is architecturally singular (singular at every pose) is
tested on a nearby non-singular geometry (``contract_helpers.usable_parameters``); its defaults
are tested for the warning and the degenerate forward elimination.
"""

from __future__ import annotations

import functools
import warnings

import contract_helpers as h
import numpy as np
import pytest

import parakin
from parakin import BadInputError, Configuration, UnsupportedOperationError
from parakin.singularity import NEAR_SINGULAR, type_ii_distance

NAMES = parakin.available()
CASES = [pytest.param(name, backend, id=f"{name}-{backend}") for name in NAMES for backend in h.BACKENDS]
KERNELS = [
    pytest.param(name, kernel, id=f"{name}-{kernel}") for name in NAMES for kernel in parakin.metadata(name).kernels
]

SAMPLES = 40  # random poses per mechanism and backend
MIN_CHECKED = 20  # of which at least this many must be reachable and checked
PARITY = 1e-9  # relative agreement of the backends


@pytest.fixture(scope="module", autouse=True)
def _no_architecture_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        yield


@functools.cache
def reachable_sample(name: str, backend: str):
    """Random poses near home with their inverse branches: (poses, actuated they came from or
    None, InversePose with strict=False)."""
    m = h.load(name, backend)
    rng = np.random.default_rng(h.seed(name, "poses"))  # the same poses on every backend
    poses, actuated = h.sample_poses(m, rng, SAMPLES)
    return poses, actuated, m.inverse_pose(poses, strict=False)


def closed_configurations(name: str, backend: str, count: int) -> list[Configuration]:
    """Up to ``count`` closed configurations: one valid inverse branch of each reachable sampled
    pose, cycling through the branches."""
    _, _, ik = reachable_sample(name, backend)
    configurations = []
    for i in np.flatnonzero(ik.valid.any(-1)):
        branches = np.flatnonzero(ik.valid[i])
        k = branches[len(configurations) % branches.size]
        configurations.append(Configuration(ik.actuated[i, k], ik.passive[i, k], ik.pose[i]))
        if len(configurations) == count:
            break
    return configurations


def require_inverse(m) -> None:
    if m.capabilities.inverse is None:
        pytest.skip(f"{m.name} has no closed-form inverse (manifest capabilities.inverse)")


# ---------------------------------------------------------------------------- inverse and forward pose
@pytest.mark.parametrize(("name", "backend"), CASES)
def test_every_valid_inverse_branch_reproduces_the_pose_and_closes_the_loop(name, backend):
    """Random poses near home: every valid branch of inverse_pose gives back the pose through
    platform_pose (1e-9, positions in length scales) and closes the loop (residual < 1e-9,
    alignment > 0); at least 20 of 40 samples are reachable."""
    m = h.load(name, backend)
    require_inverse(m)
    poses, sampled_actuated, ik = reachable_sample(name, backend)
    reachable = ik.valid.any(-1)
    assert reachable.sum() >= MIN_CHECKED, f"{name}: only {reachable.sum()} of {SAMPLES} sampled poses reachable"
    valid = ik.valid
    actuated, passive = ik.actuated[valid], ik.passive[valid]
    assert np.isfinite(actuated).all() and np.isfinite(passive).all(), f"{name}: a valid branch is not finite"
    target = np.broadcast_to(poses[:, None], valid.shape + (4, 4))[valid]
    reached = m.platform_pose(actuated, passive)
    closure = m.loop_closure(actuated, passive)
    residual = np.abs(closure["residual"]).max(-1, initial=0.0)
    assert residual.max() < h.CLOSURE, f"{name}: valid branch with loop residual {residual.max():.3g}"
    assert (closure["alignment"] > 0).all(), f"{name}: valid branch at a false closure (alignment <= 0)"
    if h.full_dof(m):
        error = h.pose_tolerance(m, reached, target)
        assert error.max() < 1e-9, f"{name}: platform_pose of a valid branch misses the pose by {error.max():.3g}"
        return
    # fewer actuators than pose coordinates: the inverse reads only what the chain controls.
    # The branch that the pose came from gives it back exactly, and every valid branch's pose
    # is equivalent (its inverse has the same valid branches).
    for i in np.flatnonzero(reachable):
        branches = np.flatnonzero(valid[i])
        mismatch = np.abs(h.wrapped(ik.actuated[i, branches] - sampled_actuated[i], h.revolute_actuated(m)))
        own = branches[np.argmin(mismatch.max(-1))]
        assert mismatch.max(-1).min() < 1e-9, f"{name}: sample {i}: no branch gives back its actuated values"
        own_pose = m.platform_pose(ik.actuated[i, own], ik.passive[i, own])
        assert h.pose_tolerance(m, own_pose, poses[i]) < 1e-9
        for k in branches:
            again = m.inverse_pose(m.platform_pose(ik.actuated[i, k], ik.passive[i, k]), strict=False)
            ours, theirs = again.actuated[again.valid], ik.actuated[i, branches]
            difference = h.wrapped(ours[:, None] - theirs[None], h.revolute_actuated(m))
            assert np.abs(difference).max(-1).min(0).max() < 1e-9 and np.abs(difference).max(-1).min(1).max() < 1e-9


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_forward_pose_from_a_nearby_guess_converges_to_the_inverse_branch(name, backend):
    """Newton (forward_pose) from each valid inverse branch, its passive values perturbed by 1e-4,
    converges (flagged converged, finite, residual <= 1e-12) to that branch's passive values
    and pose: to 1e-9, or to the forward error bound of a 1e-12 residual where the
    configuration is near a type II singularity (``contract_helpers.newton_tolerance``). Newton's
    basin shrinks with the distance d to a type II singularity: within NEAR_SINGULAR of one the
    perturbation is 1e-4 d / NEAR_SINGULAR (a user's Hexaglide samples poses at d = 1e-6, where
    1e-4 reaches another solution)."""
    m = h.load(name, backend)
    require_inverse(m)
    _, _, ik = reachable_sample(name, backend)
    valid = ik.valid
    actuated, passive = ik.actuated[valid], ik.passive[valid]
    assert len(actuated) >= MIN_CHECKED
    target = m.platform_pose(actuated, passive)
    rng = np.random.default_rng(h.seed(name, "guess"))
    scale = h.variable_scale(m, m.manifest.passive)
    distance = type_ii_distance(m, Configuration(actuated, passive, target))
    size = 1e-4 * (1.0 if distance is None else np.minimum(1.0, distance / NEAR_SINGULAR)[:, None])
    guess = passive + size * rng.normal(size=passive.shape) * scale
    fk = m.forward_pose(actuated, guess=guess, strict=False)
    assert fk.converged.all(), f"{name}: {(~fk.converged).sum()} of {fk.converged.size} Newton solves failed"
    assert np.isfinite(fk.pose).all() and np.isfinite(fk.passive).all()
    assert fk.residual.max() <= 1e-12
    closure = np.abs(m.loop_closure(actuated, fk.passive)["residual"]).max(-1, initial=0.0)
    assert closure.max() <= 1e-12, f"{name}: Newton's reported residual is not the loop closure's"
    tolerance = h.newton_tolerance(m, actuated, passive, 1e-12)
    error = np.abs(h.wrapped(fk.passive - passive, h.revolute_passive(m)) / scale).max(-1, initial=0.0)
    assert (error <= tolerance).all(), f"{name}: Newton reached other passive values ({error.max():.3g} away)"
    error = h.pose_tolerance(m, fk.pose, target)
    assert (error <= 10 * tolerance).all(), f"{name}: Newton reached another pose ({error.max():.3g} away)"


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_forward_pose_all_contains_the_pose_and_every_mode_reproduces_the_input(name, backend):
    """For actuated values of sampled poses, forward_pose_all has a valid mode at the pose, and
    each valid mode's inverse_pose has a valid branch with these actuated values (1e-8, or
    the forward error bound of the mode's residual near a type II singularity); valid modes
    are finite and close the loop."""
    m = h.load(name, backend)
    if m.capabilities.forward is None:
        pytest.skip(f"{name} has no closed-form forward elimination (manifest capabilities.forward)")
    require_inverse(m)
    configurations = closed_configurations(name, backend, 20)
    assert len(configurations) >= MIN_CHECKED
    actuated = np.stack([c.actuated for c in configurations])
    passive = np.stack([c.passive for c in configurations])
    target = m.platform_pose(actuated, passive)
    modes = m.forward_pose_all(actuated)
    assert (modes.count == modes.valid.sum(-1)).all()
    assert np.isfinite(modes.poses[modes.valid]).all() and np.isfinite(modes.passive[modes.valid]).all()
    assert (modes.residual[modes.valid] < h.CLOSURE).all()
    grid = np.broadcast_to(actuated[:, None], modes.passive.shape[:-1] + actuated.shape[-1:])
    # only the modes: the other slots hold placeholders where the closure may be undefined
    closure = np.abs(m.loop_closure(grid[modes.valid], modes.passive[modes.valid])["residual"]).max(-1, initial=0.0)
    assert (closure < h.CLOSURE).all(), f"{name}: a valid mode does not close the loop"
    chain = m.platform_pose(grid[modes.valid], modes.passive[modes.valid])
    error = h.pose_tolerance(m, chain, modes.poses[modes.valid])
    assert error.max(initial=0.0) < 1e-9, f"{name}: a mode's pose is not platform_pose of its passive values"
    tolerance = h.newton_tolerance(m, actuated, passive, 1e-13, base=1e-8)
    checked = 0
    for i in range(len(configurations)):
        distance = np.where(modes.valid[i], h.pose_tolerance(m, modes.poses[i], target[i]), np.inf)
        assert distance.min() < 10 * tolerance[i], (
            f"{name}: input {i}: the pose is not among the valid modes (nearest {distance.min():.3g})"
        )
        for k in np.flatnonzero(modes.valid[i]):
            back = m.inverse_pose(modes.poses[i, k], strict=False)
            assert back.valid.any(), f"{name}: input {i}, mode {k}: no valid inverse branch"
            mismatch = np.abs(h.wrapped(back.actuated - actuated[i], h.revolute_actuated(m)))
            mismatch = mismatch / h.variable_scale(m, m.manifest.actuated)
            best = np.where(back.valid, mismatch.max(-1), np.inf).min()
            bound = 100 * h.newton_tolerance(m, actuated[i], modes.passive[i, k], 1e-13, base=1e-10)
            assert best < bound, f"{name}: input {i}, mode {k}: inverse misses the input by {best:.3g}"
            checked += 1
    assert checked >= len(configurations)


def assert_pose_kind(m, poses: np.ndarray, what: str) -> None:
    """Rigid transforms of the manifest's pose kind: 'rotation' has p = 0, 'translation' R = I,
    'planar' a rotation about z and z = 0, 'planar_translation' R = I and z = 0."""
    poses = np.asarray(poses).reshape(-1, 4, 4)
    rotation, position = poses[:, :3, :3], poses[:, :3, 3]
    assert np.isfinite(poses).all(), f"{m.name} {what}: not finite"
    gram = np.einsum("nji,njk->nik", rotation, rotation)
    assert np.abs(gram - np.eye(3)).max(initial=0.0) < 1e-9, f"{m.name} {what}: R is not orthonormal"
    assert (np.linalg.det(rotation) > 0).all(), f"{m.name} {what}: R is a reflection"
    assert np.abs(poses[:, 3] - [0, 0, 0, 1]).max(initial=0.0) < 1e-12, f"{m.name} {what}: last row"
    kind, scale = m.manifest.pose_kind, h.length_scale(m)
    if kind == "rotation":
        assert np.abs(position).max(initial=0.0) < 1e-12 * scale, f"{m.name} {what}: a rotation pose translates"
    elif kind in ("translation", "planar_translation"):
        assert np.abs(rotation - np.eye(3)).max(initial=0.0) < 1e-12, f"{m.name} {what}: a translation pose rotates"
        if kind == "planar_translation":
            assert np.abs(position[:, 2]).max(initial=0.0) < 1e-12 * scale, f"{m.name} {what}: z != 0"
    elif kind == "planar":
        off_plane = np.abs(rotation[:, 2, :2]).max(initial=0.0) + np.abs(rotation[:, :2, 2]).max(initial=0.0)
        assert off_plane < 1e-12 and np.abs(position[:, 2]).max(initial=0.0) < 1e-12 * scale, (
            f"{m.name} {what}: a planar pose leaves the plane z = 0"
        )


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_solver_poses_are_rigid_and_of_the_manifest_pose_kind(name, backend):
    """Poses of closed configurations (valid inverse branches, Newton results, assembly modes)
    are rigid transforms of the manifest's pose kind."""
    m = h.load(name, backend)
    poses, _, ik = reachable_sample(name, backend) if m.capabilities.inverse else (None, None, None)
    if ik is None:
        poses, _ = h.sample_poses(m, np.random.default_rng(h.seed(name, "kind")), 10)
        assert_pose_kind(m, poses, "sampled pose")
        return
    assert_pose_kind(m, m.platform_pose(ik.actuated[ik.valid], ik.passive[ik.valid]), "valid inverse branch")
    configurations = closed_configurations(name, backend, 5)
    actuated = np.stack([c.actuated for c in configurations])
    fk = m.forward_pose(actuated, guess=np.stack([c.passive for c in configurations]), strict=False)
    assert_pose_kind(m, fk.pose[fk.converged], "forward_pose")
    if m.capabilities.forward is not None:
        modes = m.forward_pose_all(actuated)
        assert_pose_kind(m, modes.poses[modes.valid], "assembly mode")


# ---------------------------------------------------------------------------- Jacobians and rates
def central_difference(function, x: np.ndarray, step: np.ndarray) -> np.ndarray:
    """d function / d x (columns per component of x) by central differences."""
    columns = []
    for j in range(x.size):
        dx = np.zeros_like(x)
        dx[j] = step[j]
        columns.append((function(x + dx) - function(x - dx)) / (2 * step[j]))
    return np.stack(columns, -1)


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_loop_closure_jacobians_match_finite_differences(name, backend):
    """The loop closure's passive Jacobian ('jacobian') and actuated Jacobian
    ('jacobian_actuated') against central differences of its residual, at closed and at open
    configurations near home."""
    m = h.load(name, backend)
    if not m.manifest.passive:
        pytest.skip(f"{name} has no passive variables: its loop closure is empty")
    rng = np.random.default_rng(h.seed(name, "jacobian"))
    states = [(c.actuated, c.passive) for c in closed_configurations(name, backend, 4)]
    passive_scale = h.variable_scale(m, m.manifest.passive)
    actuated_scale = h.variable_scale(m, m.manifest.actuated)
    for _ in range(4):
        states.append(
            (
                h.perturb_actuated(m, m.home_actuated, rng),
                m.home_passive + 0.1 * rng.normal(size=m.home_passive.shape) * passive_scale,
            )
        )
    for actuated, passive in states:
        out = m.loop_closure(actuated, passive)
        numeric = central_difference(
            lambda q, a=actuated: m.loop_closure(a, q)["residual"], passive, 1e-6 * passive_scale
        )
        scale = 1.0 + np.abs(numeric).max()
        error = np.abs(out["jacobian"] - numeric).max() / scale
        assert error < 1e-6, f"{name}: loop-closure Jacobian vs finite differences: {error:.3g}"
        jacobian_actuated = m.backend.call("loop_closure_actuated", actuated, passive, m.params)["jacobian_actuated"]
        numeric = central_difference(
            lambda a, q=passive: m.loop_closure(a, q)["residual"], actuated, 1e-6 * actuated_scale
        )
        error = np.abs(jacobian_actuated - numeric).max() / (1.0 + np.abs(numeric).max())
        assert error < 1e-6, f"{name}: actuated loop-closure Jacobian vs finite differences: {error:.3g}"


def nearest_branch(m, ik, state: Configuration) -> np.ndarray:
    """Per pose of ``ik``: the valid branch nearest ``state`` in actuated and passive values
    (branches may share their actuated values, e.g. two Euler triples of one rotation)."""
    mismatch = np.abs(h.wrapped(ik.actuated - state.actuated, h.revolute_actuated(m))).max(-1)
    if m.passive_names:
        mismatch += np.abs(h.wrapped(ik.passive - state.passive, h.revolute_passive(m))).max(-1)
    return np.argmin(np.where(ik.valid, mismatch, np.inf), axis=-1)


STENCIL = np.array([-2.0, -1.0, 1.0, 2.0])  # Richardson-extrapolated central differences, O(h^4)


def stencil_rates(values: np.ndarray, revolute: np.ndarray, step: float) -> np.ndarray:
    """d values / dt from values at t = STENCIL * step (angles differenced modulo 2 pi)."""
    near = h.wrapped(values[2] - values[1], revolute)
    far = h.wrapped(values[3] - values[0], revolute)
    return (8 * near - far) / (12 * step)


def stencil_twist(poses: np.ndarray, step: float) -> np.ndarray:
    """The twist (v, w) at t = 0 from poses at t = STENCIL * step."""
    near = h.finite_difference_twist(poses[1], poses[2], step)
    far = h.finite_difference_twist(poses[0], poses[3], 2 * step)
    return (4 * near - far) / 3


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_rate_model_matches_finite_differences_of_the_pose_solvers(name, backend):
    """Twists are (v of the origin of {P}, w), both in {B}, restricted to the components the
    rate model names (w only for an orienting platform). At closed configurations:

    * forward: along actuated rates theta_dot, finite differences of forward_pose give the
      twist and the passive rates; forward_rate, passive_rates and each leg Jacobian (joint
      rates -> twist) must give them (1e-6 relative; the step shrinks as 1 / condition near a
      type II singularity, where the higher derivatives grow);
    * inverse: moving the pose along a random twist (for a lower-mobility platform, one it can
      make: the twist of random actuator rates), finite differences of inverse_pose give
      actuated and passive rates; inverse_rate must give them (1e-6 relative).

    Differences are central and Richardson-extrapolated (fourth order)."""
    m = h.load(name, backend)
    capabilities = m.capabilities
    if capabilities.rates is None and capabilities.legs is None:
        pytest.skip(f"{name} has no rate model and no serial legs (manifest capabilities.rates, .legs)")
    require_inverse(m)
    components = h.twist_components(m)
    left_out = np.delete(np.arange(6), components)
    assert len(components) == m.manifest.twist_size
    rng = np.random.default_rng(h.seed(name, "rates"))
    # finite differences need room to a type II singularity: the curvature of the solution
    # branch grows there faster than the step can shrink (a Stewart sample at condition 4e3), so
    # the best-conditioned 8 of 16 samples
    sampled = closed_configurations(name, backend, 16)
    order = np.argsort([float(h.condition(m, c.actuated, c.passive)) for c in sampled], kind="stable")
    configurations = [sampled[k] for k in order[:8]]
    assert len(configurations) == 8
    actuated_scale = h.variable_scale(m, m.manifest.actuated)
    passive_scale = h.variable_scale(m, m.manifest.passive)
    twist_scale = np.array([h.length_scale(m)] * 3 + [1.0] * 3)
    for state in configurations:
        # forward: finite differences of Newton along theta_dot
        rates = rng.normal(size=state.actuated.shape) * actuated_scale
        step = 1e-5 * min(1.0, 100.0 / float(h.condition(m, state.actuated, state.passive)))
        ends = m.forward_pose(state.actuated + step * STENCIL[:, None] * rates, guess=state, tolerance=1e-13)
        twist6 = stencil_twist(ends.pose, step)
        passive_rates = stencil_rates(ends.passive, h.revolute_passive(m), step)
        twist = twist6[components]
        size = np.abs(twist6 / twist_scale).max()
        moved = np.abs(twist6[left_out] / twist_scale[left_out]).max(initial=0.0) / size
        assert moved <= 1e-6, f"{name}: the platform moves in twist components the rate model leaves out"
        error = np.abs((m.forward_rate(state, rates) - twist) / twist_scale[components]).max() / size
        assert error < 1e-6, f"{name}: forward_rate vs finite differences of forward_pose: {error:.3g}"
        if m.passive_names:
            ours = m.passive_rates(state, rates)
            error = np.abs((ours - passive_rates) / passive_scale).max() / np.abs(passive_rates / passive_scale).max()
            assert error < 1e-6, f"{name}: passive_rates vs finite differences of forward_pose: {error:.3g}"
        for leg in capabilities.legs or ():
            joint_rates = np.array(
                [
                    rates[m.actuated_names.index(j)]
                    if j in m.actuated_names
                    else passive_rates[m.passive_names.index(j)]
                    for j in leg.joints
                ]
            )
            leg_twist = m.leg_jacobians(state)[leg.name] @ joint_rates
            error = np.abs((leg_twist - twist6) / twist_scale).max() / size
            assert error < 1e-6, f"{name}: {leg.name} leg Jacobian vs finite differences: {error:.3g}"
        # inverse: finite differences of the closed-form inverse along a twist
        motion = np.zeros(6)
        motion[components] = rng.normal(size=len(components)) * twist_scale[components]
        if capabilities.rates is not None and capabilities.rates.constraints:
            # a lower-mobility platform moves only along its feasible twists: those of actuator rates
            motion[components] = m.forward_rate(state, rng.normal(size=state.actuated.shape) * actuated_scale)
        step = 1e-5
        ik = m.inverse_pose(np.stack([h.move_pose(state.pose, motion, t * step) for t in STENCIL]), strict=False)
        k = nearest_branch(m, ik, state)
        assert ik.valid[np.arange(4), k].all()
        actuated_fd = stencil_rates(ik.actuated[np.arange(4), k], h.revolute_actuated(m), step)
        passive_fd = stencil_rates(ik.passive[np.arange(4), k], h.revolute_passive(m), step)
        back = m.inverse_rate(state, motion[components])
        error = np.abs((back.actuated - actuated_fd) / actuated_scale).max()
        error /= np.abs(actuated_fd / actuated_scale).max()
        assert error < 1e-6, f"{name}: inverse_rate actuated vs finite differences of inverse_pose: {error:.3g}"
        if m.passive_names:
            error = np.abs((back.passive - passive_fd) / passive_scale).max()
            error /= np.abs(passive_fd / passive_scale).max()
            assert error < 1e-6, f"{name}: inverse_rate passive vs finite differences of inverse_pose: {error:.3g}"


# ---------------------------------------------------------------------------- backends
@pytest.mark.parametrize(("name", "kernel"), KERNELS)
def test_every_kernel_agrees_on_numpy_casadi_and_compiled(name, kernel):
    """Every kernel of the manifest, on the same random batch of inputs (sizes from the
    manifest), has the manifest's output names and shapes and the same values (1e-9 relative)
    on the three backends; NaN where, and only where, the NumPy kernel gives NaN."""
    info = parakin.metadata(name).kernels[kernel]
    mechanisms = {backend: h.load(name, backend) for backend in h.BACKENDS}
    rng = np.random.default_rng(h.seed(name, kernel))
    batch = 7
    inputs = h.kernel_inputs(mechanisms["numpy"], kernel, rng, batch)
    outputs = {backend: m.backend.call(kernel, *inputs) for backend, m in mechanisms.items()}
    expected = {io.name: (batch, *io.shape) for io in info.outputs}
    for backend, out in outputs.items():
        shapes = {key: np.shape(value) for key, value in out.items()}
        assert shapes == expected, f"{name}.{kernel} on {backend}: outputs {shapes}, manifest {expected}"
    for output in expected:
        reference = np.asarray(outputs["numpy"][output])
        finite = np.isfinite(reference)
        scale = np.abs(reference[finite]).max(initial=0.0)
        for backend in ("casadi", "compiled"):
            value = np.asarray(outputs[backend][output])
            assert (np.isfinite(value) == finite).all(), f"{name}.{kernel}.{output}: {backend} NaN pattern differs"
            error = np.abs(value[finite] - reference[finite])
            bound = PARITY * np.abs(reference[finite]) + 1e-12 * max(scale, 1.0)
            assert (error <= bound).all(), (
                f"{name}.{kernel}.{output}: {backend} vs numpy differ by {error.max():.3g} (scale {scale:.3g})"
            )


# ---------------------------------------------------------------------------- the manifest's examples
def as_transform(pose) -> np.ndarray:
    """^B_P T from a printed pose (a rotation R (3, 3) is embedded)."""
    array = np.asarray(pose, dtype=float)
    if array.shape == (3, 3):
        full = np.eye(4)
        full[:3, :3] = array
        return full
    return array


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_every_manifest_example_is_reproduced(name, backend):
    """Each example of the manifest (its parameters, pose or actuated inputs, expected values,
    tolerance): a pose example's branch (given, or the valid branch nearest the expected
    values) matches the expected actuated / passive values; an actuated example has the
    expected number of valid assembly modes and a valid mode at each expected pose."""
    examples = parakin.metadata(name).examples
    if not examples:
        pytest.skip(f"{name}: the manifest has no examples")
    for example in examples:
        label = f"{name} example {example.name!r}"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
            m = parakin.load(name, backend=backend, **example.parameters)
        expected = dict(example.expected)
        tolerance = example.tolerance
        if example.pose is not None:
            unknown = set(expected) - {"actuated", "passive"}
            assert not unknown, f"{label}: expected values {sorted(unknown)} are not checked by the contract"
            assert expected, f"{label}: nothing expected"
            branches = m.inverse_pose(example.pose, strict=False)
            if example.branch is not None:
                k = example.branch
            else:
                distance = np.zeros(branches.valid.shape)
                for key, values in (("actuated", branches.actuated), ("passive", branches.passive)):
                    if key in expected:
                        variables = m.manifest.actuated if key == "actuated" else m.manifest.passive
                        revolute = np.array([v.revolute for v in variables], dtype=bool)
                        distance += np.abs(h.wrapped(values - np.asarray(expected[key]), revolute)).max(-1)
                k = int(np.argmin(np.where(branches.valid, distance, np.inf)))
            assert branches.valid[k], f"{label}: branch {k} is not valid ({branches.failures})"
            if "actuated" in expected:
                error = np.abs(h.wrapped(branches.actuated[k] - expected["actuated"], h.revolute_actuated(m))).max()
                assert error <= tolerance, f"{label}: actuated (branch {k}) off by {error:.3g} > {tolerance:g}"
            if "passive" in expected:
                error = np.abs(h.wrapped(branches.passive[k] - expected["passive"], h.revolute_passive(m))).max()
                assert error <= tolerance, f"{label}: passive (branch {k}) off by {error:.3g} > {tolerance:g}"
        else:
            assert example.actuated is not None, f"{label}: neither a pose nor actuated inputs"
            unknown = set(expected) - {"mode_count", "poses"}
            assert not unknown, f"{label}: expected values {sorted(unknown)} are not checked by the contract"
            assert expected, f"{label}: nothing expected"
            modes = m.forward_pose_all(np.asarray(example.actuated, dtype=float))
            if "mode_count" in expected:
                assert int(modes.count) == int(expected["mode_count"]), (
                    f"{label}: {int(modes.count)} valid modes, expected {expected['mode_count']}"
                )
            for index, pose in enumerate(expected.get("poses", [])):
                printed = as_transform(pose)
                distance = np.where(modes.valid, np.abs(modes.poses - printed).max(axis=(-2, -1)), np.inf)
                assert distance.min() <= tolerance, (
                    f"{label}: expected pose {index} matched by no valid mode (nearest {distance.min():.3g})"
                )


# ---------------------------------------------------------------------------- errors
def bad_shapes(n: int) -> list[tuple[int, ...]]:
    return [(n + 1,), (max(n - 1, 0),), (n, 1), ()] if n else [(1,), (2,)]


def state_of(m) -> Configuration:
    """A closed configuration (or home when there is no inverse)."""
    if m.capabilities.inverse is not None:
        return closed_configurations(m.name, m.backend.name, 1)[0]
    return Configuration(m.home_actuated, m.home_passive, h.home_pose(m))


def expect_bad_input(name: str, calls: list[tuple[str, object]]) -> None:
    """Every call raises BadInputError (all are tried; the failures are listed together)."""
    failures = []
    for label, call in calls:
        try:
            call()
        except BadInputError:
            continue
        except Exception as error:  # noqa: BLE001 - reported below with its type
            failures.append(f"{label}: raised {type(error).__name__}: {error}")
        else:
            failures.append(f"{label}: no error")
    assert not failures, f"{name}: not rejected with BadInputError:\n" + "\n".join(failures)


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_wrong_shapes_raise_bad_input(name, backend):
    """Joint vectors, poses, rates and twists whose last axes have the wrong shape raise
    parakin.BadInputError, on every operation the manifest offers."""
    m = h.load(name, backend)
    n_a, n_p = len(m.actuated_names), len(m.passive_names)
    state = state_of(m)
    has_rates = m.capabilities.rates is not None or m.capabilities.legs is not None
    calls = []
    for shape in bad_shapes(n_a):
        calls += [
            (f"platform_pose(actuated {shape})", lambda s=shape: m.platform_pose(np.zeros(s), state.passive)),
            (f"loop_closure(actuated {shape})", lambda s=shape: m.loop_closure(np.zeros(s), state.passive)),
            (f"forward_pose(actuated {shape})", lambda s=shape: m.forward_pose(np.zeros(s), guess=state.passive)),
        ]
        if m.capabilities.forward is not None or not n_p:
            calls.append((f"forward_pose_all(actuated {shape})", lambda s=shape: m.forward_pose_all(np.zeros(s))))
        if has_rates:
            calls.append((f"forward_rate(rates {shape})", lambda s=shape: m.forward_rate(state, np.zeros(s))))
    for shape in bad_shapes(n_p):
        calls += [
            (f"platform_pose(passive {shape})", lambda s=shape: m.platform_pose(state.actuated, np.zeros(s))),
            (
                f"singularities(passive {shape})",
                lambda s=shape: m.singularities(Configuration(state.actuated, np.zeros(s), state.pose)),
            ),
        ]
    if m.capabilities.inverse is not None:
        # (..., 3, 3) is a rotation's short form, (..., 3) a planar or translation one, (..., 2)
        # a planar translation's
        kind = m.manifest.pose_kind
        shapes = [(3, 4), (4, 5), (4,), (16,)]
        shapes += [(3,), (2, 3)] if kind == "planar_translation" else [(2,), (2, 2)]
        shapes += [(4, 3)] if kind in ("transform", "rotation") else []
        shapes += [(3, 3)] if kind != "rotation" else []
        for shape in shapes:
            pose = np.eye(*shape) if len(shape) == 2 else np.ones(shape)
            calls.append((f"inverse_pose(pose {shape})", lambda p=pose: m.inverse_pose(p)))
    if has_rates:
        size = m.manifest.twist_size
        for shape in [(size + 1,), (size - 1,), (size, 1)]:
            calls.append((f"inverse_rate(twist {shape})", lambda s=shape: m.inverse_rate(state, np.zeros(s))))
    expect_bad_input(name, calls)


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_a_guess_of_the_wrong_shape_raises_bad_input(name, backend):
    """forward_pose(actuated, guess=...) with passive values of the wrong shape raises
    BadInputError, whatever the number of passive variables."""
    m = h.load(name, backend)
    state = state_of(m)
    calls = [
        (f"forward_pose(guess {shape})", lambda s=shape: m.forward_pose(state.actuated, guess=np.zeros(s)))
        for shape in bad_shapes(len(m.passive_names))
    ]
    expect_bad_input(name, calls)


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_batches_that_do_not_broadcast_raise_bad_input(name, backend):
    """Leading batch shapes that do not broadcast against each other raise BadInputError."""
    m = h.load(name, backend)
    state = state_of(m)
    actuated, passive = np.tile(state.actuated, (5, 1)), np.tile(state.passive, (4, 1))
    calls = [
        ("platform_pose(actuated (5, n_a), passive (4, n_p))", lambda: m.platform_pose(actuated, passive)),
        ("loop_closure(actuated (5, n_a), passive (4, n_p))", lambda: m.loop_closure(actuated, passive)),
    ]
    if m.passive_names:
        calls.append(
            ("forward_pose(actuated (5, n_a), guess (4, n_p))", lambda: m.forward_pose(actuated, guess=passive))
        )
    expect_bad_input(name, calls)


def rejected_or_flagged(call, flagged) -> str | None:
    """None if ``call()`` raises BadInputError or returns a result that ``flagged`` accepts."""
    try:
        result = call()
    except BadInputError:
        return None
    except Exception as error:  # noqa: BLE001 - reported with its type
        return f"raised {type(error).__name__}: {error}"
    return None if flagged(result) else "returned a result flagged valid / converged, or NaN"


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_non_finite_inputs_are_rejected_or_flagged(name, backend):
    """NaN (and inf) in joint values, poses, guesses and rates: BadInputError, or a result
    flagged not converged / with no valid branch or mode; results without such flags (poses,
    residuals, rates) must raise."""
    m = h.load(name, backend)
    state = state_of(m)
    nan_actuated = state.actuated.copy()
    nan_actuated[0] = np.nan
    inf_actuated = state.actuated.copy()
    inf_actuated[-1] = np.inf
    nan_passive = state.passive.copy()
    if nan_passive.size:
        nan_passive[0] = np.nan
    nan_pose = state.pose.copy()
    nan_pose[0, 0] = np.nan
    has_rates = m.capabilities.rates is not None or m.capabilities.legs is not None

    def not_converged(result):  # a Newton result for non-finite input
        return not np.asarray(result.converged).any()

    def no_valid_mode(result):  # assembly modes or inverse branches for non-finite input
        return not np.asarray(result.valid).any()

    def never(result):  # results without a validity flag: only BadInputError will do
        return False

    calls = {
        "platform_pose(NaN actuated)": (lambda: m.platform_pose(nan_actuated, state.passive), never),
        "loop_closure(inf actuated)": (lambda: m.loop_closure(inf_actuated, state.passive), never),
        "forward_pose(NaN actuated)": (lambda: m.forward_pose(nan_actuated, guess=state, strict=False), not_converged),
        "forward_pose(NaN actuated, strict)": (lambda: m.forward_pose(nan_actuated, guess=state), not_converged),
        "forward_pose(inf actuated)": (lambda: m.forward_pose(inf_actuated, guess=state, strict=False), not_converged),
        "singularities(NaN state)": (
            lambda: m.singularities(Configuration(nan_actuated, state.passive, state.pose)),
            never,
        ),
    }
    if m.passive_names:
        calls["forward_pose(NaN guess)"] = (
            lambda: m.forward_pose(state.actuated, guess=nan_passive, strict=False),
            not_converged,
        )
        calls["platform_pose(NaN passive)"] = (lambda: m.platform_pose(state.actuated, nan_passive), never)
    if m.capabilities.inverse is not None:
        calls["inverse_pose(NaN pose)"] = (
            lambda: m.inverse_pose(nan_pose, strict=False),
            no_valid_mode,
        )
    if m.capabilities.forward is not None or not m.passive_names:
        calls["forward_pose_all(NaN actuated)"] = (
            lambda: m.forward_pose_all(nan_actuated, strict=False),
            no_valid_mode,
        )
    if has_rates:
        nan_rates = np.full(state.actuated.shape, np.nan)
        nan_twist = np.full(m.manifest.twist_size, np.nan)
        calls["forward_rate(NaN rates)"] = (lambda: m.forward_rate(state, nan_rates), never)
        nan_state = Configuration(state.actuated, nan_passive if m.passive_names else state.passive, state.pose)
        calls["forward_rate(NaN state)"] = (lambda: m.forward_rate(nan_state, state.actuated), never)
        calls["inverse_rate(NaN twist)"] = (lambda: m.inverse_rate(state, nan_twist), never)
        calls["passive_rates(NaN rates)"] = (lambda: m.passive_rates(state, nan_rates), never)
    failures = [f"{label}: {why}" for label, (call, ok) in calls.items() if (why := rejected_or_flagged(call, ok))]
    assert not failures, f"{name}: non-finite input passed silently:\n" + "\n".join(failures)


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_tracker_rejects_non_finite_actuated_values(name, backend):
    """ForwardPoseTracker.solve with a NaN actuated value raises BadInputError (as
    forward_pose does), and keeps its last good solution."""
    m = h.load(name, backend)
    if not m.passive_names:
        pytest.skip(f"{name} has no passive variables: there is no Newton loop to track")
    state = state_of(m)
    tracker = m.tracker(state)
    before = np.array(tracker.passive)
    bad = state.actuated.copy()
    bad[0] = np.nan
    with pytest.raises(BadInputError):
        tracker.solve(bad)
    assert np.array_equal(tracker.passive, before), "the tracker lost its last good solution"


#: (capability, operation, call) for every operation that needs a capability
CAPABILITY_OPERATIONS = [
    ("inverse", "inverse_pose", lambda m, s: m.inverse_pose(s.pose)),
    ("rates", "rate_jacobians", lambda m, s: m.rate_jacobians(s)),
    ("legs", "leg_jacobians", lambda m, s: m.leg_jacobians(s)),
    ("drawing", "drawing", lambda m, s: m.drawing(s)),
]


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_operations_without_their_capability_raise_unsupported(name, backend):
    """An operation the manifest's capabilities do not offer raises
    parakin.UnsupportedOperationError: inverse_pose without an inverse, forward_pose_all
    without a forward elimination (a serial chain, with no passive joints, has its one mode),
    rate_jacobians without a rate model, leg_jacobians without legs, forward_rate /
    inverse_rate with neither, drawing without a drawing kernel."""
    m = h.load(name, backend)
    capabilities = m.capabilities
    state = Configuration(m.home_actuated, m.home_passive, h.home_pose(m))
    operations = [(op, call) for cap, op, call in CAPABILITY_OPERATIONS if getattr(capabilities, cap) is None]
    operations = [(op, call) for op, call in operations if hasattr(m, op)]
    if capabilities.forward is None and m.passive_names:
        operations.append(("forward_pose_all", lambda m, s: m.forward_pose_all(s.actuated)))
    if capabilities.rates is None and capabilities.legs is None:
        operations += [
            ("forward_rate", lambda m, s: m.forward_rate(s, np.zeros_like(s.actuated))),
            ("inverse_rate", lambda m, s: m.inverse_rate(s, np.zeros(6))),
        ]
    if capabilities.forward is None and not m.passive_names:  # the chain's one forward pose
        modes = m.forward_pose_all(state.actuated)
        assert int(modes.count) == 1 and np.allclose(modes.poses[0], m.forward_pose(state.actuated).pose)
    if not operations:
        pytest.skip(f"{name} has every capability")
    failures = []
    for operation, call in operations:
        try:
            call(m, state)
        except UnsupportedOperationError:
            continue
        except Exception as error:  # noqa: BLE001 - reported with its type
            failures.append(f"{operation}: raised {type(error).__name__}: {error}")
        else:
            failures.append(f"{operation}: no error")
    assert not failures, f"{name}: missing capabilities not reported:\n" + "\n".join(failures)


@pytest.mark.parametrize("name", NAMES)
def test_architecturally_singular_geometries_warn_and_forward_pose_all_says_so(name):
    """For the defaults and every named example's parameters: a geometry the manifest's
    architecture measures call singular warns on load (ArchitectureSingularityWarning), one they
    call regular does not, and on a singular one forward_pose_all at the home inputs raises
    SingularConfigurationError (or its SelfMotionError) instead of returning modes."""
    manifest = parakin.metadata(name)
    info = manifest.capabilities.architecture
    if info is None:
        pytest.skip(f"{name} has no architecture measures (manifest capabilities.architecture)")
    geometries = {"defaults": {}} | {f"example {e.name!r}": dict(e.parameters) for e in manifest.examples}
    for label, parameters in geometries.items():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            m = parakin.load(name, backend="numpy", **parameters)
        warned = [w for w in caught if issubclass(w.category, parakin.ArchitectureSingularityWarning)]
        singular = any(abs(value) < info.tolerance for value in m.architecture().values())
        assert bool(warned) == singular, f"{name} {label}: warned {bool(warned)}, singular {singular}"
        if singular and m.capabilities.forward is not None:
            with pytest.raises(parakin.SingularConfigurationError):
                m.forward_pose_all(m.home_actuated)
    assert not h.load(name, "numpy").is_architecturally_singular()


#: the least pivot ratio (min |u_kk| / max |u_kk| of the closure Jacobian's elimination) of a
#: regular home: far above the runtime's singular_ratio (1e-10), so that the home is no near miss
REGULAR_HOME = 1e-6


@pytest.mark.parametrize("name", NAMES)
def test_default_home_is_a_regular_configuration(name):
    """Usable defaults: with its default parameters a mechanism loads without
    ArchitectureSingularityWarning, and its home is a regular configuration: it closes the loop
    (residual within the manifest's closure tolerance), the closure Jacobian there has a pivot
    ratio above REGULAR_HOME (no type II singularity), forward_pose from the home's actuated
    values without a guess converges back to the home's passive values, and forward_pose_all
    there finds the home among its assembly modes. (A singular home made `parakin plot` draw a
    self-motion and the exported C example exit 1.)"""
    from parakin.solvers.linalg import pivoted_solve

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = parakin.load(name, backend="numpy")
    warned = [str(w.message) for w in caught if issubclass(w.category, parakin.ArchitectureSingularityWarning)]
    assert not warned, f"{name}: the default geometry is architecturally singular: {warned}"
    closure = m.loop_closure(m.home_actuated, m.home_passive)
    residual = float(np.abs(closure["residual"]).max(initial=0.0))
    assert residual <= m.tolerances["closure"], f"{name}: the home does not close (residual {residual:.3g})"
    jacobian = closure["jacobian"]
    ratio = float(pivoted_solve(jacobian, np.zeros(jacobian.shape[-1]))[1])
    assert ratio > REGULAR_HOME, f"{name}: closure Jacobian pivot ratio {ratio:.3g} at home (type II singular)"
    forward = m.forward_pose(m.home_actuated)
    error = np.abs(h.wrapped(forward.passive - m.home_passive, h.revolute_passive(m))).max(initial=0.0)
    assert forward.converged and error < 1e-8, f"{name}: forward_pose from home's inputs lands {error:.3g} away"
    if m.capabilities.forward is not None:
        modes = m.forward_pose_all(m.home_actuated)
        assert int(modes.count) >= 1, f"{name}: forward_pose_all finds no assembly mode at home"
        distance = np.where(modes.valid, np.abs(modes.poses - h.home_pose(m)).max(axis=(-2, -1)), np.inf).min()
        assert distance < 1e-8, f"{name}: no assembly mode at the home pose (nearest {distance:.3g})"


# ---------------------------------------------------------------------------- batches and NaN
def assert_same(batched, singles, what) -> None:
    singles = np.stack([np.asarray(s, dtype=float) for s in singles])
    batched = np.asarray(batched, dtype=float)
    assert batched.shape == singles.shape, f"{what}: batch shape {batched.shape} vs {singles.shape}"
    assert (np.isnan(batched) == np.isnan(singles)).all(), f"{what}: NaN pattern differs"
    scale = 1.0 + np.abs(np.nan_to_num(singles)).max(initial=0.0)
    error = np.abs(np.nan_to_num(batched) - np.nan_to_num(singles)).max(initial=0.0)
    assert error <= 1e-12 * scale, f"{what}: batch vs single calls differ by {error:.3g}"


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_a_batch_of_five_equals_five_single_calls(name, backend):
    """Every solver on a batch (5, n) gives the results of 5 single calls."""
    m = h.load(name, backend)
    rng = np.random.default_rng(h.seed(name, "batch"))
    if m.capabilities.inverse is not None:
        configurations = closed_configurations(name, backend, 5)
    else:
        poses, actuated = h.sample_poses(m, rng, 5)
        configurations = [Configuration(a, m.home_passive, p) for a, p in zip(actuated, poses, strict=True)]
    assert len(configurations) == 5
    actuated = np.stack([c.actuated for c in configurations])
    passive = np.stack([c.passive for c in configurations])
    poses = np.stack([c.pose for c in configurations])
    batch = Configuration(actuated, passive, poses)
    singles = [Configuration(a, p, T) for a, p, T in zip(actuated, passive, poses, strict=True)]
    assert_same(
        m.platform_pose(actuated, passive),
        [m.platform_pose(a, p) for a, p in zip(actuated, passive, strict=True)],
        "pose",
    )
    closure = m.loop_closure(actuated, passive)
    for key, value in closure.items():
        assert_same(
            value, [m.loop_closure(a, p)[key] for a, p in zip(actuated, passive, strict=True)], f"loop_closure {key}"
        )
    factors = m.singularities(batch)
    for key, value in factors.items():
        assert_same(value, [m.singularities(s)[key] for s in singles], f"singularities {key}")
    guesses = passive + 1e-4 * rng.normal(size=passive.shape)
    fk = m.forward_pose(actuated, guess=guesses, strict=False)
    fk1 = [m.forward_pose(a, guess=g, strict=False) for a, g in zip(actuated, guesses, strict=True)]
    for key in ("pose", "passive", "converged", "iterations"):
        assert_same(getattr(fk, key), [getattr(f, key) for f in fk1], f"forward_pose {key}")
    if m.capabilities.inverse is not None:
        ik, ik1 = m.inverse_pose(poses, strict=False), [m.inverse_pose(T, strict=False) for T in poses]
        for key in ("actuated", "passive", "valid"):
            assert_same(getattr(ik, key), [getattr(r, key) for r in ik1], f"inverse_pose {key}")
    if m.capabilities.forward is not None or not m.passive_names:
        modes, modes1 = m.forward_pose_all(actuated), [m.forward_pose_all(a) for a in actuated]
        assert_same(modes.count, [r.count for r in modes1], "forward_pose_all count")
        assert_same(modes.valid, [r.valid for r in modes1], "forward_pose_all valid")
        valid = np.asarray(modes.valid)[..., None, None]
        assert_same(
            np.where(valid, modes.poses, 0), [np.where(r.valid[:, None, None], r.poses, 0) for r in modes1], "modes"
        )
    if m.capabilities.rates is not None or m.capabilities.legs is not None:
        rates = rng.normal(size=actuated.shape)
        assert_same(
            m.forward_rate(batch, rates),
            [m.forward_rate(s, r) for s, r in zip(singles, rates, strict=True)],
            "forward_rate",
        )
        twist = rng.normal(size=(5, m.manifest.twist_size))
        if m.capabilities.rates is not None and m.capabilities.rates.constraints:  # twists it can make
            twist = m.forward_rate(batch, rng.normal(size=actuated.shape))
        back = m.inverse_rate(batch, twist)
        back1 = [m.inverse_rate(s, t) for s, t in zip(singles, twist, strict=True)]
        assert_same(back.actuated, [b.actuated for b in back1], "inverse_rate actuated")
        assert_same(back.passive, [b.passive for b in back1], "inverse_rate passive")


def far_actuated(m, rng) -> np.ndarray:
    """The manifest's home actuated values, those of a closed configuration near home, and
    large random perturbations of the latter (some unreachable, some singular)."""
    center = state_of(m).actuated
    perturbed = [h.perturb_actuated(m, center, rng, size) for size in (1, 3, 10) for _ in range(4)]
    return np.stack([m.home_actuated, center, *perturbed])


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_an_empty_batch_gives_empty_results(name, backend):
    """A leading batch shape (0,) is a batch like any other: empty results of the right shapes."""
    m = h.load(name, backend)
    n_a, n_p = len(m.actuated_names), len(m.passive_names)
    empty_a, empty_p = np.zeros((0, n_a)), np.zeros((0, n_p))
    assert m.platform_pose(empty_a, empty_p).shape == (0, 4, 4)
    assert m.loop_closure(empty_a, empty_p)["residual"].shape == (0, n_p)
    assert m.forward_pose(empty_a, guess=empty_p, strict=False).pose.shape == (0, 4, 4)
    if m.capabilities.inverse is not None:
        branches = len(m.capabilities.inverse.combinations)
        assert m.inverse_pose(np.zeros((0, 4, 4)), strict=False).actuated.shape == (0, branches, n_a)
    if m.capabilities.forward is not None or not n_p:
        assert m.forward_pose_all(empty_a).count.shape == (0,)


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_no_silent_nan_from_forward_pose_far_from_home(name, backend):
    """Newton from a closed configuration near home for large random inputs: what is flagged
    converged is finite and closes the loop."""
    m = h.load(name, backend)
    actuated = far_actuated(m, np.random.default_rng(h.seed(name, "far")))
    guess = np.broadcast_to(state_of(m).passive, actuated.shape[:-1] + m.home_passive.shape)
    fk = m.forward_pose(actuated, guess=guess, strict=False)
    converged = fk.converged
    assert np.isfinite(fk.pose[converged]).all() and np.isfinite(fk.passive[converged]).all()
    assert (fk.residual[converged] <= 1e-12).all()
    for index in np.flatnonzero(converged):  # one by one: an empty batch is another test's subject
        closure = np.abs(m.loop_closure(actuated[index], fk.passive[index])["residual"]).max(initial=0.0)
        assert closure <= 1e-12, f"{name}: input {index}: a converged Newton result does not close the loop"


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_no_silent_nan_from_forward_pose_all_far_from_home(name, backend):
    """forward_pose_all (strict=False) for large random inputs (some with complex roots, some
    with no assembly mode): valid modes are finite and close the loop; count = valid modes."""
    m = h.load(name, backend)
    if m.capabilities.forward is None and m.passive_names:
        pytest.skip(f"{name} has no closed-form forward elimination (manifest capabilities.forward)")
    actuated = far_actuated(m, np.random.default_rng(h.seed(name, "far")))
    modes = m.forward_pose_all(actuated, strict=False)
    assert np.isfinite(modes.poses[modes.valid]).all() and np.isfinite(modes.passive[modes.valid]).all()
    assert (modes.count == modes.valid.sum(-1)).all()
    grid = np.broadcast_to(actuated[:, None], modes.passive.shape[:-1] + actuated.shape[-1:])
    # only the modes: the other slots hold placeholders where the closure may be undefined
    closure = np.abs(m.loop_closure(grid[modes.valid], modes.passive[modes.valid])["residual"]).max(-1, initial=0.0)
    assert (closure < h.CLOSURE).all(), f"{name}: a valid mode does not close the loop"


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_no_silent_nan_from_inverse_pose_far_from_home(name, backend):
    """inverse_pose for the home pose and large random perturbations of it: valid branches are
    finite and close the loop."""
    m = h.load(name, backend)
    require_inverse(m)
    rng = np.random.default_rng(h.seed(name, "far poses"))
    home = h.home_pose(m)
    poses = np.stack([home, *(h.perturb_pose(m, home, rng, size) for size in (1, 3, 10) for _ in range(4))])
    ik = m.inverse_pose(poses, strict=False)
    actuated, passive = ik.actuated[ik.valid], ik.passive[ik.valid]
    assert np.isfinite(actuated).all() and np.isfinite(passive).all()
    closure = np.abs(m.loop_closure(actuated, passive)["residual"]).max(-1, initial=0.0)
    assert (closure < h.CLOSURE).all(), f"{name}: a valid far branch does not close the loop"
