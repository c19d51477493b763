"""Planar five-bar (RRRRR): inverse branches, the two-circle forward pose, rates and the
singularities of Gosselin & Angeles (1990), against an independent NumPy implementation.

Independent reference: the elbow of leg i as a root of |A_i + a_i (cos t, sin t) - P| = b_i
found with numpy.roots on the tan-half-angle polynomial written here from scratch, the output
point as a root of the same kind of polynomial on the circle of radius b_1 about C_1, and the
rates by central differences. Defaults d = 0.15, a = 0.2, b = 0.25 m.
"""

import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError, SingularConfigurationError, UnreachablePoseError
from parakin.interfaces.cli import main
from parakin.interfaces.demo import run_examples
from parakin.pose import wrap_angle

D, A, B = 0.15, np.array([0.2, 0.2]), np.array([0.25, 0.25])
BASE = np.array([[-D, 0.0], [D, 0.0]])


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def m(request):
    return parakin.load("five_bar", backend=request.param)


# ------------------------------------------------------------------ the independent reference
def circle_angles(centre, radius, target, distance):
    """Angles t with |centre + radius (cos t, sin t) - target| = distance, by numpy.roots on
    (1 + u^2)(|w|^2 + radius^2 - distance^2) - 2 radius (w_x (1 - u^2) + w_y 2 u) = 0, u = tan(t/2),
    w = target - centre."""
    w = np.asarray(target) - np.asarray(centre)
    k = w @ w + radius**2 - distance**2
    coefficients = [k + 2 * radius * w[0], -4 * radius * w[1], k - 2 * radius * w[0]]  # u^2, u, 1
    roots = np.roots(coefficients)
    return np.sort(2 * np.arctan(roots[np.abs(roots.imag) < 1e-12].real))


def elbow_solutions(p, lengths=(A, B)):
    """Per leg (theta_out, theta_in): out is the elbow on the outer side of the line A_i -> P
    (left of it for leg 1, right of it for leg 2), or None when a leg cannot reach p."""
    a, b = lengths
    result = []
    for i in range(2):
        angles = circle_angles(BASE[i], a[i], p, b[i])
        if angles.size != 2:
            return None
        line = np.asarray(p) - BASE[i]
        side = [line[0] * np.sin(t) - line[1] * np.cos(t) for t in angles]  # cross(line, elbow)
        outer = np.argmax(side) if i == 0 else np.argmin(side)
        result.append((angles[outer], angles[1 - outer]))
    return result


def output_points(theta, lengths=(A, B)):
    """Both positions of P for the inputs: on the circle of radius b_1 about C_1, at distance b_2
    from C_2."""
    a, b = lengths
    c1 = BASE[0] + a[0] * np.array([np.cos(theta[0]), np.sin(theta[0])])
    c2 = BASE[1] + a[1] * np.array([np.cos(theta[1]), np.sin(theta[1])])
    return np.array([c1 + b[0] * np.array([np.cos(t), np.sin(t)]) for t in circle_angles(c1, b[0], c2, b[1])])


def random_points(rng, count):
    """Points above the base line; about 7 in 10 are reachable by both legs."""
    return np.column_stack([rng.uniform(-0.3, 0.3, count), rng.uniform(0.05, 0.42, count)])


# ------------------------------------------------------------------ claims
def test_forward_polynomial_is_a_quadratic():
    assert parakin.metadata("five_bar").capabilities.forward.degree == 2


def test_named_examples_hold():
    for result in run_examples("five_bar", backend="numpy"):
        assert result.holds, (result.example.name, result.error, result.comparisons)


def test_inverse_branches_match_the_independent_elbows(m):
    """All 4 branches: sigma_i = +1 is elbow i outside, to 1e-12 rad."""
    rng = np.random.default_rng(21)
    checked = 0
    for p in random_points(rng, 100):
        reference = elbow_solutions(p)
        if reference is None:
            continue
        ik = m.inverse_pose([p[0], p[1]])
        assert ik.valid.all()
        for k, signs in enumerate(ik.branches):
            expected = [reference[i][0 if s > 0 else 1] for i, s in enumerate(signs)]
            assert np.abs(wrap_angle(ik.actuated[k] - expected)).max() < 1e-12
            np.testing.assert_allclose(ik.passive[k], p, atol=0)
        checked += 1
    assert checked >= 60


