"""6-RUS rotary hexapod: Dietmaier's 40-mode problem on cranks, the inverse branches, rates,
singularities and the drawing, each against an independent source.

Independent sources: the default layout typed in again in NumPy (three motor pairs at 0, 120
and 240 degrees, shafts at +-10 degrees on a 0.4 m circle, platform joints at +-50 degrees on a
0.3 m circle, cranks 0.15 m, rods 0.6 m); crank tips E_i = A_i + a_i (cos theta_i e1_i + sin
theta_i e2_i) and rods |R c_i + p - E_i| in NumPy; Dietmaier's (1998) numbers (stewart's
DIETMAIER_* constants) and the 40 modes that the generated ``stewart`` package finds for his leg
lengths by its homotopy, a solver that shares nothing with this mechanism's model.
"""

from __future__ import annotations

import numpy as np
import pytest
from parakin.mechanisms import rus6
from parakin.mechanisms.stewart import (
    DIETMAIER_BASE,
    DIETMAIER_LENGTHS,
    DIETMAIER_PLATFORM,
    DIETMAIER_POSITION,
    DIETMAIER_ROTATION,
)

import parakin
from parakin.errors import SingularConfigurationError
from parakin.interfaces.demo import run_examples
from parakin.pose import wrap_angle
from parakin.results import Configuration
from parakin.solvers.linalg import pivoted_solve

CENTRES = np.radians([0.0, 0.0, 120.0, 120.0, 240.0, 240.0])
SIDES = np.array([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0])
RADIAL = np.stack([np.cos(CENTRES), np.sin(CENTRES), np.zeros(6)], -1)
TANGENT = np.stack([-np.sin(CENTRES), np.cos(CENTRES), np.zeros(6)], -1)
SHAFT_ANGLES = CENTRES + SIDES * np.radians(10.0)
JOINT_ANGLES = CENTRES + SIDES * np.radians(50.0)
SHAFTS = 0.4 * np.stack([np.cos(SHAFT_ANGLES), np.sin(SHAFT_ANGLES), np.zeros(6)], -1)
AXES = SIDES[:, None] * RADIAL
ZEROS = SIDES[:, None] * TANGENT
PLATFORM = 0.3 * np.stack([np.cos(JOINT_ANGLES), np.sin(JOINT_ANGLES), np.zeros(6)], -1)
CRANKS = np.full(6, 0.15)
RODS = np.full(6, 0.6)
DIETMAIER_THETA = np.pi / 6
#: the quoted pose of Dietmaier (1998)
QUOTED = np.eye(4)
QUOTED[:3, :3] = DIETMAIER_ROTATION
QUOTED[:3, 3] = DIETMAIER_POSITION


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def m(request):
    return parakin.load("rus6", backend=request.param)


@pytest.fixture(scope="module")
def dietmaier():
    example = next(e for e in parakin.metadata("rus6").examples if e.name == "dietmaier_cranks")
    return parakin.load("rus6", backend="numpy", **example.parameters)


# ------------------------------------------------------------------ the independent reference
def group(mechanism, name: str) -> np.ndarray:
    values = mechanism.parameters
    return np.array([[values[f"{name}_{axis}{k}"] for axis in "xyz"] for k in range(1, 7)])


