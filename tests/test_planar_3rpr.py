"""Planar 3-RPR: the degree-6 forward polynomial (Gosselin, Sefrioui & Richard 1992), its
6-real-mode example, round trips, rates against finite differences, type II singularities.

The independent reference is written here in NumPy: leg lengths |p + R b_i - A_i|, and the
assembly modes by a sign-change scan over phi of the leg-1 equation after solving legs 2 and 3
minus leg 1 for the position (refined by Brent's method, kept when all three legs close).
"""

import warnings

import numpy as np
import pytest
import sympy as sp
from parakin.generator.blocks import remove_spurious_factors
from parakin.mechanisms import planar_3rpr
from scipy.optimize import brentq

import parakin
from parakin.errors import SingularConfigurationError
from parakin.interfaces.demo import run_examples
from parakin.pose import wrap_angle

GSR_BASE = np.array(planar_3rpr.GSR_BASE)
GSR_PLATFORM = np.array(planar_3rpr.GSR_PLATFORM)
GSR_LENGTHS = np.array(planar_3rpr.GSR_LENGTHS)


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def m(request):
    return parakin.load("planar_3rpr", backend=request.param)


# ------------------------------------------------------------------ the independent reference
def rotation(phi):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


def leg_lengths(base, platform, pose):
    """|p + R b_i - A_i| for pose (x, y, phi)."""
    x, y, phi = pose
    points = np.array([x, y]) + platform @ rotation(phi).T
    return np.linalg.norm(points - base, axis=1)


def scan_modes(base, platform, rho, samples=400_001):
    """Every assembly mode found by a sign-change scan of the leg-1 equation over phi."""

    def position(phi):
        phi = np.atleast_1d(phi)
        c, s = np.cos(phi), np.sin(phi)
        turned = np.stack([c[:, None] * platform[:, 0] - s[:, None] * platform[:, 1],
                           s[:, None] * platform[:, 0] + c[:, None] * platform[:, 1]], -1)  # fmt: skip
        e = turned - base  # (n, 3, 2): p + e_i is leg i
        rows = 2 * (e[:, 1:] - e[:, :1])
        right = -((e[:, 1:] ** 2).sum(-1) - rho[1:] ** 2 - (e[:, :1] ** 2).sum(-1) + rho[0] ** 2)
        with np.errstate(all="ignore"):
            p = np.linalg.solve(rows, right[..., None])[..., 0]
        return p, ((p + e[:, 0]) ** 2).sum(-1) - rho[0] ** 2

    grid = np.linspace(-np.pi, np.pi, samples)
    values = position(grid)[1]
    modes = []
    for k in np.nonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)[0]:
        phi = brentq(lambda a: position(a)[1][0], grid[k], grid[k + 1], xtol=1e-15)
        p = position(phi)[0][0]
        if np.abs(leg_lengths(base, platform, (*p, phi)) - rho).max() < 1e-7:  # not a pole of Cramer
            modes.append((*p, phi))
    return np.array(modes).reshape(-1, 3)


def planar(poses):
    """(x, y, phi) of (..., 4, 4) planar poses."""
    return np.stack([poses[..., 0, 3], poses[..., 1, 3], np.arctan2(poses[..., 1, 0], poses[..., 0, 0])], -1)


def distance(a, b):
    """Max difference of (x, y, phi) triples, phi modulo 2 pi."""
    difference = a - b
    difference[..., 2] = wrap_angle(difference[..., 2])
    return np.abs(difference).max(-1)


# ------------------------------------------------------------------ the elimination
def test_forward_polynomial_has_degree_six():
    """Gosselin, Sefrioui & Richard (1992): at most 6 assembly modes, a sextic in tan(phi / 2)."""
    assert parakin.metadata("planar_3rpr").capabilities.forward.degree == 6


def test_spurious_factor_removal_on_known_products():
    """The helper divides out content, (1 + t^2)^k and t^k, and nothing else."""
    t, a, b = sp.symbols("t a b")
    clean = remove_spurious_factors(sp.expand(6 * a * t**2 * (1 + t**2) ** 2 * (t - b) * (t + 3)), t, [1 + t**2], False)
    assert clean.content == 6 * a and clean.removed == [(t**2 + 1, 2)] and clean.zero_roots == 2
    assert sp.expand(clean.as_expr() - (t - b) * (t + 3)) == 0
    kept = remove_spurious_factors(sp.expand(t * (t**2 + 2) * (t - 1)), t, [1 + t**2])
    assert kept.removed == [] and kept.zero_roots == 0 and kept.degree == 4
    product = remove_spurious_factors(sp.expand((1 + t**2) * (t + 1) * (t - b)), t, [(1 + t**2) * (t + 1) ** 2])
    assert sorted(m for _, m in product.removed) == [1, 1] and product.coefficients == [-b, 1]


