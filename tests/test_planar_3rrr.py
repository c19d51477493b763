"""Planar 3-RRR: the six-real-mode input, the inverse branches, rates, singularities and the
drawing, each against a reference written here in NumPy.

The independent reference: the default geometry typed in again (joints at 210, 330 and 90
degrees on circles of 0.5 m and 0.3 m, cranks 0.3 m, links 0.35 m); elbows E_i = A_i + a_i (cos
theta_i, sin theta_i); every assembly mode of given cranks by a dense sign-change scan over phi of
the leg-1 equation after legs 2 and 3 minus leg 1 are solved for the position (a 3-RPR on the
elbows), refined by Brent's method and polished by Newton on the full residual.
"""

from __future__ import annotations

import numpy as np
import pytest
from parakin.mechanisms import planar_3rrr
from scipy.optimize import brentq

import parakin
from parakin.errors import SingularConfigurationError
from parakin.interfaces.demo import run_examples
from parakin.pose import wrap_angle
from parakin.results import Configuration
from parakin.solvers.linalg import pivoted_solve

ANGLES = np.radians([210.0, 330.0, 90.0])
UNIT = np.stack([np.cos(ANGLES), np.sin(ANGLES)], -1)
BASE = 0.5 * UNIT
PLATFORM = 0.3 * UNIT
CRANKS = np.full(3, 0.3)
LINKS = np.full(3, 0.35)
#: the crank angles the module names for six real modes: (-54, 174, -105) degrees
SIX_INPUT = np.radians([-54.0, 174.0, -105.0])


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def m(request):
    return parakin.load("planar_3rrr", backend=request.param)


# ------------------------------------------------------------------ the independent reference
def rotation(phi: float) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


def elbows(theta: np.ndarray, base=BASE, cranks=CRANKS) -> np.ndarray:
    return base + cranks[:, None] * np.stack([np.cos(theta), np.sin(theta)], -1)


def platform_joints(pose: np.ndarray, platform=PLATFORM) -> np.ndarray:
    return pose[:2] + platform @ rotation(pose[2]).T


