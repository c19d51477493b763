"""Issue 18 items 4-8 and 11 at the runtime's edges: modes indexed as modes, ``real`` that means
real, rigid platform poses, validated stiffness, every pose kind validated, and one outcome per
input on every backend for degenerate Newton guesses and tolerances."""

from __future__ import annotations

import warnings

import contract_helpers as h
import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError, InconsistentInputError, NoSuchModeError
from parakin.pose import POSE_KINDS, transform_from_pose

BACKENDS = ["numpy", "casadi", "compiled"]


def _load(name: str, backend: str, **parameters: object) -> parakin.Mechanism:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        return parakin.load(name, backend=backend, **parameters)


def _closure(m: parakin.Mechanism, actuated: np.ndarray, passive: np.ndarray) -> np.ndarray:
    """Max-norm loop-closure residual per entry, recomputed by the public kernel."""
    return np.abs(m.loop_closure(actuated, passive)["residual"]).max(-1)


# ---------------------------------------------------------------------------- item 4: mode(k)
@pytest.mark.parametrize("backend", BACKENDS)
def test_mode_k_is_the_kth_valid_mode_and_closes(backend):
    """spm at home: every mode(k), k < count, is the k-th valid slot and closes the loop
    (recomputed residual < 1e-9); at 6bfa97b mode(0) was slot 0, residual 0.219."""
    m = _load("spm", backend)
    modes = m.forward_pose_all(m.home_actuated)
    count = int(modes.count)
    assert count == 8 and len(modes) == count
    slots = np.flatnonzero(modes.valid)
    for k in range(count):
        config = modes.mode(k)
        assert np.array_equal(config.passive, modes.passive[slots[k]])
        assert np.array_equal(config.pose, modes.poses[slots[k]])
        residual = float(_closure(m, config.actuated, config.passive))
        assert residual < 1e-9, f"mode {k}: closure residual {residual:.3g}"
    listed = list(modes)
    assert len(listed) == count and all(np.array_equal(c.pose, modes.mode(k).pose) for k, c in enumerate(listed))
    with pytest.raises(NoSuchModeError, match=r"there are 8 modes"):
        modes.mode(count)
    with pytest.raises(NoSuchModeError):
        modes.mode(-1)
    with pytest.raises(NoSuchModeError, match="integer"):
        modes.mode(1.0)  # type: ignore[arg-type]
    # slots stay reachable by name: slot 0 is not a mode here and does not close
    assert not modes.valid[0]
    assert float(_closure(m, modes.slot(0).actuated, modes.slot(0).passive)) > 0.1
    with pytest.raises(NoSuchModeError, match=r"\[0, 16\)"):
        modes.slot(16)


def test_mode_k_of_a_batch_is_mode_k_of_every_input():
    """A batch: mode(k) is mode k of each input (as the single-input call gives it); an index
    that some input lacks raises naming that input; len() and iteration refuse a batch."""
    m = _load("spm", "numpy")
    theta = np.stack([m.home_actuated, m.home_actuated + 0.2])
    modes = m.forward_pose_all(theta)
    smallest = int(modes.count.min())
    for k in range(smallest):
        batch = modes.mode(k)
        for i in range(2):
            single = m.forward_pose_all(theta[i]).mode(k)
            assert np.abs(batch.pose[i] - single.pose).max() < 1e-12
        assert (_closure(m, batch.actuated, batch.passive) < 1e-9).all()
    with pytest.raises(NoSuchModeError, match="batch index"):
        modes.mode(int(modes.count.max()))
    with pytest.raises(NoSuchModeError, match="single input"):
        len(modes)
    with pytest.raises(NoSuchModeError):
        list(modes)
    assert bool(modes)


# ---------------------------------------------------------------------------- item 5: real
@pytest.mark.parametrize("backend", ["numpy", "compiled"])
def test_real_means_real_on_the_homotopy_pipeline(backend):
    """stewart, home lengths with l1 = 1.2: of 40 path ends, 34 are complex (at 6bfa97b all 40
    were flagged real). Every slot flagged real ends at a real endpoint (imaginary part below
    the real_endpoint tolerance) or is a mode; no complex end is real."""
    m = _load("stewart", backend)
    theta = m.home_actuated.copy()
    theta[0] = 1.2
    modes = m.forward_pose_all(theta)
    kinds = m.manifest.abi.root_kinds
    complex_end = modes.root_kind == kinds.index("complex")
    assert complex_end.sum() == 34
    assert not (modes.real & complex_end).any()
    assert (modes.root[modes.real] < m.tolerances["real_endpoint"]).all()
    assert modes.real.sum() == int(modes.real_roots) == 6
    assert (modes.real | ~modes.valid).all()


