"""A lower-mobility inverse validates reachability (issue 31, item 5).

A user's 3-RPS (``tests/fixtures/rps3.py``: R-P-S legs whose base revolute joints keep each leg in
a plane) written with the documented keyword ``prismatic_leg(..., revolute_axis=u)`` and
generated with ``parakin generate``: the poses of its assembly modes (on the reachable set by
construction) are valid and give back their leg lengths, and the same poses moved 5 cm off the
set, or turned about the vertical, are invalid on every branch with the failing plane constraint
named (``leg<i>_plane_reachable``), at 1 m and at 1 mm scale alike. Before, every branch of such
a pose was valid, with leg lengths whose configuration does not close (plane rows +-0.043 m).
The 3-RRS (``tests/fixtures/rrs3.py``, ``crank_leg(..., revolute_axis=u)``) is checked on the
model's own inverse here, and as a generated package with --run-slow (its first root-count proof
takes about two minutes).
"""

from __future__ import annotations

import importlib.util
import itertools
import math
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
import sympy as sp
from parakin.generator import joints
from parakin.generator.model import POSE_POSITION, POSE_ROTATION
from scipy.spatial.transform import Rotation

import parakin
from parakin.errors import UnreachablePoseError

FIXTURES = Path(__file__).parent / "fixtures"
#: how far off the reachable set the moved poses are (metres at the default scale)
OFF = 0.05