def test_six_real_modes_example_against_an_independent_scan(m):
    """The default geometry with rho = (14.98, 15.38, 12): 6 real assembly modes (the maximum),
    each equal to one found by the independent scan to 1e-9 and closing every leg to 1e-9."""
    modes = m.forward_pose_all(GSR_LENGTHS)
    reference = scan_modes(GSR_BASE, GSR_PLATFORM, GSR_LENGTHS)
    assert reference.shape[0] == 6
    assert int(modes.count) == 6
    found = planar(modes.poses[modes.valid])
    matches = distance(found[:, None, :], reference[None, :, :])
    assert matches.min(1).max() < 1e-9 and matches.min(0).max() < 1e-9  # a bijection up to 1e-9
    for pose in found:
        assert np.abs(leg_lengths(GSR_BASE, GSR_PLATFORM, pose) - GSR_LENGTHS).max() < 1e-9


def test_named_examples_hold():
    for result in run_examples("planar_3rpr", backend="numpy"):
        assert result.holds, (result.example.name, result.error, result.comparisons)


def test_random_round_trips_and_scan_agreement(m):
    """Random poses: rho from inverse_pose equals the NumPy leg lengths; forward_pose_all finds the
    pose again; every valid mode closes the legs; every scan solution is among the modes."""
    rng = np.random.default_rng(20261123)
    checked = 0
    mode_total = 0
    for _ in range(40):
        pose = np.array([*rng.uniform(-15, 15, 2), rng.uniform(-np.pi, np.pi)])
        ik = m.inverse_pose(pose)
        assert ik.valid.shape == (1,) and ik.valid[0]
        rho = ik.actuated[0]
        np.testing.assert_allclose(rho, leg_lengths(GSR_BASE, GSR_PLATFORM, pose), rtol=0, atol=1e-12)
        np.testing.assert_allclose(ik.passive[0], pose, atol=1e-12)
        np.testing.assert_allclose(planar(m.platform_pose(rho, ik.passive[0])), pose, atol=1e-12)
        modes = m.forward_pose_all(rho)
        found = planar(modes.poses[modes.valid])
        assert distance(found, pose).min() < 1e-8
        for mode in found:
            assert np.abs(leg_lengths(GSR_BASE, GSR_PLATFORM, mode) - rho).max() < 1e-9
            back = m.inverse_pose(mode).actuated[0]
            assert np.abs(back - rho).max() < 1e-9
        reference = scan_modes(GSR_BASE, GSR_PLATFORM, rho, samples=100_001)
        if reference.size:
            assert distance(reference[:, None, :], found[None, :, :]).min(1).max() < 1e-7
        mode_total += int(modes.count)
        checked += 1
    assert checked == 40 and mode_total >= 80  # 2, 4 or 6 modes per input


def test_random_geometries_modes_close_and_match_the_scan():
    """Random base and platform triangles (coordinates in [-1, 1] m): the same claims."""
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(25):
        base, platform = rng.uniform(-1, 1, (3, 2)), rng.uniform(-1, 1, (3, 2))
        g = parakin.load("planar_3rpr", backend="numpy", base=base, platform=platform)
        pose = np.array([*rng.uniform(-1, 1, 2), rng.uniform(-np.pi, np.pi)])
        rho = leg_lengths(base, platform, pose)
        modes = g.forward_pose_all(rho)
        found = planar(modes.poses[modes.valid])
        assert distance(found, pose).min() < 1e-7
        for mode in found:
            assert np.abs(leg_lengths(base, platform, mode) - rho).max() < 1e-9
        reference = scan_modes(base, platform, rho, samples=100_001)
        assert distance(reference[:, None, :], found[None, :, :]).min(1).max() < 1e-7
        assert int(modes.count) in (2, 4, 6)
        checked += 1
    assert checked == 25


def test_backends_agree_on_the_example():
    counts, poses = [], []
    for backend in ("numpy", "compiled", "casadi"):
        modes = parakin.load("planar_3rpr", backend=backend).forward_pose_all(GSR_LENGTHS)
        counts.append(int(modes.count))
        poses.append(np.sort(planar(modes.poses[modes.valid])[:, 2]))
    assert counts == [6, 6, 6]
    np.testing.assert_allclose(poses[1], poses[0], atol=1e-12)
    np.testing.assert_allclose(poses[2], poses[0], atol=1e-12)


def test_short_pose_form_and_newton(m):
    """(x, y, phi) is accepted for ^B_P T; Newton from a nearby guess recovers the pose."""
    pose = np.array([-3.0, 4.0, 0.7])
    full = parakin.pose.transform_from_pose(pose, "planar")
    np.testing.assert_allclose(m.inverse_pose(pose).actuated, m.inverse_pose(full).actuated, atol=0)
    rho = m.inverse_pose(pose).actuated[0]
    fk = m.forward_pose(rho, guess=pose + [0.3, -0.2, 0.05])
    assert fk.converged and fk.residual < 1e-12
    np.testing.assert_allclose(fk.passive, pose, atol=1e-10)


