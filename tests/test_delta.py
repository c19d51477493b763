"""Delta robot (3-RUU, Clavel 1988): inverse branches, the three-sphere forward pose, rates and
singularities against an independent NumPy implementation written here.

Independent reference: per leg, the sphere of radius l about the platform joint cut by the leg's
plane is a circle; the elbow is where it meets the arm's circle of radius L (a circle-circle
intersection in the leg plane). Forward: textbook trilateration (the frame e_x, e_y, e_z of the
three sphere centres). Defaults R = 0.2, r = 0.05, L = 0.35, l = 1.3 m.
"""

import numpy as np
import pytest

import parakin
from parakin.errors import SingularConfigurationError, UnreachablePoseError
from parakin.interfaces.demo import run_examples
from parakin.pose import wrap_angle

BASE_R, PLATFORM_R, ARM, FOREARM = 0.2, 0.05, 0.35, 1.3  # R, r, L, l
ETA = 2 * np.pi * np.arange(3) / 3
RADIAL = np.stack([np.cos(ETA), np.sin(ETA), np.zeros(3)], -1)
Z = np.array([0.0, 0.0, 1.0])


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def m(request):
    return parakin.load("delta", backend=request.param)


# ------------------------------------------------------------------ the independent reference
def arm(angle, i):
    return np.cos(angle) * RADIAL[i] - np.sin(angle) * Z


def elbows(theta, geometry=(BASE_R, PLATFORM_R, ARM, FOREARM)):
    big_r, _, big_l, _ = geometry
    return np.array([big_r * RADIAL[i] + big_l * arm(theta[i], i) for i in range(3)])


def leg_solution(p, i, geometry=(BASE_R, PLATFORM_R, ARM, FOREARM)):
    """Leg i's (theta_out, theta_in), or None when unreachable: circle-circle in the leg plane,
    coordinates X along e_i and Y along -z from the motor joint (theta = atan2(Y, X))."""
    big_r, small_r, big_l, small_l = geometry
    tangent = np.cross(Z, RADIAL[i])
    joint = p + small_r * RADIAL[i] - big_r * RADIAL[i]  # platform joint seen from the motor
    offset = joint @ tangent
    if small_l**2 <= offset**2:
        return None
    rho = np.sqrt(small_l**2 - offset**2)  # the sphere's circle in the leg plane
    q = np.array([joint @ RADIAL[i], -joint @ Z])
    dist = np.linalg.norm(q)
    along = (big_l**2 - rho**2 + dist**2) / (2 * dist)
    if big_l**2 <= along**2:
        return None
    height = np.sqrt(big_l**2 - along**2)
    unit, normal = q / dist, np.array([-q[1], q[0]]) / dist
    out, inside = along * unit - height * normal, along * unit + height * normal  # out: clockwise of q
    return np.arctan2(out[1], out[0]), np.arctan2(inside[1], inside[0])


def leg_solutions(p, geometry=(BASE_R, PLATFORM_R, ARM, FOREARM)):
    """Every leg's (theta_out, theta_in), or None when a leg cannot reach p."""
    result = [leg_solution(p, i, geometry) for i in range(3)]
    return None if any(s is None for s in result) else result


def trilaterate(theta, geometry=(BASE_R, PLATFORM_R, ARM, FOREARM)):
    """Both platform positions for the inputs: spheres of radius l about c_i - r e_i."""
    big_r, small_r, big_l, small_l = geometry
    centres = elbows(theta, geometry) - small_r * RADIAL
    ex = centres[1] - centres[0]
    d = np.linalg.norm(ex)
    ex /= d
    i = ex @ (centres[2] - centres[0])
    ey = centres[2] - centres[0] - i * ex
    ey /= np.linalg.norm(ey)
    ez = np.cross(ex, ey)
    j = ey @ (centres[2] - centres[0])
    x = d / 2
    y = (i**2 + j**2) / (2 * j) - i * x / j
    z = np.sqrt(small_l**2 - x**2 - y**2)
    return np.array([centres[0] + x * ex + y * ey + s * z * ez for s in (1, -1)])


def random_positions(rng, count):
    return np.column_stack([rng.uniform(-0.35, 0.35, (count, 2)), rng.uniform(-1.4, -0.8, count)])


# ------------------------------------------------------------------ claims
def test_forward_polynomial_is_a_quadratic():
    assert parakin.metadata("delta").capabilities.forward.degree == 2


def test_named_examples_hold():
    for result in run_examples("delta", backend="numpy"):
        assert result.holds, (result.example.name, result.error, result.comparisons)