@pytest.mark.parametrize("backend", ["numpy", "compiled"])
def test_real_means_real_on_the_polynomial_pipeline(backend):
    """spm at home (and near-home inputs): slots flagged real hold a finite real root of the
    polynomial (simple or cluster) or a root at infinity, never a near-real pair or an empty slot;
    the count agrees with real_roots + at_infinity, per branch combination."""
    m = _load("spm", backend)
    rng = np.random.default_rng(5)
    theta = m.home_actuated + 0.3 * rng.standard_normal((20, 3))
    modes = m.forward_pose_all(theta, strict=False)
    kinds = m.manifest.abi.root_kinds
    real_kind = np.isin(modes.root_kind, [kinds.index("simple"), kinds.index("cluster")])
    assert np.array_equal(modes.real, real_kind | modes.valid)
    assert not (modes.real & (modes.root_kind < 0)).any()
    per_root = modes.real.reshape(modes.real.shape[:-1] + (-1, modes.branch_count)).any(-1).sum(-1)
    assert (per_root <= modes.real_roots + modes.at_infinity).all()


def _stewart_near_home(m: parakin.Mechanism) -> np.ndarray:
    """The 200 inputs near home of issue 18 item 5: home lengths x (1 + 0.1 N(0, 1)), seed 18."""
    rng = np.random.default_rng(18)
    return m.home_actuated * (1 + 0.1 * rng.standard_normal((200, 6)))


def _check_forward_pose_without_guess(m: parakin.Mechanism, inputs: np.ndarray) -> None:
    """Every input with an assembly mode: forward_pose without a guess converges (one batch
    call, strict), closes the loop (recomputed) and lands on one of forward_pose_all's modes."""
    modes = m.forward_pose_all(inputs, strict=False)
    good = modes.count > 0
    solved = m.forward_pose(inputs[good])
    assert (solved.residual <= 1e-12).all()
    assert (_closure(m, solved.actuated, solved.passive) < 1e-10).all()
    distance = np.abs(modes.poses[good] - solved.pose[:, None]).max(axis=(-2, -1))
    assert (np.where(modes.valid[good], distance, np.inf).min(-1) < 1e-8).all()


@pytest.mark.parametrize("backend", BACKENDS)
def test_forward_pose_without_a_guess_seeds_from_modes_only(backend):
    """Inputs 146, 155 and 159 of the 200 near home (2 modes each) failed at 6bfa97b (numpy,
    casadi: BadInputError "non-finite"; compiled: SingularConfigurationError): Newton was seeded
    from a complex endpoint flagged real. With two neighbours."""
    m = _load("stewart", backend)
    _check_forward_pose_without_guess(m, _stewart_near_home(m)[[146, 150, 155, 158, 159]])


@pytest.mark.slow
@pytest.mark.parametrize("backend", BACKENDS)
def test_forward_pose_without_a_guess_on_200_inputs_near_home(backend):
    """The full 200 inputs of issue 18 item 5 (199 with a mode), on every backend."""
    m = _load("stewart", backend)
    _check_forward_pose_without_guess(m, _stewart_near_home(m))