def residual(theta: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """(|B_i - E_i|^2 - b_i^2) / (2 b_i)."""
    d = platform_joints(pose) - elbows(theta)
    return ((d**2).sum(-1) - LINKS**2) / (2 * LINKS)


def newton(theta: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """Newton on the residual in (x, y, phi), with central-difference Jacobians."""
    pose = np.array(pose, dtype=float)
    for _ in range(30):
        value = residual(theta, pose)
        if np.abs(value).max() < 1e-15:
            break
        step = 1e-7
        jacobian = np.stack(
            [(residual(theta, pose + step * e) - residual(theta, pose - step * e)) / (2 * step) for e in np.eye(3)], -1
        )
        pose = pose - np.linalg.solve(jacobian, value)
    return pose


def scan_modes(theta: np.ndarray, samples: int = 400_001) -> np.ndarray:
    """Every assembly mode (x, y, phi) of the cranks theta: legs 2, 3 minus leg 1 are linear in
    p = (x, y); leg 1 times det^2 (no poles) is scanned over phi in [-pi, pi) for sign changes."""
    e = elbows(theta)

    def leg1(phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        phi = np.atleast_1d(phi)
        c, s = np.cos(phi), np.sin(phi)
        turned = np.stack(
            [
                c[:, None] * PLATFORM[:, 0] - s[:, None] * PLATFORM[:, 1],
                s[:, None] * PLATFORM[:, 0] + c[:, None] * PLATFORM[:, 1],
            ],
            -1,
        )
        w = turned - e  # B_i - E_i = p + w_i
        rows = 2 * (w[:, 1:] - w[:, :1])
        right = -((w[:, 1:] ** 2).sum(-1) - LINKS[1:] ** 2 - (w[:, :1] ** 2).sum(-1) + LINKS[0] ** 2)
        det = rows[:, 0, 0] * rows[:, 1, 1] - rows[:, 0, 1] * rows[:, 1, 0]
        px = right[:, 0] * rows[:, 1, 1] - right[:, 1] * rows[:, 0, 1]
        py = rows[:, 0, 0] * right[:, 1] - rows[:, 1, 0] * right[:, 0]
        value = (px + det * w[:, 0, 0]) ** 2 + (py + det * w[:, 0, 1]) ** 2 - LINKS[0] ** 2 * det**2
        with np.errstate(all="ignore"):
            return np.stack([px / det, py / det], -1), value

    grid = np.linspace(-np.pi, np.pi, samples)
    values = leg1(grid[:-1])[1]
    values = np.append(values, values[0])  # periodic: the last interval closes at -pi
    modes = []
    for k in np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0):
        phi = brentq(lambda t: leg1(t)[1][0], grid[k], grid[k + 1], xtol=1e-15)
        pose = newton(theta, np.array([*leg1(phi)[0][0], phi]))
        if np.abs(residual(theta, pose)).max() < 1e-12:
            modes.append(pose)
    return np.array(modes).reshape(-1, 3)


def planar(poses: np.ndarray) -> np.ndarray:
    return np.stack([poses[..., 0, 3], poses[..., 1, 3], np.arctan2(poses[..., 1, 0], poses[..., 0, 0])], -1)


def distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    difference = np.asarray(a, dtype=float) - b
    difference[..., 2] = wrap_angle(difference[..., 2])
    return np.abs(difference).max(-1)


# ------------------------------------------------------------------ the defaults
def test_default_geometry_is_the_documented_one(m):
    """Base joints at 0.5 m, platform joints at 0.3 m (210, 330, 90 deg), cranks 0.3, links 0.35."""
    values = m.parameters
    np.testing.assert_allclose([[values[f"base_x{k}"], values[f"base_y{k}"]] for k in (1, 2, 3)], BASE, atol=1e-15)
    np.testing.assert_allclose(
        [[values[f"platform_x{k}"], values[f"platform_y{k}"]] for k in (1, 2, 3)], PLATFORM, atol=1e-15
    )
    assert [values[f"a{k}"] for k in (1, 2, 3)] == list(CRANKS)
    assert [values[f"b{k}"] for k in (1, 2, 3)] == list(LINKS)


def test_home_is_centred_and_regular(m):
    """Home: p = 0, phi = 0 on branch 0, closing the loop (1e-12) with a pivot ratio > 0.3."""
    np.testing.assert_allclose(m.home_passive, [0.0, 0.0, 0.0], atol=1e-15)
    assert np.abs(residual(m.home_actuated, m.home_passive)).max() < 1e-12
    jacobian = m.loop_closure(m.home_actuated, m.home_passive)["jacobian"]
    assert float(pivoted_solve(jacobian, np.zeros(3))[1]) > 0.3


# ------------------------------------------------------------------ six real assembly modes
def test_six_mode_input_has_six_modes_by_the_independent_scan():
    """theta = (-54, 174, -105) deg: the scan finds exactly 6 real modes, each closing every leg
    to 1e-9, equal to the module's SIX_MODES to 1e-9 (a bijection)."""
    np.testing.assert_allclose(planar_3rrr.SIX_MODES_INPUT, SIX_INPUT, atol=1e-15)
    reference = scan_modes(SIX_INPUT)
    assert reference.shape[0] == 6, f"{reference.shape[0]} real modes found, 6 expected"
    for pose in reference:
        assert np.abs(residual(SIX_INPUT, pose)).max() < 1e-9
    printed = np.array(planar_3rrr.SIX_MODES)
    matches = distance(reference[:, None, :], printed[None, :, :])
    assert matches.min(1).max() < 1e-9 and matches.min(0).max() < 1e-9
    # distinct modes: no two within 1e-3 of each other
    apart = distance(reference[:, None, :], reference[None, :, :]) + np.eye(6)
    assert apart.min() > 1e-3


def test_six_modes_close_the_generated_loop_and_newton_returns_to_each(m):
    """Each of the six modes closes the generated loop closure (1e-9); Newton (forward_pose)
    from a guess 1e-3 away converges back to it (1e-9); the inverse of each mode has a valid
    branch with the six-mode input (1e-9)."""
    modes = scan_modes(SIX_INPUT)
    closure = m.loop_closure(np.broadcast_to(SIX_INPUT, (6, 3)), modes)["residual"]
    assert np.abs(closure).max() < 1e-9
    fk = m.forward_pose(np.broadcast_to(SIX_INPUT, (6, 3)), guess=modes + 1e-3)
    assert fk.converged.all()
    assert distance(fk.passive, modes).max() < 1e-9
    ik = m.inverse_pose(modes, strict=False)
    mismatch = np.abs(wrap_angle(ik.actuated - SIX_INPUT)).max(-1)
    assert np.where(ik.valid, mismatch, np.inf).min(-1).max() < 1e-9


# ------------------------------------------------------------------ inverse
def test_inverse_branches_are_the_two_circle_intersections(m):
    """Random poses near home: each leg's two angles are angle(v) +- acos((|v|^2 + a^2 - b^2) /
    (2 a |v|)) with v = B_i - A_i, sigma = +1 the counter-clockwise one; valid branches close."""
    rng = np.random.default_rng(20261125)
    checked = 0
    for _ in range(30):
        pose = np.array([*rng.uniform(-0.08, 0.08, 2), rng.uniform(-0.4, 0.4)])
        v = platform_joints(pose) - BASE
        reach = np.linalg.norm(v, axis=1)
        cosine = (reach**2 + CRANKS**2 - LINKS**2) / (2 * CRANKS * reach)
        if np.abs(cosine).max() >= 1:
            continue
        angle, gamma = np.arctan2(v[:, 1], v[:, 0]), np.arccos(cosine)
        ik = m.inverse_pose(pose)
        assert ik.valid.all()
        for k, signs in enumerate(ik.branches):
            expected = angle + np.asarray(signs) * gamma
            assert np.abs(wrap_angle(ik.actuated[k] - expected)).max() < 1e-12
            assert np.abs(residual(ik.actuated[k], pose)).max() < 1e-12
        checked += 1
    assert checked >= 25


def test_unreachable_leg_is_flagged():
    """A pose with B_1 beyond a_1 + b_1 = 0.65 m from A_1: no valid branch (leg1_reachable)."""
    m = parakin.load("planar_3rrr", backend="numpy")
    pose = np.array([0.5, 0.4, 0.0])
    assert np.linalg.norm(platform_joints(pose)[0] - BASE[0]) > 0.65
    ik = m.inverse_pose(pose, strict=False)
    assert not ik.valid.any() and ik.failures["leg1_reachable"].all()
    with pytest.raises(parakin.UnreachablePoseError):
        m.inverse_pose(pose)


# ------------------------------------------------------------------ rates and singularities
def test_inverse_rate_matches_finite_differences_of_the_reference_inverse(m):
    """theta_dot for a twist (vx, vy, wz) against central differences of the circle-intersection
    angles along (x, y, phi) + h (vx, vy, wz); forward_rate inverts it."""
    rng = np.random.default_rng(5)
    h = 1e-6
    for _ in range(15):
        pose = np.array([*rng.uniform(-0.05, 0.05, 2), rng.uniform(-0.3, 0.3)])
        twist = rng.normal(size=3)

        def angles(q: np.ndarray) -> np.ndarray:
            v = platform_joints(q) - BASE
            reach = np.linalg.norm(v, axis=1)
            gamma = np.arccos((reach**2 + CRANKS**2 - LINKS**2) / (2 * CRANKS * reach))
            return np.arctan2(v[:, 1], v[:, 0]) + gamma  # branch 0

        numeric = wrap_angle(angles(pose + h * twist) - angles(pose - h * twist)) / (2 * h)
        state = m.inverse_pose(pose).branch(0)
        rates = m.inverse_rate(state, twist)
        np.testing.assert_allclose(rates.actuated, numeric, rtol=1e-6, atol=1e-7)
        np.testing.assert_allclose(m.forward_rate(state, rates.actuated), twist, atol=1e-9)


def test_rate_matrices_and_factors_against_numpy(m):
    """A rows (d, ((E_i - p) x d_i)_z), B = diag(((E_i - A_i) x d_i)_z); det A is the named
    type II factor, the serial factors the diagonal of B."""
    pose = np.array([0.03, -0.02, 0.2])
    state = m.inverse_pose(pose).branch(0)
    e = elbows(state.actuated)
    d = platform_joints(pose) - e
    lever = e - pose[:2]
    a = np.column_stack([d, lever[:, 0] * d[:, 1] - lever[:, 1] * d[:, 0]])
    crank = e - BASE
    b = np.diag(crank[:, 0] * d[:, 1] - crank[:, 1] * d[:, 0])
    jacobians = m.rate_jacobians(state)
    np.testing.assert_allclose(jacobians["a"], a, atol=1e-14)
    np.testing.assert_allclose(jacobians["b"], b, atol=1e-14)
    factors = m.singularities(state)
    assert factors["link_lines_concurrent_or_parallel"] == pytest.approx(np.linalg.det(a), rel=1e-10)
    for k in range(3):
        assert factors[f"leg{k + 1}_links_aligned"] == pytest.approx(b[k, k], rel=1e-12)


def test_type2_singularity_where_the_link_lines_meet():
    """Elbows placed on the lines from a common point O through the platform joints (and the
    base joints a crank length away): the link lines are concurrent, det A = 0 relative to its
    rows, and forward_rate refuses."""
    pose = np.array([0.02, 0.01, 0.1])
    points = platform_joints(pose)
    centre = np.array([0.05, 0.03])
    towards = (centre - points) / np.linalg.norm(centre - points, axis=1)[:, None]
    elbow = points - LINKS[:, None] * towards  # link i on the line O B_i
    outward = np.array([[-1.0, 0.2], [0.9, 0.5], [0.1, 1.0]])
    outward /= np.linalg.norm(outward, axis=1)[:, None]
    base = elbow + CRANKS[:, None] * outward
    g = parakin.load("planar_3rrr", backend="numpy", base=base)
    theta = np.arctan2(-outward[:, 1], -outward[:, 0])
    state = Configuration(theta, pose, parakin.pose.transform_from_pose(pose, "planar"))
    assert np.abs(g.loop_closure(theta, pose)["residual"]).max() < 1e-15
    a = g.rate_jacobians(state)["a"]
    scale = np.prod(np.linalg.norm(a, axis=1))
    assert abs(g.singularities(state)["link_lines_concurrent_or_parallel"]) < 1e-13 * scale
    with pytest.raises(SingularConfigurationError):
        g.forward_rate(state, [1.0, 0.0, 0.0])


# ------------------------------------------------------------------ drawing and examples
def test_drawing_points(m):
    pose = np.array([0.02, -0.03, 0.15])
    state = m.inverse_pose(pose).branch(0)
    points = m.drawing(state)
    np.testing.assert_allclose(points["base"][:2].T, BASE, atol=1e-15)
    np.testing.assert_allclose(points["elbow"][:2].T, elbows(state.actuated), atol=1e-14)
    np.testing.assert_allclose(points["platform"][:2].T, platform_joints(pose), atol=1e-14)
    assert not points["base"][2].any() and not points["elbow"][2].any() and not points["platform"][2].any()


def test_named_examples_hold():
    for result in run_examples("planar_3rrr", backend="numpy"):
        assert result.holds, (result.example.name, result.error, result.comparisons)


def test_every_mode_of_the_six_mode_input_from_the_derived_polynomial_form(m):
    """No forward model is written in the mechanism file: forward_pose_all (the generator's
    polynomial form of the closure, method "automatic") finds the scan's six modes (1e-9, a
    bijection), and the certificate proves that no other solution exists (6 distinct certified
    roots = the root count proven by the trace test)."""
    assert set(m.capabilities.forward_methods) == {"automatic"}
    modes = m.forward_pose_all(SIX_INPUT)
    assert int(modes.count) == 6
    found = modes.passive[modes.valid]
    reference = scan_modes(SIX_INPUT)
    matches = distance(found[:, None, :], reference[None, :, :])
    assert matches.min(1).max() < 1e-9 and matches.min(0).max() < 1e-9
    certificate = modes.certificate()
    assert int(certificate["root_count"]) == 6 and bool(certificate["complete"])