def test_forward_modes_match_the_independent_points_and_round_trip(m):
    """Every branch of random points: the two modes equal the independent points (1e-12 m), the
    point is one of them, and each mode reproduces the inputs through inverse_pose."""
    rng = np.random.default_rng(22)
    checked = 0
    for p in random_points(rng, 50):
        ik = m.inverse_pose([p[0], p[1]], strict=False)
        for k in np.nonzero(ik.valid)[0]:
            theta = ik.actuated[k]
            modes = m.forward_pose_all(theta)
            found = modes.poses[modes.valid][:, :2, 3]
            reference = output_points(theta)
            assert int(modes.count) == reference.shape[0] == 2
            gaps = np.abs(found[:, None, :] - reference[None, :, :]).max(-1)
            assert gaps.min(1).max() < 1e-12 and gaps.min(0).max() < 1e-12
            assert np.abs(found - p).max(-1).min() < 1e-12
            assert not modes.poses[modes.valid][:, 2, 3].any()  # z = 0
            for point in found:
                back = m.inverse_pose([point[0], point[1]])
                assert np.abs(wrap_angle(back.actuated - theta)).max(-1)[back.valid].min() < 1e-10
            checked += 1
    assert checked >= 120


def test_unequal_links():
    """Four different lengths (a1, a2, b1, b2): the same round trip."""
    lengths = (np.array([0.18, 0.23]), np.array([0.27, 0.21]))
    g = parakin.load("five_bar", backend="numpy", a1=0.18, a2=0.23, b1=0.27, b2=0.21)
    rng = np.random.default_rng(23)
    checked = 0
    for p in random_points(rng, 40):
        reference = elbow_solutions(p, lengths)
        if reference is None:
            continue
        ik = g.inverse_pose([p[0], p[1]])
        assert np.abs(wrap_angle(ik.actuated[0] - [reference[0][0], reference[1][0]])).max() < 1e-12
        modes = g.forward_pose_all(ik.actuated[0])
        points = output_points(ik.actuated[0], lengths)
        assert np.abs(modes.poses[modes.valid][:, None, :2, 3] - points[None]).max(-1).min(1).max() < 1e-12
        checked += 1
    assert checked >= 25


def test_unreachable_point():
    m = parakin.load("five_bar", backend="numpy")
    with pytest.raises(UnreachablePoseError, match="leg1_reachable"):
        m.inverse_pose([-0.8, 0.1])


def test_a_point_off_the_plane_is_refused():
    """The five-bar moves in the plane z = 0 (pose kind planar_translation): P = (0, 0.4, 0.1)
    is 0.1 m off it and has no branch, where the same point in the plane has four."""
    m = parakin.load("five_bar", backend="numpy")
    assert m.manifest.pose_kind == "planar_translation"
    assert int(m.inverse_pose([0.0, 0.4]).valid.sum()) == 4
    off_plane = np.eye(4)
    off_plane[:3, 3] = [0.0, 0.4, 0.1]
    with pytest.raises(BadInputError, match=r"z offset.*off by 0\.1\b"):
        m.inverse_pose(off_plane)
    with pytest.raises(BadInputError):
        m.inverse_pose([0.0, 0.4, 0.1])
    assert main(["ik", "five_bar", "--pose", "0", "0.4", "0.1"]) == 2
    assert main(["ik", "five_bar", "--pose", "0", "0.4"]) == 0