def fixture(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(f"fixture_{name}", FIXTURES / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def generate(name: str, folder: Path) -> Path:
    """``parakin generate tests/fixtures/NAME.py --out FOLDER`` as a user runs it."""
    done = subprocess.run(
        [sys.executable, "-m", "parakin", "generate", str(FIXTURES / f"{name}.py"), "--out", str(folder)],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert done.returncode == 0, done.stderr
    return folder


@pytest.fixture(scope="module")
def rps3(tmp_path_factory) -> Path:
    return generate("rps3", tmp_path_factory.mktemp("rps3") / "package")


def reachable_poses(
    m: parakin.Mechanism, spread: float, count: int, seed: int, scale: float = 1.0
) -> list[tuple[np.ndarray, np.ndarray]]:
    """(actuated, pose) of every assembly mode of ``count`` inputs drawn around the home (its
    lengths times ``scale``)."""
    home = np.array([v.home for v in m.manifest.actuated]) * scale
    rng = np.random.default_rng(seed)
    found = []
    for _ in range(count):
        actuated = home + spread * rng.uniform(-1, 1, home.size)
        modes = m.forward_pose_all(actuated)
        found += [(actuated, modes.mode(k).pose) for k in range(int(modes.count))]
    return found


def moved(pose: np.ndarray, how: str, scale: float) -> np.ndarray:
    """The pose moved off the 3-RPS's reachable set: along x or y by OFF (times ``scale``), or
    turned about the vertical (a torsion the three planes forbid)."""
    result = pose.copy()
    if how == "turn":
        c, s = math.cos(0.2), math.sin(0.2)
        result[:3, :3] = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ pose[:3, :3]
    else:
        result["xy".index(how), 3] += OFF * scale
    return result


def plane_offsets(pose: np.ndarray, scale: float) -> np.ndarray:
    """(C_i - A_i) . u_i of the fixture 3-RPS (r_b = 0.2, r_p = 0.1 times ``scale``; legs at 0, 120,
    240 deg), computed here."""
    angles = np.radians([0.0, 120.0, 240.0])
    radial = np.stack([np.cos(angles), np.sin(angles), np.zeros(3)], 1)
    tangent = np.stack([-np.sin(angles), np.cos(angles), np.zeros(3)], 1)
    joints_at = pose[:3, 3] + (0.1 * scale * radial) @ pose[:3, :3].T
    return ((joints_at - 0.2 * scale * radial) * tangent).sum(-1)


def check(m: parakin.Mechanism, scale: float) -> int:
    """Every mode's pose valid and round-tripping; the same poses moved off the set invalid on
    every branch, each with a plane condition failing on every branch. Returns the poses checked."""
    checked = 0
    for actuated, pose in reachable_poses(m, 0.02 * scale, 6, seed=3, scale=scale):
        ik = m.inverse_pose(pose, strict=False)
        back = ik.valid & (np.abs(ik.actuated - actuated).max(-1) < 1e-9 * scale)
        assert back.any(), f"a mode of {actuated} is not given back: {ik.failures}"
        branch = int(np.flatnonzero(back)[0])
        closure = m.loop_closure(ik.actuated[branch], ik.passive[branch])["residual"]
        assert np.abs(closure).max() < 1e-12 * scale
        for how in ("x", "y", "turn"):
            off = m.inverse_pose(moved(pose, how, scale), strict=False)
            assert not off.valid.any(), (how, off.failures)
            planes = [name for name in off.failures if name.endswith("_plane_reachable") and off.failures[name].all()]
            assert planes, f"{how}: no plane condition fails on every branch: {off.failures}"
            # the legs it names are out of their planes at the given pose (this test's geometry,
            # beyond the tolerance relative to legs of at least r_b = 0.2 m), the farthest by about the move
            rows = np.abs(plane_offsets(moved(pose, how, scale), scale))
            assert all(rows[int(name[3]) - 1] > joints.PLANE_TOLERANCE * 0.2 * scale for name in planes)
            assert rows.max() > 0.2 * OFF * scale
            # and its values are the pose read onto the reachable set: a configuration that closes,
            # with the given pose's height and tilt R^T k, its joints in their planes
            read = m.platform_pose(off.actuated[0], off.passive[0])
            assert np.abs(m.loop_closure(off.actuated[0], off.passive[0])["residual"]).max() < 1e-12 * scale
            assert abs(read[2, 3] - pose[2, 3]) < 1e-12 * scale
            assert np.abs(read[2, :3] - moved(pose, how, scale)[2, :3]).max() < 1e-12
            assert np.abs(plane_offsets(read, scale)).max() < 1e-12 * scale
            with pytest.raises(UnreachablePoseError, match="plane_reachable"):
                m.inverse_pose(moved(pose, how, scale))
        checked += 1
    return checked


def test_rps3_poses_on_the_reachable_set_are_valid_and_off_it_invalid(rps3):
    m = parakin.load(rps3)
    assert [n for n in m.capabilities.inverse.validity if n.endswith("plane_reachable")] == [
        f"leg{k}_plane_reachable" for k in (1, 2, 3)
    ]
    assert check(m, 1.0) >= 6


def test_rps3_at_millimetre_scale_decides_the_same(rps3):
    """The tolerance is relative to the legs' size: the same mechanism 1000 times smaller (poses
    5e-5 m off the set) decides every pose as at 1 m."""
    scale = 1e-3
    limits = {f"l{k}": (0.05 * scale, 1.0 * scale) for k in (1, 2, 3)}
    m = parakin.load(rps3, r_b=0.2 * scale, r_p=0.1 * scale, limits=limits)
    pose = np.eye(4)
    pose[2, 3] = 0.3 * scale
    assert m.inverse_pose(pose).valid[0]
    assert check(m, scale) >= 6


def test_rps3_the_home_pose_round_trips_with_every_plane_measure_one(rps3):
    m = parakin.load(rps3, backend="numpy")
    pose = np.eye(4)
    pose[2, 3] = 0.3
    ik = m.inverse_pose(pose)
    assert ik.valid[0] and np.allclose(ik.actuated[0], math.sqrt(0.1**2 + 0.3**2), atol=1e-15)


def numeric_inverse(model: joints.DistanceMechanism, values: dict):
    """The model's inverse as a function (rotation, position, branch) -> every symbol."""
    inverse = model.inverse()

    def run(rotation: np.ndarray, position: np.ndarray, branch: tuple[int, ...]) -> dict:
        known: dict = {k: sp.Float(v, 30) for k, v in values.items()}
        known.update({POSE_ROTATION[i, j]: sp.Float(rotation[i, j], 30) for i in range(3) for j in range(3)})
        known.update({s: sp.Float(v, 30) for s, v in zip(POSE_POSITION, position, strict=True)})
        known.update({s: sp.Integer(v) for s, v in zip(inverse.branches, branch, strict=True)})
        for target, expression in inverse.steps:
            known[target] = sp.N(expression.xreplace(known), 30)
        known["validity"] = {n: float(sp.N(v.xreplace(known), 30)) for n, v in inverse.validity.items()}
        return known

    return run


def test_rrs3_inverse_checks_its_planes_and_gives_angles_in_range():
    """The 3-RRS model (crank legs with a revolute axis parallel to the crank's): the level home
    is valid on every branch, with crank angles in (-pi, pi]; the pose moved 5 cm along y fails
    leg 1's plane, turned about the vertical every leg's."""
    module = fixture("rrs3")
    model, values = module.MODEL, module.DEFAULTS
    run = numeric_inverse(model, values)
    assert [n for n in model.inverse().validity if "plane" in n] == [f"leg{k}_plane_reachable" for k in (1, 2, 3)]
    home = np.array([0.0, 0.0, module.HOME_HEIGHT])
    branches = list(itertools.product((1, -1), repeat=3))
    for branch in branches:
        result = run(np.eye(3), home, branch)
        assert all(v > 0 for v in result["validity"].values())
        assert all(-math.pi < float(result[a]) <= math.pi for a in module.angles)
    moved_pose = run(np.eye(3), home + np.array([0.0, OFF, 0.0]), branches[0])
    assert moved_pose["validity"]["leg1_plane_reachable"] < 0
    c, s = math.cos(0.2), math.sin(0.2)
    turned = run(np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]), home, branches[0])
    assert all(turned["validity"][f"leg{k}_plane_reachable"] < 0 for k in (1, 2, 3))


def test_legs_take_a_revolute_axis_as_a_documented_keyword():
    """issue 32: ``prismatic_leg`` and ``crank_leg`` take ``revolute_axis`` (they used to raise
    "unexpected keyword argument"); a crank's must be parallel to its axis (the link's plane is
    then fixed), and either direction names the same plane."""
    theta, length = sp.Symbol("theta"), sp.Symbol("l")
    leg = joints.prismatic_leg([0.2, 0, 0], [0.1, 0, 0], length, revolute_axis=[0, 1, 0])
    assert leg.plane_normal == sp.Matrix([0, 1, 0])
    crank = joints.crank_leg([0.2, 0, 0], [0, 1, 0], [1, 0, 0], 0.1, 0.3, [0.1, 0, 0], theta, revolute_axis=[0, -1, 0])
    assert crank.plane_normal == sp.Matrix([0, 1, 0])
    with pytest.raises(ValueError, match="must be parallel to the crank's axis"):
        joints.crank_leg([0, 0, 0], [0, 1, 0], [1, 0, 0], 0.1, 0.3, [0, 0, 0], theta, revolute_axis=[0, 0, 1])
    with pytest.raises(ValueError, match="revolute joint's axis must be a unit vector"):
        joints.prismatic_leg([0, 0, 0], [0, 0, 0], length, revolute_axis=[0, 2, 0])


def test_prs3_declares_an_off_set_pose_valid_and_the_others_invalid():
    """The generator derives the same reading for prs3, rps3 and rrs3 (their three planes contain
    the vertical axis, and the turn about it is 0 or a half-turn at every tilt); prs3 declares
    ``unreachable="read"`` (its documented convention: no plane measure), the others check the
    given pose's planes. Each names its controlled coordinates in its joint graph."""
    from parakin.mechanisms import prs3

    models = {"prs3": prs3.MODEL, "rps3": fixture("rps3").MODEL, "rrs3": fixture("rrs3").MODEL}
    for name, model in models.items():
        assert model.reading is not None and model.reading.symmetric, name
        assert list(model.reading.axis) == [0, 0, 1], name
        assert model.graph.controlled is not None and "height p . k and the tilt n = R^T k" in model.graph.controlled
        planes = [n for n in model.inverse().validity if "plane" in n]
        assert planes == ([] if name == "prs3" else [f"leg{k}_plane_reachable" for k in (1, 2, 3)]), name
    with pytest.raises(ValueError, match="unreachable='read' needs a reading"):
        legs = [joints.prismatic_leg([k, 0, 0], [0, 0, 0], sp.Symbol(f"l{k}")) for k in range(3)]
        joints.DistanceMechanism(joints.platform("translation"), legs, unreachable="read")


def test_the_derived_reading_returns_a_reachable_pose_with_the_given_height_and_tilt():
    """The 3-RRS fixture's reading at 12 random poses (any rotation, any position; 30 digits): the
    pose it returns keeps every platform joint in its leg's plane (this test's geometry, 1e-15 m),
    has the given pose's height and tilt R^T k, is a rotation whose quaternion (q0 >= 0) is the
    one returned (1e-14: the input rotation's own rounding), and is the given pose itself where that was reachable (its own output, read
    again, 1e-12: the round to double precision, amplified at tilts near upside down)."""
    module = fixture("rrs3")
    run = numeric_inverse(module.MODEL, module.DEFAULTS)
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(12):
        rotation = Rotation.random(random_state=rng.integers(1 << 30)).as_matrix()
        if rng.uniform() < 0.5:  # and tilts below 90 deg
            rotation = Rotation.from_rotvec(rng.normal(scale=0.5, size=3)).as_matrix()
        position = np.array([*rng.normal(scale=0.05, size=2), rng.uniform(0.1, 0.4)])
        values = run(rotation, position, (1, 1, 1))
        read, p = read_pose(values)
        assert abs(p[2] - position[2]) < 1e-25
        assert np.abs(np.array(read.T * sp.Matrix([0, 0, 1]), dtype=float).ravel() - rotation[2]).max() < 1e-14
        assert float((read.T * read - sp.eye(3)).norm()) < 1e-14  # the input's own rounding
        offsets = rrs3_plane_offsets(read, p)
        assert max(abs(o) for o in offsets) < 1e-15
        q = [values[sp.Symbol(f"q{k}", real=True)] for k in range(4)]
        assert q[0] >= 0 and float((quaternion_matrix(q) - read).norm()) < 1e-14
        again = run(np.array(read, dtype=float), np.array(p, dtype=float), (1, 1, 1))
        assert float((read_pose(again)[0] - read).norm()) < 1e-12 and float((read_pose(again)[1] - p).norm()) < 1e-12
        checked += 1
    assert checked == 12


def read_pose(values: dict) -> tuple[sp.Matrix, sp.Matrix]:
    """The rotation and position the reading returned (its quaternion and x, y, z)."""
    q = [values[sp.Symbol(f"q{k}", real=True)] for k in range(4)]
    p = sp.Matrix([values[sp.Symbol(c, real=True)] for c in "xyz"])
    return quaternion_matrix(q), p


def quaternion_matrix(q: list) -> sp.Matrix:
    """R of a unit quaternion (scalar first), written here."""
    w, x, y, z = q
    return sp.Matrix(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def rrs3_plane_offsets(rotation: sp.Matrix, position: sp.Matrix) -> list:
    """(C_i - A_i) . u_i of the fixture 3-RRS (r_b = 0.2, r_p = 0.1, legs at 0, 120, 240 deg)."""
    out = []
    for angle in (0, 2 * sp.pi / 3, 4 * sp.pi / 3):
        e = sp.Matrix([sp.cos(angle), sp.sin(angle), 0])
        u = sp.Matrix([-sp.sin(angle), sp.cos(angle), 0])
        out.append(float(sp.N((position + rotation * (sp.Rational(1, 10) * e) - sp.Rational(1, 5) * e).dot(u), 30)))
    return out


@pytest.mark.slow
def test_rrs3_generated_poses_on_and_off_the_reachable_set(tmp_path):
    """The 3-RRS as a package: every mode's pose of inputs around the home valid and giving
    back its crank angles (in (-pi, pi]), the same poses 5 cm off the set invalid with a plane named."""
    m = parakin.load(generate("rrs3", tmp_path / "package"))
    checked = 0
    for actuated, pose in reachable_poses(m, 0.1, 6, seed=5):
        ik = m.inverse_pose(pose, strict=False)
        difference = np.abs(np.remainder(ik.actuated - actuated + np.pi, 2 * np.pi) - np.pi)
        assert (ik.valid & (difference.max(-1) < 1e-9)).any()
        for how in ("x", "y", "turn"):
            off = m.inverse_pose(moved(pose, how, 1.0), strict=False)
            assert not off.valid.any()
            assert any(name.endswith("_plane_reachable") and mask.all() for name, mask in off.failures.items())
        checked += 1
    assert checked >= 6


#: an asymmetric 3-RPS made up here: legs at 0, 120, 240 deg (r_b = 0.2 m), platform joints at
#: other angles and radii, so that the turn that keeps the joints in their planes varies with the tilt
ASYMMETRIC = {
    "angles": (0.0, 2 * math.pi / 3, 4 * math.pi / 3),
    "offsets": (0.4, -0.2, 1 / 3),
    "radii": (0.1, 0.12, 0.08),
}


def asymmetric_geometry() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A_i, u_i, c_i) of ASYMMETRIC, one row per leg, in NumPy."""
    theta = np.array(ASYMMETRIC["angles"])
    twist = theta + np.array(ASYMMETRIC["offsets"])
    bases = 0.2 * np.stack([np.cos(theta), np.sin(theta), np.zeros(3)], 1)
    normals = np.stack([-np.sin(theta), np.cos(theta), np.zeros(3)], 1)
    platform_joints = np.array(ASYMMETRIC["radii"])[:, None] * np.stack([np.cos(twist), np.sin(twist), np.zeros(3)], 1)
    return bases, normals, platform_joints


def test_an_asymmetric_design_reads_the_turn_its_planes_force():
    """The asymmetric 3-RPS: the reading is derived (not the symmetric case), and at 16 random
    poses it returns a pose in the planes (this test's geometry, 1e-15 m) with the given height and
    tilt; a reachable pose found independently (scipy's least squares on the three plane equations
    in x, y and a turn about the vertical from the given pose) reads as itself (1e-12), the two
    turns half a turn apart both occurring."""
    from scipy.optimize import least_squares

    bases, normals, platform_joints = asymmetric_geometry()
    lengths = sp.symbols("l1:4", positive=True)
    legs = [
        joints.prismatic_leg(sp.Matrix(a), sp.Matrix(c), length, revolute_axis=sp.Matrix(u))
        for a, u, c, length in zip(bases, normals, platform_joints, lengths, strict=True)
    ]
    model = joints.DistanceMechanism(joints.platform("transform"), legs)
    assert model.reading is not None and not model.reading.symmetric
    assert "the turn about k, which the tilt fixes up to a half-turn: two separate sets" in model.reading.describe()
    run = numeric_inverse(model, {})

    def offsets(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
        return ((position + platform_joints @ rotation.T - bases) * normals).sum(-1)

    def turned(angle: float) -> np.ndarray:
        return Rotation.from_rotvec([0.0, 0.0, angle]).as_matrix()

    rng = np.random.default_rng(12)
    turns, checked = set(), 0
    for _ in range(16):
        rotation = Rotation.from_rotvec(rng.normal(scale=0.5, size=3)).as_matrix()
        position = np.array([*rng.normal(scale=0.05, size=2), rng.uniform(0.1, 0.4)])
        read, p = (np.array(v, dtype=float) for v in read_pose(run(rotation, position, ())))
        assert np.abs(offsets(read, p.ravel())).max() < 1e-15
        assert abs(p[2, 0] - position[2]) < 1e-15 and np.abs(read[2] - rotation[2]).max() < 1e-14
        start = float(rng.uniform(-np.pi, np.pi))

        def planes(unknowns: np.ndarray, rotation: np.ndarray = rotation, height: float = position[2]) -> np.ndarray:
            return offsets(turned(unknowns[2]) @ rotation, np.array([unknowns[0], unknowns[1], height]))

        x, y, angle = least_squares(planes, [0.0, 0.0, start], xtol=1e-15, ftol=1e-15, gtol=1e-15).x
        reachable = turned(angle) @ rotation
        assert np.abs(planes(np.array([x, y, angle]))).max() < 1e-14
        again, q = (np.array(v, dtype=float) for v in read_pose(run(reachable, np.array([x, y, position[2]]), ())))
        assert np.abs(again - reachable).max() < 1e-12 and np.abs(q.ravel() - [x, y, position[2]]).max() < 1e-12
        turns.add(int(np.sign(np.trace(reachable @ read.T) - 1 + 1e-9)))  # the same turn or half a turn apart
        checked += 1
    assert checked == 16 and turns == {-1, 1}


@pytest.mark.parametrize(("name", "stretch"), [("prs3", 1.0), ("rps3", 1.5)])
def test_the_motion_text_says_the_turn_is_none_or_a_half_turn_and_it_is(name, stretch):
    """``parakin inspect prs3`` once said "(two turns, half a turn apart)", which a new user could
    not read. The text now says what it means: the turn about k is none (a pure tilt) or a
    half-turn, two separate sets of reachable poses. Checked here: every assembly mode at the home
    and at three inputs around it, decomposed independently as R = Rot_k(psi) R0 (R0 the pure tilt
    taking n = R^T k to k, Rodrigues), has psi = 0 or pi (1e-9 rad), and both occur (the 3-RPS
    at 1.5 times its home leg lengths: at the home only psi = 0 is reached, the legs too short for
    the half-turn)."""
    m = parakin.load(name, backend="numpy")
    text = m.manifest.joints.motion.text
    assert "two turns, half a turn apart" not in text
    assert (
        "the turn about k, none (the platform only tilts) or a half-turn: two separate sets of reachable poses" in text
    )
    k = np.array([0.0, 0.0, 1.0])
    assert "k = (0, 0, 1)" in text

    def skew(v: np.ndarray) -> np.ndarray:
        return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

    rng = np.random.default_rng(1)
    home = stretch * m.home_actuated
    turns, checked = set(), 0
    for actuated in [home, *(home + 0.02 * rng.uniform(-1, 1, home.size) for _ in range(3))]:
        for mode in m.forward_pose_all(actuated):
            n = mode.rotation.T @ k
            v = np.cross(n, k)
            tilt = np.eye(3) + skew(v) + skew(v) @ skew(v) / (1 + n @ k)
            turn = mode.rotation @ tilt.T  # Rot_k(psi)
            assert np.abs(turn[:, 2] - k).max() < 1e-12
            psi = math.atan2(turn[1, 0], turn[0, 0])
            assert min(abs(psi), abs(abs(psi) - math.pi)) < 1e-9, f"{name}: turn {psi} rad about k"
            turns.add(abs(psi) > 1)
            checked += 1
    assert checked >= 8 and turns == {False, True}