def test_inverse_branches_match_the_independent_legs(m):
    """All 8 branches: sigma_i = +1 is the elbow out, -1 the elbow in, to 1e-11 rad."""
    rng = np.random.default_rng(11)
    checked = 0
    for p in random_positions(rng, 80):
        reference = leg_solutions(p)
        if reference is None:
            continue
        ik = m.inverse_pose(p)
        assert ik.valid.all()
        for k, signs in enumerate(ik.branches):
            expected = [reference[i][0 if s > 0 else 1] for i, s in enumerate(signs)]
            assert np.abs(wrap_angle(ik.actuated[k] - expected)).max() < 1e-11
            np.testing.assert_allclose(ik.passive[k], p, atol=0)
        checked += 1
    assert checked >= 48  # about 3 in 4 random positions are reachable by every leg


def test_forward_modes_match_trilateration_and_round_trip(m):
    """For every branch of random poses: both modes of forward_pose_all equal the trilateration
    points (1e-10 m), the pose is one of them, and each mode reproduces the inputs through
    inverse_pose."""
    rng = np.random.default_rng(12)
    checked = 0
    for p in random_positions(rng, 40):
        ik = m.inverse_pose(p, strict=False)
        for k in np.nonzero(ik.valid)[0]:
            theta = ik.actuated[k]
            modes = m.forward_pose_all(theta)
            assert int(modes.count) == 2
            found = modes.poses[modes.valid][:, :3, 3]
            reference = trilaterate(theta)
            gaps = np.abs(found[:, None, :] - reference[None, :, :]).max(-1)
            assert gaps.min(1).max() < 1e-10 and gaps.min(0).max() < 1e-10
            assert np.abs(found - p).max(-1).min() < 1e-10
            np.testing.assert_allclose(modes.poses[modes.valid][:, :3, :3], np.broadcast_to(np.eye(3), (2, 3, 3)))
            for position in found:
                back = m.inverse_pose(position)
                mismatch = np.abs(wrap_angle(back.actuated - theta)).max(-1)
                assert mismatch[back.valid].min() < 1e-9
            checked += 1
    assert checked >= 150


def test_newton_forward_pose_from_home(m):
    """Without a guess, Newton starts at the mode nearest home (the platform below)."""
    p = np.array([0.1, -0.05, -1.1])
    theta = m.inverse_pose(p).actuated[0]
    fk = m.forward_pose(theta)
    assert fk.converged and fk.residual < 1e-12
    np.testing.assert_allclose(fk.pose[:3, 3], p, atol=1e-10)


def test_unreachable_pose():
    m = parakin.load("delta", backend="numpy")
    with pytest.raises(UnreachablePoseError, match="leg1_reachable"):
        m.inverse_pose([0.0, 0.0, -2.0])


def test_short_form_of_the_pose(m):
    p = np.array([0.05, 0.1, -1.0])
    full = np.eye(4)
    full[:3, 3] = p
    np.testing.assert_array_equal(m.inverse_pose(p).actuated, m.inverse_pose(full).actuated)