def rotation_of(q: np.ndarray) -> np.ndarray:
    """R of a quaternion (scalar first), normalised."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def crank_tips(theta: np.ndarray, shafts=SHAFTS, cranks=CRANKS) -> np.ndarray:
    e2 = np.cross(AXES, ZEROS)
    return shafts + cranks[:, None] * (np.cos(theta)[:, None] * ZEROS + np.sin(theta)[:, None] * e2)


def joints(pose: np.ndarray, platform=PLATFORM) -> np.ndarray:
    return platform @ pose[:3, :3].T + pose[:3, 3]


def rod_errors(theta, pose, shafts=SHAFTS, platform=PLATFORM, rods=RODS) -> np.ndarray:
    """|B_i - E_i| - b_i."""
    return np.linalg.norm(joints(pose, platform) - crank_tips(theta, shafts), axis=1) - rods


def reference_inverse(pose: np.ndarray, shafts=SHAFTS, platform=PLATFORM, rods=RODS):
    """Per leg the two crank angles angle(v) -+ gamma (v = B_i - A_i in the crank plane, gamma
    from the law of cosines with the projected distance), NaN where unreachable."""
    v = joints(pose, platform) - shafts
    e2 = np.cross(AXES, ZEROS)
    along, up = (v * ZEROS).sum(-1), (v * e2).sum(-1)
    normal = (v * AXES).sum(-1)
    planar = np.hypot(along, up)
    with np.errstate(invalid="ignore"):
        gamma = np.arccos((planar**2 + CRANKS**2 - (rods**2 - normal**2)) / (2 * CRANKS * planar))
    angle = np.arctan2(up, along)
    return angle - gamma, angle + gamma


def move(pose: np.ndarray, twist: np.ndarray, t: float) -> np.ndarray:
    """The pose after a time t at the constant twist (v of the origin of {P}, w), both in {B}."""
    w = twist[3:] * t
    angle = np.linalg.norm(w)
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]) / (angle or 1.0)
    turn = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    out = pose.copy()
    out[:3, :3] = turn @ pose[:3, :3]
    out[:3, 3] = pose[:3, 3] + t * twist[:3]
    return out


def pose_of(passive: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = rotation_of(passive[3:])
    out[:3, 3] = passive[:3]
    return out


# ------------------------------------------------------------------ defaults and home
def test_default_layout_is_the_documented_one(m):
    """Shafts, axes, crank directions, platform joints, cranks and rods as typed in here; the
    crank frames are orthonormal with e2 = u x e1 = z (cranks rise for theta > 0)."""
    np.testing.assert_allclose(group(m, "base"), SHAFTS, atol=1e-15)
    np.testing.assert_allclose(group(m, "axis"), AXES, atol=1e-15)
    np.testing.assert_allclose(group(m, "crank_zero"), ZEROS, atol=1e-15)
    np.testing.assert_allclose(group(m, "platform"), PLATFORM, atol=1e-15)
    assert [m.parameters[f"a{k}"] for k in range(1, 7)] == list(CRANKS)
    assert [m.parameters[f"b{k}"] for k in range(1, 7)] == list(RODS)
    np.testing.assert_allclose(np.cross(AXES, ZEROS), np.tile([0.0, 0.0, 1.0], (6, 1)), atol=1e-15)


def test_home_has_level_cranks_and_is_regular(m):
    """Home: R = I, p = (0, 0, sqrt(b^2 - h^2)) with h the horizontal distance from a level crank
    tip to its platform joint (by hand for leg 1), theta = 0 (1e-15), closing to 1e-15; pivot
    ratio of the closure Jacobian > 0.1."""
    h = np.linalg.norm((PLATFORM[0] - SHAFTS[0] - CRANKS[0] * ZEROS[0])[:2])
    assert h == pytest.approx(0.2013532097851158, abs=1e-15)
    np.testing.assert_allclose(m.home_passive, [0, 0, np.sqrt(0.36 - h**2), 1, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(m.home_actuated, 0.0, atol=1e-15)
    assert np.abs(rod_errors(m.home_actuated, pose_of(m.home_passive))).max() < 1e-15
    jacobian = m.loop_closure(m.home_actuated, m.home_passive)["jacobian"]
    assert float(pivoted_solve(jacobian, np.zeros(7))[1]) > 0.1


def test_crank_range_is_enforced():
    """Crank angles outside [-pi/2, pi/2] are refused by every solver (BadInputError naming the crank)."""
    m = parakin.load("rus6", backend="numpy")
    theta = m.home_actuated.copy()
    theta[2] = 1.6
    with pytest.raises(parakin.BadInputError, match="theta3"):
        m.forward_pose(theta, guess=m.home_passive)
    wide = parakin.load("rus6", backend="numpy", limits={"theta3": (-np.pi, np.pi)})
    assert wide.forward_pose(theta, guess=m.home_passive, strict=False).pose.shape == (4, 4)


# ------------------------------------------------------------------ Dietmaier's problem on cranks
def test_dietmaier_cranks_put_the_tips_on_dietmaiers_base_points(dietmaier):
    """At theta = pi/6 the crank tips of the example's shafts are Dietmaier's X_i (1e-15); its
    platform joints and rods are Dietmaier's x_i and leg lengths."""
    tips = crank_tips(np.full(6, DIETMAIER_THETA), shafts=group(dietmaier, "base"))
    np.testing.assert_allclose(tips, DIETMAIER_BASE, atol=1e-15)
    np.testing.assert_allclose(group(dietmaier, "platform"), DIETMAIER_PLATFORM, atol=0)
    assert [dietmaier.parameters[f"b{k}"] for k in range(1, 7)] == DIETMAIER_LENGTHS