# ---------------------------------------------------------------------------- item 6: rigid poses
@pytest.mark.parametrize("backend", BACKENDS)
def test_platform_pose_is_rigid_or_refused(backend):
    """spm's joint values that did not close once gave |R^T R - I| = 0.09 (6bfa97b). Its passive
    values are now a quaternion, normalised by the pose kernel, so any values give a rigid pose;
    a pose kernel that does give a non-rigid pose off closure (one built from points, as a user's
    mechanism may) is refused with InconsistentInputError naming the closure residual. At a mode
    the pose is rigid to 1e-14 and equals the mode's pose (1e-9); a non-converged forward_pose
    never returns a non-rigid pose."""
    m = _load("spm", backend)
    modes = m.forward_pose_all(m.home_actuated)
    closed = modes.mode(0).passive
    passive = closed + np.array([0.1, -0.2, 0.15, -0.05])[: closed.size]  # a unit quaternion, moved off
    residual = float(_closure(m, m.home_actuated, passive))
    assert residual > 0.1
    off = m.platform_pose(m.home_actuated, passive)[:3, :3]
    assert np.abs(off.T @ off - np.eye(3)).max() < 1e-14
    for config in modes:
        pose = m.platform_pose(config.actuated, config.passive)
        rotation = pose[:3, :3]
        assert np.abs(rotation.T @ rotation - np.eye(3)).max() < 1e-14
        assert np.abs(pose - config.pose).max() < 1e-9
    failed = m.forward_pose(m.home_actuated, guess=passive, max_iterations=0, strict=False)
    assert not failed.converged
    rotation = failed.pose[:3, :3]  # the last iterate's pose: rigid (or NaN), never off rigid
    assert np.isnan(failed.pose).all() or np.abs(rotation.T @ rotation - np.eye(3)).max() < 1e-14
    # a kernel whose pose is not rigid off closure (the rotation block scaled by |q|^2)
    call = m.backend.call

    def unnormalised(kernel, *inputs):
        out = call(kernel, *inputs)
        if kernel == "platform_pose":
            q = np.asarray(inputs[1])
            out = dict(out, pose=out["pose"] * np.where(np.arange(4) < 3, 1.0, 0.0)[:, None] * (q * q).sum(-1)[
                ..., None, None] + np.eye(4) * np.where(np.arange(4) == 3, 1.0, 0.0))  # fmt: skip
        return out

    m.backend.call = unnormalised
    try:
        with pytest.raises(InconsistentInputError, match=rf"closure residual {residual:.3g}"):
            m.platform_pose(m.home_actuated, passive)
        with pytest.raises(InconsistentInputError, match=r"batch index \(1,\)"):
            m.platform_pose(m.home_actuated, np.stack([closed, passive]))
    finally:
        del m.backend.call


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_single_chain_pose_kernel_stays_rigid_off_closure(backend):
    """sam reads the platform from its first leg: any joint values give a rigid pose (|R^T R - I|
    < 1e-14), closed or not, so platform_pose returns it."""
    m = _load("sam", backend)
    passive = m.home_passive + 0.1
    assert float(_closure(m, m.home_actuated, passive)) > 1e-3
    rotation = m.platform_pose(m.home_actuated, passive)[:3, :3]
    assert np.abs(rotation.T @ rotation - np.eye(3)).max() < 1e-14 and np.linalg.det(rotation) > 0


# ---------------------------------------------------------------------------- item 7: stiffness
@pytest.fixture(scope="module")
def sps_state():
    m = _load("sps", "numpy")
    return m, m.forward_pose(m.home_actuated)


@pytest.mark.parametrize(
    ("value", "match"),
    [
        (["1e5", "1e5", "1e5"], "real numbers"),
        ("1e5", "numeric"),
        ([1e5 + 1j, 1e5, 1e5], "complex"),
        ([True, True, True], "boolean"),
        ([1e5, -1e5, 1e5], r"actuator_stiffness\[1\] = -100000"),
        ([1e5, 0.0, 1e5], "> 0"),
        ([1e5, np.nan, 1e5], "non-finite"),
        ([1e5, 1e5], "shape"),
        ([[1e5, 1e3, 0], [0, 1e5, 0], [0, 0, 1e5]], "not symmetric"),
        ([[1e5, 2e5, 0], [2e5, 1e5, 0], [0, 0, 1e5]], "not positive definite: smallest eigenvalue -100000"),
    ],
)
def test_stiffness_refuses_what_is_not_a_stiffness(sps_state, value, match):
    """At 6bfa97b strings were parsed, complex values lost their imaginary part, booleans,
    negative and non-symmetric stiffnesses were accepted."""
    m, state = sps_state
    with pytest.raises(BadInputError, match=match):
        m.stiffness(state, value)


def test_stiffness_of_a_valid_diagonal_and_matrix(sps_state):
    """A positive diagonal and the same matrix give the same K = G^T K_q G (symmetric, positive
    definite), recomputed from the actuation matrix."""
    from parakin.solvers.statics import actuation_matrix

    m, state = sps_state
    diagonal = np.array([1e5, 2e5, 3e5])
    k = m.stiffness(state, diagonal)
    assert np.abs(k - m.stiffness(state, np.diag(diagonal))).max() == 0.0
    g = actuation_matrix(m, state)
    assert np.abs(k - g.T @ np.diag(diagonal) @ g).max() <= 1e-9 * np.abs(k).max()
    assert np.abs(k - k.T).max() <= 1e-12 * np.abs(k).max() and np.linalg.eigvalsh(k).min() > 0