# ------------------------------------------------------------------ rates
def test_inverse_rate_matches_finite_differences(m):
    """rho_dot for a planar twist (vx, vy, wz) against central differences of the NumPy leg
    lengths along (x, y, phi) + h (vx, vy, wz); forward_rate and the loop-closure passive rates
    invert it."""
    rng = np.random.default_rng(3)
    h = 1e-6
    checked = 0
    for _ in range(20):
        pose = np.array([*rng.uniform(-15, 15, 2), rng.uniform(-np.pi, np.pi)])
        twist = rng.normal(size=3)
        state = m.inverse_pose(pose).branch(0)
        numeric = (
            leg_lengths(GSR_BASE, GSR_PLATFORM, pose + h * twist)
            - leg_lengths(GSR_BASE, GSR_PLATFORM, pose - h * twist)
        ) / (2 * h)
        rates = m.inverse_rate(state, twist)
        np.testing.assert_allclose(rates.actuated, numeric, rtol=1e-7, atol=1e-7)
        np.testing.assert_allclose(rates.passive, twist, atol=1e-10)  # passive = (x, y, phi)
        np.testing.assert_allclose(m.forward_rate(state, rates.actuated), twist, atol=1e-9)
        checked += 1
    assert checked == 20


def test_rate_matrices_and_determinants_against_numpy(m):
    """A = rows (d_x, d_y, ((A_i - p) x d_i)_z), B = diag(rho); det A is the named type II factor
    and det B the product of the leg lengths."""
    pose = np.array([2.0, -5.0, 0.4])
    state = m.inverse_pose(pose).branch(0)
    points = pose[:2] + GSR_PLATFORM @ rotation(pose[2]).T
    d = points - GSR_BASE
    lever = GSR_BASE - pose[:2]
    a = np.column_stack([d, lever[:, 0] * d[:, 1] - lever[:, 1] * d[:, 0]])
    jacobians = m.rate_jacobians(state)
    np.testing.assert_allclose(jacobians["a"], a, atol=1e-12)
    np.testing.assert_allclose(jacobians["b"], np.diag(state.actuated), atol=1e-12)
    factors = m.singularities(state)
    assert abs(factors["det_A"]) == pytest.approx(abs(np.linalg.det(a)), rel=1e-12)
    assert factors["leg_lines_concurrent_or_parallel"] == pytest.approx(factors["det_A"], rel=1e-12)
    assert factors["det_B"] == pytest.approx(np.prod(state.actuated), rel=1e-12)


def test_type2_singularity_where_the_leg_lines_meet():
    """Base points moved along the lines from a common point O through the platform points: the
    leg lines are concurrent, det A = 0 (relative to its rows) and forward_rate refuses."""
    pose = np.array([0.3, -0.2, 0.5])
    points = pose[:2] + GSR_PLATFORM / 10 @ rotation(pose[2]).T
    centre = np.array([0.4, 0.9])
    base = points + np.array([[0.5], [0.8], [1.3]]) * (points - centre)
    g = parakin.load("planar_3rpr", backend="numpy", base=base, platform=GSR_PLATFORM / 10)
    state = g.inverse_pose(pose).branch(0)
    a = g.rate_jacobians(state)["a"]
    scale = np.prod(np.linalg.norm(a, axis=1))
    assert abs(g.singularities(state)["leg_lines_concurrent_or_parallel"]) < 1e-13 * scale
    with pytest.raises(SingularConfigurationError):
        g.forward_rate(state, [1.0, 0.0, 0.0])


def test_congruent_design_with_equal_legs_has_a_translational_self_motion():
    """b_i = A_i: at phi = 0 the platform translates on the circle |p| = rho when the legs are
    equal (the elimination's blind spot, module docstring); forward_pose_all still returns only
    closed modes, and self_motion traces the circle."""
    triangle = np.array([[0.0, 0.0], [1.0, 0.0], [0.3, 0.8]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        g = parakin.load("planar_3rpr", backend="numpy", base=triangle, platform=triangle)
        rho = np.full(3, 0.5)
        modes = g.forward_pose_all(rho)
        for pose in planar(modes.poses[modes.valid]):
            assert np.abs(leg_lengths(triangle, triangle, pose) - rho).max() < 1e-9
        motion = g.self_motion(rho)
    assert motion.count > 20
    assert np.abs(wrap_angle(motion.passive[:, 2])).max() < 1e-9
    np.testing.assert_allclose(np.hypot(motion.passive[:, 0], motion.passive[:, 1]), 0.5, atol=1e-9)


def test_drawing_points(m):
    pose = np.array([1.0, 2.0, -0.4])
    state = m.inverse_pose(pose).branch(0)
    points = m.drawing(state)
    np.testing.assert_allclose(points["base"][:2].T, GSR_BASE, atol=0)
    np.testing.assert_allclose(points["platform"][:2].T, pose[:2] + GSR_PLATFORM @ rotation(pose[2]).T, atol=1e-12)
    assert not points["base"][2].any() and not points["platform"][2].any()