def test_inverse_of_dietmaiers_pose_gives_the_crank_angles_on_one_branch(dietmaier):
    """inverse_pose of the quoted pose: one valid branch has theta = pi/6 on every leg (1e-9;
    the printed lengths agree with the quoted pose to 4e-13 m), and there the loop closure
    (generated and NumPy) vanishes to 1e-9."""
    ik = dietmaier.inverse_pose(QUOTED)
    error = np.abs(wrap_angle(ik.actuated - DIETMAIER_THETA)).max(-1)
    k = int(np.argmin(np.where(ik.valid, error, np.inf)))
    assert ik.valid[k] and error[k] < 1e-9, f"nearest valid branch {k} is {error[k]:.3g} from pi/6"
    theta = np.full(6, DIETMAIER_THETA)
    residual = dietmaier.loop_closure(theta, ik.passive[k])["residual"]
    assert np.abs(residual).max() < 1e-9
    errors = rod_errors(theta, QUOTED, group(dietmaier, "base"), DIETMAIER_PLATFORM, np.array(DIETMAIER_LENGTHS))
    assert np.abs(errors).max() < 1e-9
    np.testing.assert_allclose(pose_of(ik.passive[k]), QUOTED, atol=1e-12)


def test_dietmaiers_forty_modes_are_assembly_modes_of_the_cranks(dietmaier):
    """stewart's forward_pose_all for Dietmaier's lengths: 40 real modes (his count), pairwise
    distinct; each closes the rus6 loop at theta = pi/6 to 1e-8 (generated closure and NumPy rod
    lengths), and rus6's Newton from 1e-4 away returns to it (1e-9): all 40 are modes of the
    6-RUS at these cranks. The quoted pose is among them."""
    modes = parakin.load("stewart", backend="numpy").forward_pose_all(DIETMAIER_LENGTHS)
    assert int(modes.count) == 40
    passive = modes.passive[modes.valid]
    poses = modes.poses[modes.valid]
    theta = np.broadcast_to(np.full(6, DIETMAIER_THETA), (40, 6))
    residual = dietmaier.loop_closure(theta, passive)["residual"]
    assert np.abs(residual).max() < 1e-8
    lengths = np.array(DIETMAIER_LENGTHS)
    shafts = group(dietmaier, "base")
    for pose in poses:
        assert np.abs(rod_errors(theta[0], pose, shafts, DIETMAIER_PLATFORM, lengths)).max() < 1e-8
    fk = dietmaier.forward_pose(theta, guess=passive + 1e-4)
    assert fk.converged.all()
    assert np.abs(fk.pose - poses).max() < 1e-9
    apart = np.abs(poses[:, None] - poses[None]).max(axis=(-2, -1)) + np.eye(40)
    assert apart.min() > 1e-3
    assert np.abs(poses - QUOTED).max(axis=(-2, -1)).min() < 1e-8