# ---------------------------------------------------------------------------- item 8: pose kinds
#: per pose kind: a short form and the transform it means, and a pose that kind cannot take
POSE_CASES = {
    "transform": (np.eye(4), np.eye(4), np.diag([1.0, 1.0, 1.1, 1.0]), "rigid"),
    "rotation": (np.eye(3), np.eye(4), [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.2], [0, 0, 0, 1]], "off by 0.2"),
    "planar": (
        [0.1, 0.2, np.pi / 2],
        [[0, -1, 0, 0.1], [1, 0, 0, 0.2], [0, 0, 1, 0], [0, 0, 0, 1]],
        [[1, 0, 0, 0.1], [0, 1, 0, 0.2], [0, 0, 1, 0.3], [0, 0, 0, 1]],
        "off by 0.3",
    ),
    "translation": (
        [0.1, 0.2, 0.3],
        [[1, 0, 0, 0.1], [0, 1, 0, 0.2], [0, 0, 1, 0.3], [0, 0, 0, 1]],
        [[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],
        "off by 1",
    ),
    "planar_translation": (
        [0.0, 0.4],
        [[1, 0, 0, 0], [0, 1, 0, 0.4], [0, 0, 1, 0], [0, 0, 0, 1]],
        [[1, 0, 0, 0], [0, 1, 0, 0.4], [0, 0, 1, 0.1], [0, 0, 0, 1]],
        "off by 0.1",
    ),
}


def test_every_pose_kind_has_a_case():
    assert set(POSE_CASES) == set(POSE_KINDS)


@pytest.mark.parametrize("kind", sorted(POSE_KINDS))
def test_every_pose_kind_reads_its_short_form_and_refuses_other_poses(kind):
    """Each kind: its short form is the documented transform; a pose the kind cannot take is a
    BadInputError naming how far it is off (a planar_translation point 0.1 m off the plane was
    accepted by the five-bar at 6bfa97b, which had no such kind)."""
    short, full, bad, match = POSE_CASES[kind]
    assert np.abs(transform_from_pose(short, kind) - np.asarray(full, dtype=float)).max() < 1e-15
    with pytest.raises(BadInputError, match=match):
        transform_from_pose(bad, kind)
    with pytest.raises(BadInputError, match="must be"):
        transform_from_pose(np.zeros(5), kind)


def test_planar_translation_refuses_a_rotation_and_batches():
    """A rotation about z is refused too (a planar translating platform does not turn); a batch
    of points (..., 2) gives (..., 4, 4), the offending entry named."""
    turn = transform_from_pose([0.0, 0.0, 0.3], "planar")
    with pytest.raises(BadInputError, match=f"off by {np.sin(0.3):.3g}"):
        transform_from_pose(turn, "planar_translation")
    points = np.array([[0.1, 0.2], [0.3, -0.1]])
    poses = transform_from_pose(points, "planar_translation")
    assert poses.shape == (2, 4, 4) and np.array_equal(poses[:, :2, 3], points) and (poses[:, 2, 3] == 0).all()
    lifted = poses.copy()
    lifted[1, 2, 3] = 1e-3
    with pytest.raises(BadInputError, match=r"batch index \(1,\)"):
        transform_from_pose(lifted, "planar_translation")
    with pytest.raises(BadInputError, match="unknown pose kind"):
        transform_from_pose(np.eye(4), "planar_rotation")


# ---------------------------------------------------------------------------- item 11: one outcome
def _outcome(call) -> tuple[str, str]:
    try:
        call()
    except parakin.errors.ParakinError as error:
        return type(error).__name__, str(error)
    return "ok", ""


def test_a_zero_quaternion_guess_is_the_same_bad_input_on_every_backend():
    """stewart, guess (x, y, z, 0, 0, 0, 0): the closure is undefined there (q / |q|). At
    6bfa97b numpy and casadi said "non-finite" of a finite guess and compiled raised
    SingularConfigurationError (C's fmax dropped the NaN). Now BadInputError naming the guess
    on every backend, with the same message."""
    outcomes = {}
    for backend in BACKENDS:
        m = _load("stewart", backend)
        guess = np.concatenate([m.home_passive[:3], np.zeros(4)])
        outcomes[backend] = _outcome(lambda m=m, guess=guess: m.forward_pose(m.home_actuated, guess=guess))
    assert len(set(outcomes.values())) == 1, outcomes
    kind, message = outcomes["numpy"]
    assert kind == "BadInputError" and "undefined (NaN) at the guess" in message and "non-finite" not in message
    assert "0.955868" in message  # the guess's x