# ------------------------------------------------------------------ rates
def test_rates_against_finite_differences(m):
    """theta_dot for a platform velocity, against central differences of the independent leg
    solutions (same branch); forward_rate and the loop-closure passive rates invert it."""
    rng = np.random.default_rng(13)
    h = 1e-6
    checked = 0
    for p in random_positions(rng, 50):
        if leg_solutions(p) is None or leg_solutions(p + 0.01) is None:
            continue
        velocity = rng.normal(size=3)
        state = m.inverse_pose(p).branch(0)
        plus, minus = leg_solutions(p + h * velocity), leg_solutions(p - h * velocity)
        numeric = wrap_angle(np.array([a[0] for a in plus]) - np.array([a[0] for a in minus])) / (2 * h)
        rates = m.inverse_rate(state, velocity)
        np.testing.assert_allclose(rates.actuated, numeric, rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(rates.passive, velocity, atol=1e-10)
        np.testing.assert_allclose(m.forward_rate(state, rates.actuated), velocity, atol=1e-9)
        checked += 1
    assert checked >= 30


def test_rate_matrices_against_numpy(m):
    """A rows are the forearms d_i = p + r e_i - c_i, B = diag(L d_i . du_i/dtheta_i); det A and
    det B are the named factors' products."""
    p = np.array([0.12, -0.07, -1.05])
    state = m.inverse_pose(p).branch(0)
    theta = state.actuated
    forearms = p + PLATFORM_R * RADIAL - elbows(theta)
    derivative = np.array([-np.sin(theta[i]) * RADIAL[i] - np.cos(theta[i]) * Z for i in range(3)])
    diagonal = ARM * (forearms * derivative).sum(-1)
    jacobians = m.rate_jacobians(state)
    np.testing.assert_allclose(jacobians["a"], forearms, atol=1e-13)
    np.testing.assert_allclose(jacobians["b"], np.diag(diagonal), atol=1e-13)
    factors = m.singularities(state)
    assert factors["forearms_coplanar"] == pytest.approx(np.linalg.det(forearms), rel=1e-12)
    assert abs(factors["det_B"]) == pytest.approx(abs(np.prod(diagonal)), rel=1e-12)
    for i in range(3):
        assert factors[f"leg{i + 1}_forearm_in_arm_plane"] == pytest.approx(diagonal[i], rel=1e-12)


def test_type1_singularity_with_the_forearm_in_the_arm_plane():
    """Leg 1 stretched with its forearm in the plane of arm and motor axis, d_1 = l (cos b u_1 +
    sin b t_1), theta_1 = 2 rad (the arm down and inwards): its factor vanishes (the other legs'
    do not), leg 1 is at its reachability boundary, and inverse_rate refuses."""
    m = parakin.load("delta", backend="numpy")
    angle, tilt = 2.0, 0.3
    forearm = FOREARM * (np.cos(tilt) * arm(angle, 0) + np.sin(tilt) * np.cross(Z, RADIAL[0]))
    p = BASE_R * RADIAL[0] + ARM * arm(angle, 0) + forearm - PLATFORM_R * RADIAL[0]
    others = [leg_solution(p, i) for i in (1, 2)]
    assert all(s is not None for s in others)
    theta = np.array([angle, others[0][0], others[1][0]])
    assert np.abs(m.loop_closure(theta, p)["residual"]).max() < 1e-15
    state = parakin.Configuration(theta, p, parakin.pose.transform_from_pose(p, "translation"))
    factors = m.singularities(state)
    assert abs(factors["leg1_forearm_in_arm_plane"]) < 1e-15
    assert min(abs(factors["leg2_forearm_in_arm_plane"]), abs(factors["leg3_forearm_in_arm_plane"])) > 1e-2
    ik = m.inverse_pose(p, strict=False)
    assert ik.failures["leg1_reachable"].all()  # the discriminant is 0 up to rounding (< 1e-9)
    with pytest.raises(SingularConfigurationError):
        m.inverse_rate(state, [0.0, 0.0, 1.0])


def test_type2_singularity_with_horizontal_forearms():
    """l = 0.3 m: with every arm at cos(theta) = (l - R + r) / L the forearms lie in the plane of
    the elbows (z = -L sin(theta)) and det A = 0; forward_rate refuses; the two modes merge."""
    g = parakin.load("delta", backend="numpy", l=0.3)
    angle = np.arccos((0.3 - BASE_R + PLATFORM_R) / ARM)
    theta = np.full(3, angle)
    state_pose = np.array([0.0, 0.0, -ARM * np.sin(angle)])
    state = parakin.Configuration(theta, state_pose, parakin.pose.transform_from_pose(state_pose, "translation"))
    assert np.abs(g.loop_closure(theta, state_pose)["residual"]).max() < 1e-15
    assert abs(g.singularities(state)["forearms_coplanar"]) < 1e-15
    with pytest.raises(SingularConfigurationError):
        g.forward_rate(state, [0.1, 0.0, 0.0])
    modes = g.forward_pose_all(theta)
    assert int(modes.count) == 1  # the double root is one mode
    np.testing.assert_allclose(modes.poses[modes.valid][0, :3, 3], state_pose, atol=1e-7)


def test_backends_agree():
    theta = np.array([0.3, -0.2, 0.5])
    results = [parakin.load("delta", backend=b).forward_pose_all(theta) for b in ("numpy", "compiled", "casadi")]
    for other in results[1:]:
        np.testing.assert_allclose(other.poses, results[0].poses, atol=1e-13)
        np.testing.assert_array_equal(other.valid, results[0].valid)


def test_drawing_points(m):
    p = np.array([0.1, 0.05, -1.1])
    state = m.inverse_pose(p).branch(0)
    points = m.drawing(state)
    np.testing.assert_allclose(points["base"].T, BASE_R * RADIAL, atol=1e-15)
    np.testing.assert_allclose(points["elbow"].T, elbows(state.actuated), atol=1e-14)
    np.testing.assert_allclose(points["platform"].T, np.vstack([p + PLATFORM_R * RADIAL, p]), atol=1e-15)
