"""The general 6-6 Gough-Stewart platform (mechanisms/stewart.py): every assembly mode by the
generated parameter homotopy, checked against Dietmaier's 40 real modes, the inverse pose of
random geometries, an independent multi-start search and special geometries."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from scipy.optimize import least_squares

import parakin
from parakin.errors import SelfMotionError
from parakin.pose import euler_zyx_to_rotation

BACKENDS = ["compiled", "numpy"]

DIETMAIER_LENGTHS = [1.0, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071]
DIETMAIER_ROTATION = np.array(
    [
        [-0.040450357031281, -0.932229494397471, 0.359599691867884],
        [0.983337493748685, 0.026695523074364, 0.179818582009314],
        [-0.177231887661606, 0.360881585597300, 0.915616371179918],
    ]
)
DIETMAIER_POSITION = np.array([0.955868038233880, -0.046995628998516, -0.290013283037649])


def leg_lengths(base: np.ndarray, platform: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """|R b_i + p - A_i|, written here independently of the generated code."""
    rotation, position = pose[..., :3, :3], pose[..., :3, 3]
    legs = np.einsum("...ij,kj->...ki", rotation, platform) + position[..., None, :] - base
    return np.linalg.norm(legs, axis=-1)


@pytest.fixture(scope="module", params=BACKENDS)
def dietmaier(request):
    m = parakin.load("stewart", backend=request.param)
    return m, m.forward_pose_all(DIETMAIER_LENGTHS)


def geometry(m) -> tuple[np.ndarray, np.ndarray]:
    params = {p.name: value for p, value in zip(m.manifest.parameters, m.params, strict=True)}
    base = np.array([[params[f"base_{a}{k}"] for a in "xyz"] for k in range(1, 7)])
    platform = np.array([[params[f"platform_{a}{k}"] for a in "xyz"] for k in range(1, 7)])
    return base, platform


def test_dietmaier_has_40_real_modes_all_accounted(dietmaier):
    m, modes = dietmaier
    assert modes.count == 40
    certificate = modes.certificate()
    assert certificate["roots"] == 40 and certificate["with_modes"] == 40
    poses = modes.poses[modes.valid]
    base, platform = geometry(m)
    # every mode reproduces the leg lengths (independent evaluation) and is a rigid pose
    assert np.abs(leg_lengths(base, platform, poses) - DIETMAIER_LENGTHS).max() < 1e-12
    rotations = poses[:, :3, :3]
    assert np.abs(np.einsum("kij,kil->kjl", rotations, rotations) - np.eye(3)).max() < 1e-12
    assert np.linalg.det(rotations).min() > 0.999999
    # 40 distinct poses
    distance = np.abs(poses[:, None] - poses[None]).max(axis=(-2, -1)) + np.eye(40)
    assert distance.min() > 1e-6
    assert modes.residual[modes.valid].max() < 1e-12


def test_dietmaier_quoted_pose_is_a_mode(dietmaier):
    _, modes = dietmaier
    poses = modes.poses[modes.valid]
    error = np.abs(poses[:, :3, :3] - DIETMAIER_ROTATION).max(axis=(-2, -1))
    error = np.maximum(error, np.abs(poses[:, :3, 3] - DIETMAIER_POSITION).max(-1))
    # the lengths are printed to 6 decimals: the pose moves by about 1e-6 with them
    assert error.min() < 2e-5


def leg_jacobian_condition(base: np.ndarray, platform: np.ndarray, pose: np.ndarray, step: float = 1e-7) -> float:
    """cond of d(leg lengths) / d(twist) by central differences (an independent check)."""
    from scipy.spatial.transform import Rotation

    columns = []
    for k in range(6):
        delta = np.zeros(6)
        delta[k] = step

        def moved(sign: float, delta: np.ndarray = delta) -> np.ndarray:
            shifted = pose.copy()
            shifted[:3, 3] += sign * delta[:3]
            shifted[:3, :3] = Rotation.from_rotvec(sign * delta[3:]).as_matrix() @ pose[:3, :3]
            return leg_lengths(base, platform, shifted)

        columns.append((moved(1.0) - moved(-1.0)) / (2 * step))
    return float(np.linalg.cond(np.array(columns).T))


def test_dietmaier_near_singular_cluster_is_kept(dietmaier):
    """Six of the 40 modes are ill-conditioned (Dietmaier's near-singular cluster: condition
    numbers of the leg Jacobian 2.7e3 ... 7.3e4 here, 'about 2e5' as quoted, for another
    normalisation); none is dropped, and the reported conditioning ranks them worst."""
    m, modes = dietmaier
    base, platform = geometry(m)
    poses = modes.poses[modes.valid]
    condition = np.array([leg_jacobian_condition(base, platform, pose) for pose in poses])
    worst = np.argsort(-condition)[:6]
    assert condition[worst].min() > 2e3 and 3e4 < condition.max() < 1e6
    assert np.sort(condition)[-5] > 1e4 > np.sort(condition)[-6]
    # the reported conditioning (sigma_min / sigma_max of the closure Jacobian) ranks the five worst alike
    ratio = modes.conditioning[modes.valid]
    assert set(np.argsort(ratio)[:5]) == set(worst[:5])
    assert modes.residual[modes.valid][worst].max() < 1e-12


def test_backends_agree_on_dietmaier():
    found = {}
    for backend in BACKENDS:
        modes = parakin.load("stewart", backend=backend).forward_pose_all(DIETMAIER_LENGTHS)
        poses = modes.poses[modes.valid]
        found[backend] = poses[np.lexsort(np.round(poses.reshape(-1, 16), 6).T[::-1])]
    assert found["numpy"].shape == found["compiled"].shape == (40, 4, 4)
    assert np.abs(found["numpy"] - found["compiled"]).max() < 1e-9


def random_design(rng: np.random.Generator) -> dict[str, Any]:
    return {"base": rng.uniform(-1, 1, (6, 3)).tolist(), "platform": rng.uniform(-0.6, 0.6, (6, 3)).tolist()}


def random_pose(rng: np.random.Generator) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = euler_zyx_to_rotation(*rng.uniform(-1.2, 1.2, 3))
    pose[:3, 3] = rng.uniform(-0.5, 0.5, 3) + [0, 0, 1.0]
    return pose


def check_random_geometries(count: int, backend: str, seed: int) -> int:
    rng = np.random.default_rng(seed)
    checked = 0
    for _ in range(count):
        m = parakin.load("stewart", backend=backend, **random_design(rng))
        pose = random_pose(rng)
        lengths = m.inverse_pose(pose).actuated[0]
        modes = m.forward_pose_all(lengths)
        certificate = modes.certificate()
        assert certificate["roots"] == 40  # every path accounted for
        assert 1 <= modes.count <= 40
        poses = modes.poses[modes.valid]
        assert np.abs(poses - pose).max(axis=(-2, -1)).min() < 1e-8, "the generating pose was not found"
        base, platform = geometry(m)
        assert np.abs(leg_lengths(base, platform, poses) - lengths).max() < 1e-9
        checked += 1
    return checked


@pytest.mark.parametrize("backend", BACKENDS)
def test_random_geometries_find_the_generating_pose(backend):
    count = 40 if backend == "compiled" else 10
    assert check_random_geometries(count, backend, seed=11) == count


@pytest.mark.slow
def test_a_thousand_random_geometries():
    assert check_random_geometries(1000, "compiled", seed=12) == 1000


def multi_start(base: np.ndarray, platform: np.ndarray, lengths: np.ndarray, starts: int, rng) -> np.ndarray:
    """An independent search: least squares on (p, rotation vector) from random starts."""
    from scipy.spatial.transform import Rotation

    found: list[np.ndarray] = []

    def residual(x: np.ndarray) -> np.ndarray:
        rotation = Rotation.from_rotvec(x[3:]).as_matrix()
        return np.linalg.norm(platform @ rotation.T + x[:3] - base, axis=1) - lengths

    for _ in range(starts):
        start = np.concatenate([rng.uniform(-2, 2, 3), Rotation.random(random_state=rng.integers(1 << 31)).as_rotvec()])
        fit = least_squares(residual, start, xtol=1e-15, ftol=1e-15, gtol=1e-15)
        if np.abs(fit.fun).max() < 1e-10:
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = Rotation.from_rotvec(fit.x[3:]).as_matrix(), fit.x[:3]
            if all(np.abs(pose - other).max() > 1e-6 for other in found):
                found.append(pose)
    return np.array(found).reshape(-1, 4, 4)


def test_no_mode_missing_against_multi_start():
    """Every mode a 400-start least-squares search finds on Dietmaier's data and on random
    geometries is among ours."""
    rng = np.random.default_rng(5)
    checked = 0
    for design in [None] + [random_design(rng) for _ in range(2)]:
        m = parakin.load("stewart", backend="compiled", **(design or {}))
        base, platform = geometry(m)
        lengths = np.array(DIETMAIER_LENGTHS) if design is None else m.inverse_pose(random_pose(rng)).actuated[0]
        modes = m.forward_pose_all(lengths)
        ours = modes.poses[modes.valid]
        for pose in multi_start(base, platform, lengths, 400 if design is None else 150, rng):
            assert np.abs(ours - pose).max(axis=(-2, -1)).min() < 1e-7
            checked += 1
    assert checked >= 20


def test_planar_base_and_platform_give_mirror_pairs():
    """Base and platform in z = 0: the reflection z -> -z of a mode through the base plane is a
    mode (R -> S R S, p -> S p with S = diag(1, 1, -1))."""
    rng = np.random.default_rng(3)
    base = np.c_[rng.uniform(-1, 1, (6, 2)), np.zeros(6)]
    platform = np.c_[rng.uniform(-0.5, 0.5, (6, 2)), np.zeros(6)]
    m = parakin.load("stewart", base=base.tolist(), platform=platform.tolist())
    pose = random_pose(rng)
    modes = m.forward_pose_all(m.inverse_pose(pose).actuated[0])
    poses = modes.poses[modes.valid]
    assert modes.count >= 2 and modes.count % 2 == 0
    mirror = np.diag([1.0, 1.0, -1.0, 1.0])
    for mode in poses:
        assert np.abs(poses - mirror @ mode @ mirror).max(axis=(-2, -1)).min() < 1e-8


def test_architecturally_singular_design_is_answered():
    """Kong and Gosselin's section 5.4 design (base on a conic, platform a linear image of it)
    has a self-motion: no path reaches an isolated solution; strict raises SelfMotionError with
    the traced solution set (whose poses close every leg), otherwise the input is degenerate."""
    base = [[0, 0, 0], [5, -5, 0], [9, -3, 0], [10, 0, 0], [9, 3, 0], [5, 5, 0]]
    platform = [[x + y, y, 0] for x, y, _ in base]
    m = parakin.load("stewart", base=base, platform=platform)
    pose = np.eye(4)
    pose[:3, 3] = [0.5, 0.2, 30.0]
    lengths = m.inverse_pose(pose).actuated[0]
    modes = m.forward_pose_all(lengths, strict=False)
    assert modes.count == 0 and modes.status == m.manifest.abi.code("input_status", "degenerate")
    assert modes.certificate()["roots"] == 40
    with pytest.raises(SelfMotionError) as raised:
        m.forward_pose_all(lengths)
    motion = raised.value.solution_set
    assert motion.count >= 10
    poses = m.platform_pose(lengths, motion.passive)
    assert np.abs(leg_lengths(np.array(base, float), np.array(platform, float), poses) - lengths).max() < 1e-8


def test_coincident_points_are_answered():
    # base points 1 and 2 coincide
    base = np.array([[0, 0, 0], [0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.2], [0.3, 0.5, 0.4]])
    platform = np.array([[0, 0, 0], [0.4, 0, 0], [0.2, 0.3, 0], [0.1, -0.2, 0.3], [-0.3, 0.1, 0.1], [0.2, 0.2, -0.2]])
    m = parakin.load("stewart", base=base.tolist(), platform=platform.tolist())
    pose = random_pose(np.random.default_rng(8))
    lengths = m.inverse_pose(pose).actuated[0]
    modes = m.forward_pose_all(lengths, strict=False)
    assert modes.certificate()["roots"] == 40
    poses = modes.poses[modes.valid]
    assert np.abs(poses - pose).max(axis=(-2, -1)).min() < 1e-8


@pytest.mark.parametrize("backend", BACKENDS)
def test_newton_has_no_parametrisation_singularity(backend):
    """At beta = pi/2 (where Z-Y-X Euler angles are singular) the quaternion Newton converges."""
    m = parakin.load("stewart", backend=backend)
    pose = np.eye(4)
    pose[:3, :3] = euler_zyx_to_rotation(0.3, np.pi / 2, -0.2)
    pose[:3, 3] = DIETMAIER_POSITION
    lengths = m.inverse_pose(pose).actuated[0]
    guess = pose.copy()
    guess[:3, :3] = euler_zyx_to_rotation(0.33, np.pi / 2 - 0.02, -0.18)
    solved = m.forward_pose(lengths, guess=guess)
    assert np.abs(solved.pose - pose).max() < 1e-10
    assert abs(np.linalg.norm(solved.passive[3:]) - 1) < 1e-12


#: a random design (from a 10^4-input run) where one path from the first start system fails
#: (it passes too close to another) and that path led to the generating pose
RETRY_BASE = [
    [0.3189328944592347, -0.9917640447622387, -0.12598230756944884],
    [0.3778243172794582, -0.6932828095540053, 0.6574105077861447],
    [-0.08224856651227008, -0.14008650804802159, 0.8224340999123212],
    [0.2953504325512857, -0.890366257737589, -0.786013850851208],
    [-0.9876627315564048, -0.7663007261631012, -0.15113626549875891],
    [0.9639778259681415, -0.18156707852749654, -0.3798301962510704],
]
RETRY_PLATFORM = [
    [0.07361472916691147, -0.1959300942260389, 0.011166120237766974],
    [-0.19658840693064594, 0.5708121759488808, -0.20984086392954465],
    [0.5780119369089, -0.09028052064418124, -0.22464255922299303],
    [-0.11200457979314543, 0.49443683941454164, 0.060933545448675686],
    [-0.2649859993333678, 0.5853036163206605, 0.5183993751111672],
    [-0.003909924066180515, -0.031062398029702454, 0.4796216086237378],
]
RETRY_POSE = [
    [0.4000300375630557, -0.36686486886798125, 0.8398726909703513, -0.053722421968423806],
    [-0.19981130769172925, 0.8594357859973223, 0.4705800368329344, 0.4512814033711289],
    [-0.8944559298063943, -0.3560622104880604, 0.27049638056087705, 1.226413989452997],
    [0.0, 0.0, 0.0, 1.0],
]


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_failed_path_is_recovered_from_the_second_start_system(backend):
    """A path of the first start system that fails (here: marked failed after the run, the way
    the tracker marks a path it cannot follow) is recovered from the second start system, along
    another segment: its slot gets the very root the first run had reached, and no other."""
    from parakin.solvers.modes import _path_table, _retry_failed
    from parakin.solvers.path_tracking import PATH_FAILED, PATH_REACHED, Paths, sparse_system, track

    m = parakin.load("stewart", backend=backend, base=RETRY_BASE, platform=RETRY_PLATFORM)
    lengths = m.inverse_pose(np.array(RETRY_POSE)).actuated[0]
    info = m.capabilities.forward
    homotopy = info.homotopy
    table = _path_table(m, info, lengths[None], 0)
    system = sparse_system(table, homotopy.exponents, homotopy.equation, homotopy.start.shape[0])
    first = track(system, homotopy.start)
    assert (first.status == PATH_REACHED).all()
    lost = [3, 17]
    status = first.status.copy()
    status[lost] = PATH_FAILED
    z = first.z.copy()
    z[lost] = np.nan
    retried = _retry_failed(m, lengths[None], Paths(z, status, first.steps, first.update), 1e-7, info)
    assert (retried.status == PATH_REACHED).all()
    # the lost roots come back, in some order, to tracking accuracy
    for k in lost:
        assert np.abs(retried.z[lost] - first.z[k]).max(-1).min() < 1e-7
    modes = m.forward_pose_all(lengths)
    assert modes.certificate()["rejected"]["path_failed"] == 0
    assert np.abs(modes.poses[modes.valid] - np.array(RETRY_POSE)).max(axis=(-2, -1)).min() < 1e-8
