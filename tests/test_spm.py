"""3-RRR spherical parallel manipulator: claims of the ED5314 report (section 3) and checks."""

import numpy as np
import pytest

import parakin
from parakin.pose import wrap_angle

DEG = np.pi / 180
AGILE_EYE = {"alpha1": np.pi / 2, "alpha2": np.pi / 2, "beta": np.arctan(np.sqrt(2)), "gamma": np.arctan(np.sqrt(2))}
EXAMPLE_THETA = np.deg2rad([105.0, 60.0, 105.0])  # section 3.2.3


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def spm(request):
    return parakin.load("spm", backend=request.param)


def random_rotations(rng: np.random.Generator, count: int) -> np.ndarray:
    q = rng.normal(size=(count, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def reproduces_inputs(m, modes, theta) -> np.ndarray:
    """Max actuator error of each valid mode through inverse pose (best branch)."""
    errors = []
    for k in np.nonzero(modes.valid)[0]:
        back = m.inverse_pose(modes.poses[k, :3, :3], strict=False)
        errors.append(np.abs(wrap_angle(back.actuated - theta)).max(-1)[back.valid].min())
    return np.array(errors)


def test_section323_example_has_eight_modes_with_alpha1_alpha2_swapped(spm):
    """The report prints alpha1 = 90, alpha2 = 45 deg but claims 8 independent solutions; its own
    eq (5) calls the distal link alpha1. Read as proximal 45, distal 90 deg (our defaults), the
    example has 8 real modes, each reproducing the inputs through inverse pose to 1e-10."""
    modes = spm.forward_pose_all(EXAMPLE_THETA)
    assert int(modes.count) == 8
    errors = reproduces_inputs(spm, modes, EXAMPLE_THETA)
    assert errors.size == 8 and errors.max() < 1e-10
    assert (modes.residual[modes.valid] < 1e-12).all()


def test_section323_example_as_printed_has_two_modes(spm):
    printed = parakin.load("spm", backend=spm.backend.name, alpha1=90 * DEG, alpha2=45 * DEG)
    assert int(printed.forward_pose_all(EXAMPLE_THETA).count) == 2


def test_forward_polynomial_degree_is_eight():
    assert parakin.metadata("spm").capabilities.forward.degree == 8


def test_inverse_pose_eight_branches_reproduce_the_rotation(spm):
    rng = np.random.default_rng(20)
    rotations = random_rotations(rng, 300)
    result = spm.inverse_pose(rotations, strict=False)
    assert result.actuated.shape == (300, 8, 3)
    assert result.valid.any()
    # invalid branches do not close: platform_pose refuses them (issue 18 item 6)
    reached = spm.platform_pose(result.actuated[result.valid], result.passive[result.valid])[..., :3, :3]
    target = np.broadcast_to(rotations[:, None], result.valid.shape + (3, 3))[result.valid]
    assert np.abs(reached - target).max() < 1e-12
    closure = spm.loop_closure(result.actuated, result.passive)
    assert np.abs(closure["residual"][result.valid]).max() < 1e-12


def test_unreachable_orientation_gives_an_empty_mask_with_the_reason(spm):
    rotations = random_rotations(np.random.default_rng(23), 200)
    result = spm.inverse_pose(rotations, strict=False)
    unreachable = ~result.valid.any(-1)
    assert unreachable.any()
    assert np.isfinite(result.actuated).all() and np.isfinite(result.passive).all()
    reasons = np.logical_or.reduce([result.failures[f"leg{i}_reachable"].all(-1) for i in (1, 2, 3)])
    assert (reasons == unreachable).all()
    with pytest.raises(parakin.UnreachablePoseError, match="batch index"):
        spm.inverse_pose(rotations)


def test_every_mode_reproduces_the_inputs_on_random_inputs(spm):
    rng = np.random.default_rng(21)
    rotations = random_rotations(rng, 200)
    branches = spm.inverse_pose(rotations, strict=False)
    keep = branches.valid.any(-1)
    first = np.argmax(branches.valid, axis=-1)
    theta = np.take_along_axis(branches.actuated, first[:, None, None], axis=1)[:, 0][keep]
    modes = spm.forward_pose_all(theta)
    errors = np.concatenate([reproduces_inputs(spm, _row(modes, i), theta[i]) for i in range(theta.shape[0])])
    assert errors.max() < 1e-10
    # the rotation that made the inputs is among the modes
    target = rotations[keep]
    found = np.abs(modes.poses[..., :3, :3] - target[:, None]).max(axis=(-2, -1))
    assert (np.where(modes.valid, found, np.inf).min(-1) < 1e-9).all()


def _row(modes, i):
    fields = {f: getattr(modes, f) for f in modes.__dataclass_fields__}
    return parakin.AssemblyModes(**{f: v[i] if isinstance(v, np.ndarray) else v for f, v in fields.items()})


def test_agile_eye_reports_four_genuine_modes_and_flags_the_input_independent_ones():
    """alpha1 = alpha2 = 90 deg, beta = gamma = atan(sqrt 2): the polynomial carries (x^2 - 1)^2
    for every input; those modes are the folded poses v_i = +-u_i, the same for any input."""
    eye = parakin.load("spm", backend="numpy", **AGILE_EYE)
    rng = np.random.default_rng(22)
    spurious_sets = []
    for theta in rng.uniform(-0.6, 0.6, (5, 3)):
        modes = eye.forward_pose_all(theta)
        assert int(modes.count) == 4
        errors = reproduces_inputs(eye, modes, theta)
        assert errors.max() < 1e-9
        assert modes.input_independent.any()
        spurious_sets.append(modes.poses[modes.input_independent][:, :3, :3])

    def same_set(first, second):
        distance = np.abs(first[:, None] - second[None]).max(axis=(-2, -1))
        return (distance.min(1) < 1e-9).all() and (distance.min(0) < 1e-9).all()

    assert all(same_set(spurious_sets[0], other) for other in spurious_sets[1:])


def test_rates_against_finite_differences(spm):
    modes = spm.forward_pose_all(EXAMPLE_THETA)
    config = modes.mode(0)
    rates = np.array([0.3, -0.2, 0.1])
    omega = spm.forward_rate(config, rates)
    h = 1e-6
    plus = spm.forward_pose(EXAMPLE_THETA + h * rates, guess=config).pose[:3, :3]
    minus = spm.forward_pose(EXAMPLE_THETA - h * rates, guess=config).pose[:3, :3]
    skew = (plus - minus) / (2 * h) @ config.pose[:3, :3].T
    assert np.abs(omega - [skew[2, 1], skew[0, 2], skew[1, 0]]).max() < 1e-6
    back = spm.inverse_rate(config, omega)
    assert np.abs(back.actuated - rates).max() < 1e-9
    dphi = (
        spm.forward_pose(EXAMPLE_THETA + h * rates, guess=config).passive
        - spm.forward_pose(EXAMPLE_THETA - h * rates, guess=config).passive
    ) / (2 * h)
    assert np.abs(back.passive - dphi).max() < 1e-6


def test_singularity_factors_multiply_to_the_determinants(spm):
    modes = spm.forward_pose_all(EXAMPLE_THETA)
    config = modes.mode(0)
    jac = spm.rate_jacobians(config)
    factors = spm.singularities(config)
    assert np.linalg.det(jac["a"]) == pytest.approx(float(factors["det_A"]), rel=1e-10)
    assert np.linalg.det(jac["b"]) == pytest.approx(float(factors["det_B"]), rel=1e-10)
    product = factors["leg1_axes_coplanar"] * factors["leg2_axes_coplanar"] * factors["leg3_axes_coplanar"]
    assert abs(float(factors["det_B"])) == pytest.approx(abs(float(product)), rel=1e-10)
    assert abs(float(factors["det_A"])) == pytest.approx(
        abs(float(factors["distal_plane_normals_coplanar"])), rel=1e-10
    )


def test_newton_tracker_follows_a_mode(spm):
    modes = spm.forward_pose_all(EXAMPLE_THETA)
    config = modes.mode(0)
    forward = spm.forward_pose(EXAMPLE_THETA + 0.01, guess=config)
    assert forward.converged and forward.residual < 1e-12
    back = spm.inverse_pose(forward.pose[:3, :3], strict=False)
    assert np.abs(wrap_angle(back.actuated - (EXAMPLE_THETA + 0.01))).max(-1).min() < 1e-10


def _compare_with_quaternion_route(m, theta, geometry, seed):
    import spm_quaternion

    info: dict = {}
    oracle = spm_quaternion.forward_rotations(
        geometry["alpha1"], geometry["alpha2"], geometry["beta"], geometry["gamma"], theta, seed=seed, info=info
    )
    modes = m.forward_pose_all(theta)
    skipped = 0
    for i, rotations in enumerate(oracle):
        if info["complex_counts"][i] < 8:  # the oracle lost a path (two poses merging): no verdict
            skipped += 1
            continue
        ours = modes.poses[i][modes.valid[i]][:, :3, :3]
        assert ours.shape[0] == rotations.shape[0], (i, theta[i])
        if ours.shape[0]:
            distance = np.abs(ours[:, None] - rotations[None]).max(axis=(-2, -1))
            assert (distance.min(1) < 1e-8).all() and (distance.min(0) < 1e-8).all(), i
    return skipped


def test_mode_counts_agree_with_the_quaternion_route_on_1000_inputs():
    """Section 3.2.2's unit-quaternion formulation, solved by an independent batched homotopy
    (tests/spm_quaternion.py): same number of real modes and the same rotations, none missing.
    Half the inputs come from the inverse pose of a random rotation (at least one mode), half
    are uniform."""
    m = parakin.load("spm", backend="compiled")
    rng = np.random.default_rng(24)
    branches = m.inverse_pose(random_rotations(rng, 1500), strict=False)
    reachable = branches.valid.any(-1)
    first = np.argmax(branches.valid, axis=-1)
    made = np.take_along_axis(branches.actuated, first[:, None, None], axis=1)[:, 0][reachable][:500]
    theta = np.concatenate([made, rng.uniform(-np.pi, np.pi, (500, 3))])
    geometry = {k: m.parameters[k] for k in ("alpha1", "alpha2", "beta", "gamma")}
    skipped = _compare_with_quaternion_route(m, theta, geometry, seed=1)
    assert skipped <= 5


def test_mode_counts_agree_with_the_quaternion_route_on_random_geometries():
    rng = np.random.default_rng(25)
    for case in range(60):
        geometry = {
            "alpha1": rng.uniform(0.2, np.pi - 0.2),
            "alpha2": rng.uniform(0.2, np.pi - 0.2),
            "beta": rng.uniform(0.1, 1.5),
            "gamma": rng.uniform(0.1, 1.5),
        }
        m = parakin.load("spm", backend="numpy", **geometry)
        theta = rng.uniform(-np.pi, np.pi, (5, 3))
        _compare_with_quaternion_route(m, theta, geometry, seed=case)


def test_near_double_roots_are_not_dropped():
    """Walk theta3 from the example towards a fold where two real modes merge, bisect the fold to
    1e-11 rad, and check that just inside it both nearly coincident modes are still reported."""
    m = parakin.load("spm", backend="numpy")
    start = EXAMPLE_THETA.copy()
    count0 = int(m.forward_pose_all(start).count)
    inside = outside = None
    for step in np.deg2rad(np.arange(0.5, 90, 0.5)):
        probe = start + [0.0, 0.0, step]
        if int(m.forward_pose_all(probe, strict=False).count) < count0:
            inside, outside = probe - [0.0, 0.0, np.deg2rad(0.5)], probe
            break
    assert inside is not None
    for _ in range(60):
        middle = (inside + outside) / 2
        if int(m.forward_pose_all(middle, strict=False).count) >= count0:
            inside = middle
        else:
            outside = middle
    assert abs(outside[2] - inside[2]) < 1e-11
    modes = m.forward_pose_all(inside)
    assert int(modes.count) == count0
    assert reproduces_inputs(m, modes, inside).max() < 1e-9


def test_modes_with_phi1_equal_pi_are_found():
    """x = tan(phi1/2) is infinite at phi1 = pi, a natural pose (review finding: such modes were
    dropped with the degree). The elimination measures phi1 from an offset, so they are found."""
    m = parakin.load("spm", backend="numpy")
    a1, a2 = m.parameters["alpha1"], m.parameters["alpha2"]
    gamma, beta = m.parameters["gamma"], m.parameters["beta"]
    rng = np.random.default_rng(26)
    u1 = np.array([0.0, np.sin(gamma), -np.cos(gamma)])
    e1 = np.array([0.0, -np.cos(gamma), -np.sin(gamma)])
    e2 = np.cross(u1, e1)
    v10 = np.array([0.0, np.sin(beta), np.cos(beta)])

    def rotation(axis, angle):
        k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k

    found = 0
    for _ in range(400):
        theta1 = rng.uniform(-np.pi, np.pi)
        w1 = np.cos(a1) * u1 + np.sin(a1) * (np.cos(theta1) * e1 + np.sin(theta1) * e2)
        n1 = np.cos(theta1) * e2 - np.sin(theta1) * e1
        v1 = np.cos(a2) * w1 - np.sin(a2) * n1  # phi1 = pi
        axis = np.cross(v10, v1)
        align = rotation(axis / np.linalg.norm(axis), np.arccos(np.clip(v10 @ v1, -1, 1)))
        target = rotation(v1, rng.uniform(-np.pi, np.pi)) @ align
        branches = m.inverse_pose(target, strict=False)
        matching = branches.valid & (np.abs(wrap_angle(branches.actuated[:, 0] - theta1)) < 1e-9)
        if not matching.any():
            continue
        k = int(np.argmax(matching))
        # phi1 = pi on this branch: the distal axis v1 = R v0_1 is the constructed one, in the
        # proximal plane on the far side (w1 . v1 = cos(alpha2), (u1 x w1) . v1 = 0 with n1 . v1 < 0)
        assert np.abs(target @ v10 - v1).max() < 1e-12
        modes = m.forward_pose_all(branches.actuated[k])
        distance = np.abs(modes.poses[:, :3, :3] - target).max(axis=(-2, -1))
        assert distance[modes.valid].min() < 1e-9
        found += 1
        if found == 30:
            break
    assert found == 30