# ------------------------------------------------------------------ rates and singularities
def test_rates_against_finite_differences(m):
    """theta_dot for a velocity of P against central differences of the independent elbows (same
    branch); forward_rate and the loop-closure passive rates invert it."""
    rng = np.random.default_rng(24)
    h = 1e-7
    checked = 0
    for p in random_points(rng, 50):
        velocity = rng.normal(size=2)
        plus, minus = elbow_solutions(p + h * velocity), elbow_solutions(p - h * velocity)
        if plus is None or minus is None:
            continue
        state = m.inverse_pose([p[0], p[1]]).branch(0)
        numeric = wrap_angle(np.array([s[0] for s in plus]) - np.array([s[0] for s in minus])) / (2 * h)
        rates = m.inverse_rate(state, velocity)
        np.testing.assert_allclose(rates.actuated, numeric, rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(rates.passive, velocity, atol=1e-10)
        np.testing.assert_allclose(m.forward_rate(state, rates.actuated), velocity, atol=1e-9)
        checked += 1
    assert checked >= 30


def test_rate_matrices_against_numpy(m):
    p = np.array([0.05, 0.3])
    state = m.inverse_pose([p[0], p[1]]).branch(0)
    theta = state.actuated
    elbows = BASE + A[:, None] * np.column_stack([np.cos(theta), np.sin(theta)])
    distal = p - elbows
    diagonal = A * (distal[:, 0] * -np.sin(theta) + distal[:, 1] * np.cos(theta))
    jacobians = m.rate_jacobians(state)
    np.testing.assert_allclose(jacobians["a"], distal, atol=1e-14)
    np.testing.assert_allclose(jacobians["b"], np.diag(diagonal), atol=1e-14)
    factors = m.singularities(state)
    assert factors["distal_links_aligned"] == pytest.approx(np.linalg.det(distal), rel=1e-12)
    assert factors["det_B"] == pytest.approx(np.prod(diagonal), rel=1e-12)


def test_type2_singularity_with_aligned_distal_links():
    """theta = (2 pi / 3, pi / 3): elbows (-0.25, h) and (0.25, h), h = sqrt(0.03), and P = (0, h)
    between them: the distal links are aligned (Gosselin & Angeles' type II), forward_rate refuses
    and the two modes merge into one."""
    m = parakin.load("five_bar", backend="numpy")
    h = np.sqrt(0.03)
    theta = np.array([2 * np.pi / 3, np.pi / 3])
    p = np.array([0.0, h])
    assert np.abs(m.loop_closure(theta, p)["residual"]).max() < 1e-15
    state = parakin.Configuration(theta, p, parakin.pose.transform_from_pose([0.0, h], "planar_translation"))
    factors = m.singularities(state)
    assert abs(factors["distal_links_aligned"]) < 1e-15
    assert min(abs(factors["leg1_links_aligned"]), abs(factors["leg2_links_aligned"])) > 1e-2
    with pytest.raises(SingularConfigurationError):
        m.forward_rate(state, [1.0, 0.0])
    modes = m.forward_pose_all(theta)
    assert int(modes.count) == 1
    np.testing.assert_allclose(modes.poses[modes.valid][0, :2, 3], p, atol=1e-7)


def test_type1_singularity_with_a_stretched_leg():
    """P at distance a1 + b1 from A1 (leg 1 stretched): its factor vanishes, inverse_rate refuses."""
    m = parakin.load("five_bar", backend="numpy")
    angle = 1.2
    p = BASE[0] + (A[0] + B[0]) * np.array([np.cos(angle), np.sin(angle)])
    leg2 = circle_angles(BASE[1], A[1], p, B[1])
    theta = np.array([angle, leg2[0]])
    assert np.abs(m.loop_closure(theta, p)["residual"]).max() < 1e-15
    state = parakin.Configuration(theta, p, parakin.pose.transform_from_pose(p, "planar_translation"))
    factors = m.singularities(state)
    assert abs(factors["leg1_links_aligned"]) < 1e-15 and abs(factors["leg2_links_aligned"]) > 1e-3
    with pytest.raises(SingularConfigurationError):
        m.inverse_rate(state, [0.0, 1.0])


def test_backends_agree():
    theta = np.array([1.9, 1.1])
    results = [parakin.load("five_bar", backend=b).forward_pose_all(theta) for b in ("numpy", "compiled", "casadi")]
    for other in results[1:]:
        np.testing.assert_allclose(other.poses, results[0].poses, atol=1e-14)
        np.testing.assert_array_equal(other.valid, results[0].valid)


def test_drawing_points(m):
    p = np.array([-0.05, 0.35])
    state = m.inverse_pose([p[0], p[1]]).branch(0)
    points = m.drawing(state)
    theta = state.actuated
    elbows = BASE + A[:, None] * np.column_stack([np.cos(theta), np.sin(theta)])
    np.testing.assert_allclose(points["base"][:2].T, BASE, atol=0)
    np.testing.assert_allclose(points["elbow"][:2].T, elbows, atol=1e-15)
    np.testing.assert_allclose(points["platform"][:2].T, np.vstack([p, p]), atol=1e-15)  # both legs end at P
    assert not points["base"][2].any() and not points["elbow"][2].any() and not points["platform"][2].any()