def test_a_tolerance_below_what_doubles_resolve_is_refused_alike():
    """tolerance=1e-16 converged on one backend and raised ConvergenceError on the others at
    6bfa97b (the closure's rounding differs between kernels); the documented lower bound is now
    MIN_TOLERANCE, refused alike everywhere, and MIN_TOLERANCE itself converges everywhere."""
    from parakin.validation import MIN_TOLERANCE

    outcomes = {}
    for backend in BACKENDS:
        m = _load("stewart", backend)
        outcomes[backend] = _outcome(lambda m=m: m.forward_pose(m.home_actuated, tolerance=1e-16))
        solved = m.forward_pose(m.home_actuated, tolerance=MIN_TOLERANCE)
        assert solved.residual <= MIN_TOLERANCE
    assert len(set(outcomes.values())) == 1, outcomes
    assert outcomes["numpy"][0] == "BadInputError" and "tolerance" in outcomes["numpy"][1]


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_planar_translating_mechanism_refuses_a_point_off_its_plane(backend):
    """Every mechanism of kind planar_translation (the five-bar): a point 0.1 m off the plane
    (4 valid branches at 6bfa97b) is refused naming the offset; (x, y) gives the in-plane pose."""
    names = [n for n in parakin.available() if parakin.metadata(n).pose_kind == "planar_translation"]
    assert names, "no mechanism of pose kind planar_translation"
    for name in names:
        m = _load(name, backend)
        inside = m.inverse_pose(m.forward_pose(m.home_actuated).pose)
        point = inside.pose[:2, 3]
        lifted = inside.pose.copy()
        lifted[2, 3] = 0.1
        with pytest.raises(BadInputError, match="off by 0.1"):
            m.inverse_pose(lifted)
        again = m.inverse_pose(point)
        assert np.array_equal(again.valid, inside.valid)
        assert np.abs(again.actuated[again.valid] - inside.actuated[inside.valid]).max() < 1e-12


def _with_rates() -> list[str]:
    return [
        n
        for n in parakin.available()
        if (parakin.metadata(n).capabilities.rates or parakin.metadata(n).capabilities.legs)
        and parakin.metadata(n).passive
    ]


@pytest.mark.parametrize("name", _with_rates())
def test_rates_twists_and_wrenches_beyond_the_magnitude_bound_are_refused(name):
    """A thorough fuzz run found spm's inverse_rate taking a twist of 9.2e307: its joint rates
    were finite, but forward_rate of them overflowed to NaN. Rates, twists and wrenches are
    bounded like every other input (1e9 SI), refused naming the component; below the bound the
    round trip holds."""
    from parakin.validation import MAX_MAGNITUDE

    m = parakin.load(name, backend="numpy")
    state = m.forward_pose(m.home_actuated)
    rates_model = m.capabilities.rates
    size = len(rates_model.twist) if rates_model is not None else 6
    huge = np.zeros(size)
    huge[-1] = -9.183085953863693e307
    with pytest.raises(BadInputError, match="twist .* is outside its range"):
        m.inverse_rate(state, huge)
    with pytest.raises(BadInputError, match="actuated_rates .* is outside its range"):
        m.forward_rate(state, np.full(len(m.actuated_names), 2 * MAX_MAGNITUDE))
    with pytest.raises(BadInputError, match="wrench .* is outside its range"):
        m.actuator_forces(state, huge)
    twist = h.feasible_twist(m, state, np.linspace(0.1, 0.3, size))
    back = m.forward_rate(state, m.inverse_rate(state, twist).actuated)
    assert np.allclose(back, twist, rtol=1e-8, atol=1e-10)


def test_four_quaternion_guesses_are_not_taken_for_a_pose():
    """A mechanism with four passive values (spm: a unit quaternion): guesses for four inputs are
    a (4, 4) array too; it is read as passive values unless it is a homogeneous transform, so
    both forms give the same Newton solutions."""
    m = parakin.load("spm", backend="numpy")
    actuated = m.home_actuated + 0.01 * np.arange(4)[:, None]
    by_passive = m.forward_pose(actuated, guess=np.tile(m.home_passive, (4, 1)))
    assert by_passive.converged.all()
    by_pose = m.forward_pose(actuated, guess=np.eye(4))
    assert by_pose.converged.all()
    np.testing.assert_allclose(by_passive.pose, by_pose.pose, atol=1e-12)