# ------------------------------------------------------------------ inverse
def test_inverse_branches_are_the_reference_crank_angles(m):
    """Random poses near home: on every branch each crank angle is angle -+ gamma of the NumPy
    reference (sigma = +1 the minus sign, the crank turned back from A_i -> B_i), and valid
    branches close every rod (1e-12)."""
    rng = np.random.default_rng(20261125)
    checked = 0
    home = pose_of(m.home_passive)
    for _ in range(30):
        pose = move(home, np.concatenate([0.03 * rng.normal(size=3), 0.1 * rng.normal(size=3)]), 1.0)
        minus, plus = reference_inverse(pose)
        ik = m.inverse_pose(pose, strict=False)
        if not np.isfinite(minus).all():
            assert not ik.valid.any()
            continue
        for k, signs in enumerate(ik.branches):
            expected = np.where(np.asarray(signs) > 0, minus, plus)
            assert np.abs(wrap_angle(ik.actuated[k] - expected)).max() < 1e-12
            if ik.valid[k]:
                assert np.abs(rod_errors(ik.actuated[k], pose)).max() < 1e-12
        assert ik.valid[0]  # branch 0 is the working mode near home
        checked += 1
    assert checked >= 25


# ------------------------------------------------------------------ rates and singularities
def test_inverse_rate_matches_finite_differences_of_the_reference_inverse(m):
    """theta_dot for a twist against central differences of the reference crank angles (branch
    0) along the twist; forward_rate inverts it."""
    rng = np.random.default_rng(11)
    step = 1e-6
    home = pose_of(m.home_passive)
    for _ in range(10):
        pose = move(home, np.concatenate([0.02 * rng.normal(size=3), 0.05 * rng.normal(size=3)]), 1.0)
        twist = rng.normal(size=6)
        numeric = (reference_inverse(move(pose, twist, step))[0] - reference_inverse(move(pose, twist, -step))[0]) / (
            2 * step
        )
        state = m.inverse_pose(pose).branch(0)
        rates = m.inverse_rate(state, twist)
        np.testing.assert_allclose(rates.actuated, numeric, rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(m.forward_rate(state, rates.actuated), twist, atol=1e-8)


def test_rate_matrices_and_factors_against_numpy(m):
    """A rows (d_i, (E_i - p) x d_i), B = diag(u_i . ((E_i - A_i) x d_i)); det A is the named type
    II factor (written differently: a block Laplace expansion of polynomial rows), the serial
    factors the diagonal of B."""
    pose = move(pose_of(m.home_passive), np.array([0.01, -0.02, 0.03, 0.05, -0.04, 0.1]), 1.0)
    state = m.inverse_pose(pose).branch(0)
    tips = crank_tips(state.actuated)
    d = joints(pose) - tips
    a = np.column_stack([d, np.cross(tips - pose[:3, 3], d)])
    b = np.diag((AXES * np.cross(tips - SHAFTS, d)).sum(-1))
    jacobians = m.rate_jacobians(state)
    np.testing.assert_allclose(jacobians["a"], a, atol=1e-14)
    np.testing.assert_allclose(jacobians["b"], b, atol=1e-14)
    factors = m.singularities(state)
    assert factors["rod_lines_dependent"] == pytest.approx(np.linalg.det(a), rel=1e-9)
    for k in range(6):
        assert factors[f"leg{k + 1}_rod_in_crank_axis_plane"] == pytest.approx(b[k, k], rel=1e-12)


def test_type2_singularity_where_every_rod_line_meets_one_point():
    """Shafts placed so that at theta = 0 each rod lies on the line from its platform joint to a
    common point O: six lines through one point span at most 3 dimensions of Pluecker space, so
    det A = 0 (relative to its rows), and forward_rate refuses."""
    pose = np.eye(4)
    pose[:3, 3] = [0.01, -0.02, 0.55]
    centre = np.array([0.02, 0.01, -0.3])
    points = joints(pose)
    towards = (centre - points) / np.linalg.norm(centre - points, axis=1)[:, None]
    tips = points + RODS[:, None] * towards
    shafts = tips - CRANKS[:, None] * ZEROS
    g = parakin.load("rus6", backend="numpy", base=shafts)
    theta = np.zeros(6)
    passive = np.array([*pose[:3, 3], 1.0, 0.0, 0.0, 0.0])
    assert np.abs(g.loop_closure(theta, passive)["residual"]).max() < 1e-15
    state = Configuration(theta, passive, pose)
    a = g.rate_jacobians(state)["a"]
    scale = np.prod(np.linalg.norm(a, axis=1))
    assert abs(g.singularities(state)["rod_lines_dependent"]) < 1e-13 * scale
    with pytest.raises(SingularConfigurationError):
        g.forward_rate(state, np.ones(6) * 0.1)


# ------------------------------------------------------------------ drawing and examples
def test_drawing_points(m):
    pose = move(pose_of(m.home_passive), np.array([0.01, 0.02, -0.01, 0.03, 0.02, -0.05]), 1.0)
    state = m.inverse_pose(pose).branch(0)
    points = m.drawing(state)
    np.testing.assert_allclose(points["base"].T, SHAFTS, atol=1e-15)
    np.testing.assert_allclose(points["elbow"].T, crank_tips(state.actuated), atol=1e-14)
    np.testing.assert_allclose(points["platform"].T, joints(pose), atol=1e-14)


def test_named_examples_hold():
    for result in run_examples("rus6", backend="numpy"):
        assert result.holds, (result.example.name, result.error, result.comparisons)


def test_dietmaiers_forty_modes_from_the_derived_polynomial_form(dietmaier):
    """No forward model is written in the mechanism file: forward_pose_all at theta = pi/6 (the
    generator's polynomial form of the closure, the crank angles entering through the circle
    parametrisation) gives the 40 modes stewart's own homotopy finds for Dietmaier's lengths
    (1e-9, a bijection), from the 80 paths of the family (q and -q)."""
    assert set(dietmaier.capabilities.forward_methods) == {"automatic"}
    modes = dietmaier.forward_pose_all(np.full(6, DIETMAIER_THETA))
    assert int(modes.count) == 40
    reference = parakin.load("stewart", backend="numpy").forward_pose_all(DIETMAIER_LENGTHS)
    a, b = modes.poses[modes.valid], reference.poses[reference.valid]
    apart = np.abs(a[:, None] - b[None]).max(axis=(-2, -1))
    assert apart.min(1).max() < 1e-9 and apart.min(0).max() < 1e-9
    assert int(modes.certificate()["root_count"]) == 80


def test_every_endpoint_at_dietmaiers_input_is_certified(dietmaier):
    """74 of the 80 endpoints certify in double precision; the rest in exact arithmetic
    (``parakin.solvers.exact_certify``): complete, with the count proven."""
    certificate = dietmaier.forward_pose_all(np.full(6, DIETMAIER_THETA)).certificate()
    assert int(certificate["certified_roots"]) == int(certificate["root_count"]) == 80
    assert bool(certificate["complete"])
    double = dietmaier.forward_pose_all(np.full(6, DIETMAIER_THETA), certify="double").certificate()
    assert int(double["certified_roots"]) < 80 and not bool(double["complete"])


def test_module_constants_agree_with_the_reference():
    """The module's Dietmaier crank angle and its example pose are the ones used here."""
    assert rus6.DIETMAIER_THETA == DIETMAIER_THETA
    np.testing.assert_allclose(np.array(rus6.DIETMAIER_POSE), QUOTED, atol=0)
