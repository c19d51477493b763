"""A leg no closed form matches, solved numerically (issue 32 item 2: the per-leg fallback).

The fixture ``tests/fixtures/rrs3_skew.py`` is a 3-RRS whose elbow axes are turned out of
parallel with the crank axes: each link stays normal to an axis that turns with its crank, two
equations in the crank angle that match none of the generator's subproblems. Before, such a chain
written joint by joint was taken for a plane leg (the elbow axis frozen at the crank's zero, a
wrong closure); now its closure turns with the crank and its inverse is Gauss-Newton on the leg's
own closure from the middle of its limits, validated by the residual (``leg<i>_numeric_reachable``).

The references are this file's NumPy geometry of the fixture: C = p + R c, E = A + r_c (cos t k +
sin t (u x k)), h(t) = Rot_u(t) h0; a configuration closes where |C - E| = L and (C - E) . h = 0.
"""

from __future__ import annotations

import functools
import importlib.util
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from parakin.generator.model import POSE_POSITION, POSE_ROTATION, InverseSolution
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

FIXTURE = Path(__file__).parent / "fixtures" / "rrs3_skew.py"


@pytest.fixture(scope="module")
def skew():
    spec = importlib.util.spec_from_file_location("fixture_rrs3_skew", FIXTURE)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def geometry(skew) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(A_i, u_i, h0_i, c_i), one row per leg, from the fixture's numbers."""
    t = 2 * np.pi * np.arange(3) / 3
    e = np.stack([np.cos(t), np.sin(t), np.zeros(3)], 1)
    u = np.stack([-np.sin(t), np.cos(t), np.zeros(3)], 1)
    d = (skew.R_P - skew.R_B) * e + [0.0, 0.0, skew.HOME_HEIGHT - skew.R_C]
    w = np.cross(d, u) / np.linalg.norm(d, axis=1)[:, None]
    h = np.cos(skew.BETA) * u + np.sin(skew.BETA) * w
    return skew.R_B * e, u, h, skew.R_P * e


def rotate(axis: np.ndarray, angle: float, vector: np.ndarray) -> np.ndarray:
    return Rotation.from_rotvec(angle * axis).apply(vector)


def residuals(skew, crank: np.ndarray, rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    """|C - E| - L and (C - E) . h per leg, this file's geometry."""
    bases, axes, elbow_axes, joints = geometry(skew)
    out = []
    for a, u, h, c, t in zip(bases, axes, elbow_axes, joints, crank, strict=True):
        elbow = a + skew.R_C * (np.cos(t) * np.array([0.0, 0.0, 1.0]) + np.sin(t) * np.cross(u, [0.0, 0.0, 1.0]))
        d = position + rotation @ c - elbow
        out += [np.linalg.norm(d) - skew.LINK, d @ rotate(u, t, h)]
    return np.array(out)


def reachable_pose(skew, crank: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The pose near the home that closes with these crank angles (least squares, this file)."""

    def equations(x: np.ndarray) -> np.ndarray:
        return residuals(skew, crank, Rotation.from_rotvec(x[:3]).as_matrix(), x[3:])

    found = least_squares(equations, [0, 0, 0, 0, 0, skew.HOME_HEIGHT], xtol=1e-15, ftol=1e-15, gtol=1e-15)
    rotation, position = Rotation.from_rotvec(found.x[:3]).as_matrix(), found.x[3:]
    assert np.abs(residuals(skew, crank, rotation, position)).max() < 1e-13
    return rotation, position


@functools.cache
def program(skew) -> InverseSolution:
    """The fixture model's inverse (built once: 13 Newton steps per leg take seconds of SymPy)."""
    return skew.MODEL.inverse()


def inverse(skew, rotation: np.ndarray, position: np.ndarray) -> dict:
    """The model's inverse program evaluated step by step (17 digits)."""
    solution = program(skew)
    known: dict = {k: sp.Float(v, 17) for k, v in skew.DEFAULTS.items()}
    known.update({POSE_ROTATION[i, j]: sp.Float(rotation[i, j], 17) for i in range(3) for j in range(3)})
    known.update({s: sp.Float(v, 17) for s, v in zip(POSE_POSITION, position, strict=True)})
    for target, expression in solution.steps:
        known[target] = sp.N(expression.xreplace(known), 17)
    known["validity"] = {n: float(sp.N(v.xreplace(known), 17)) for n, v in solution.validity.items()}
    return known


def test_the_skew_leg_is_solved_numerically_and_closes(skew):
    """At 2 crank triples (up to 0.3 rad from the home) and the pose that closes with them (this
    file's least squares): the inverse gives the crank angles back (1e-10 rad), every
    ``leg<i>_numeric_reachable`` positive, and this file's closure at the computed angles is met
    (1e-12 m); the model's own closure vanishes there too (its turning rows, not a frozen plane)."""
    model = skew.MODEL
    assert model.turning == [0, 1, 2] and model.branch_names == []
    assert list(program(skew).validity) == [f"leg{k}_numeric_reachable" for k in (1, 2, 3)]
    closure = model.closure().residual.xreplace({k: sp.Float(v) for k, v in skew.DEFAULTS.items()})
    rng = np.random.default_rng(21)
    checked = 0
    for _ in range(2):
        crank = rng.uniform(-0.3, 0.3, 3)
        rotation, position = reachable_pose(skew, crank)
        found = inverse(skew, rotation, position)
        computed = np.array([float(found[a]) for a in skew.angles])
        assert np.abs(computed - crank).max() < 1e-10
        assert all(v > 0 for v in found["validity"].values())
        assert np.abs(residuals(skew, computed, rotation, position)).max() < 1e-12
        quaternion = Rotation.from_matrix(rotation).as_quat()  # (x, y, z, w)
        state = dict(zip(skew.angles, computed, strict=True))
        state.update(zip(sp.symbols("x y z", real=True), position, strict=True))
        state.update(zip(sp.symbols("q0:4", real=True), [quaternion[3], *quaternion[:3]], strict=True))
        assert max(abs(float(r.xreplace(state))) for r in closure) < 1e-12
        checked += 1
    assert checked == 2


def test_a_pose_off_the_legs_reach_names_the_leg(skew):
    """The home pose moved 1 cm sideways: no crank angle closes leg 1 (this file's least squares in
    the angle leaves a residual > 1e-4 m), and its ``leg1_numeric_reachable`` is negative."""
    rotation, position = np.eye(3), np.array([0.0, 0.01, skew.HOME_HEIGHT])
    found = inverse(skew, rotation, position)
    best = least_squares(lambda t: residuals(skew, np.array([t[0], 0.0, 0.0]), rotation, position)[:2], [0.0])
    assert np.abs(best.fun).max() > 1e-4
    assert found["validity"]["leg1_numeric_reachable"] < 0


@pytest.fixture(scope="module")
def package(tmp_path_factory) -> Path:
    """``parakin generate`` of the fixture (72 s of CPU, 3 minutes on the loaded 2-core machine:
    its root count is found by monodromy and proven by two equilibrated total-degree runs), once
    for this module's slow tests."""
    import subprocess
    import sys

    folder = tmp_path_factory.mktemp("rrs3_skew") / "package"
    done = subprocess.run(
        [sys.executable, "-m", "parakin", "generate", str(FIXTURE), "--out", str(folder)],
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert done.returncode == 0, done.stderr
    return folder


@pytest.mark.slow
def test_the_generated_package_inverts_the_skew_legs(skew, package):
    """At 10 poses that close with random cranks (this file's least squares), inverse_pose in both
    backends gives the cranks back (1e-12 rad), and Newton's forward pose from the home gives the
    pose back (1e-9)."""
    import parakin

    rng = np.random.default_rng(3)
    cases = [(crank, *reachable_pose(skew, crank)) for crank in rng.uniform(-0.3, 0.3, (10, 3))]
    for backend in ("numpy", "compiled"):
        m = parakin.load(package, backend=backend)
        for crank, rotation, position in cases:
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = rotation, position
            ik = m.inverse_pose(pose)
            assert ik.valid[0] and np.abs(ik.actuated[0] - crank).max() < 1e-12
            assert np.abs(m.forward_pose(crank, guess=m.home_passive).pose - pose).max() < 1e-9


def real_poses(skew, crank: np.ndarray, starts: int, seed: int) -> list[np.ndarray]:
    """The distinct poses (4 x 4) that close with ``crank`` by this file's geometry, found by least
    squares from ``starts`` random poses (rotation uniform, position within 0.4 m): a lower
    bound on the real assembly modes, independent of parakin's solvers."""
    rng = np.random.default_rng(seed)
    found: list[np.ndarray] = []
    for _ in range(starts):
        start = np.concatenate([Rotation.random(random_state=rng).as_rotvec(), rng.uniform(-0.4, 0.4, 3)])
        fit = least_squares(
            lambda x: residuals(skew, crank, Rotation.from_rotvec(x[:3]).as_matrix(), x[3:]),
            start,
            xtol=1e-15,
            ftol=1e-15,
            gtol=1e-15,
        )
        if np.abs(fit.fun).max() < 1e-12:
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = Rotation.from_rotvec(fit.x[:3]).as_matrix(), fit.x[3:]
            if all(np.abs(pose - other).max() > 1e-7 for other in found):
                found.append(pose)
    return found


def among(pose: np.ndarray, poses: np.ndarray, tolerance: float) -> bool:
    return bool((np.abs(poses - pose).max(axis=(-2, -1)) < tolerance).any())


@pytest.mark.slow
def test_every_mode_of_the_skew_package_closes_and_the_home_is_one(skew, package):
    """forward_pose_all in both backends. Before, the solver rescaled the model's length
    parameters (r_c, L) but not its lengths written as numbers (R_B, R_P, HOME_HEIGHT): it listed
    2 modes per input whose closure residual was 0.087-0.17 m and missed the home. Now, at the
    home's cranks: the 8 real poses that least squares from 300 random starts finds (this file's
    geometry) are exactly the modes (1e-9), the home among them; at 10 random crank triples:
    every mode closes this file's geometry (1e-12) and the pose that closes with the cranks is
    one. The root count, 32, is proven: monodromy's 32 are what each of two total-degree runs of
    1024 paths found (before the runs were equilibrated they found 21-22 each, and no input was
    certified complete); every input here is certified complete."""
    import parakin

    home = np.eye(4)
    home[2, 3] = skew.HOME_HEIGHT
    expected = real_poses(skew, np.zeros(3), 300, 5)
    assert len(expected) == 8 and among(home, np.array(expected), 1e-12)
    rng = np.random.default_rng(3)
    cases = [(crank, *reachable_pose(skew, crank)) for crank in rng.uniform(-0.3, 0.3, (10, 3))]
    checked = 0
    for backend in ("numpy", "compiled"):
        m = parakin.load(package, backend=backend)
        modes = m.forward_pose_all(np.zeros(3), strict=False)
        listed = modes.poses[modes.valid]
        assert len(listed) == 8 and all(among(pose, listed, 1e-9) for pose in expected)
        assert modes.root_count == 32 and modes.root_count_proven and modes.complete()
        for crank, rotation, position in cases:
            modes = m.forward_pose_all(crank, strict=False)
            listed = modes.poses[modes.valid]
            for pose in listed:
                assert np.abs(residuals(skew, crank, pose[:3, :3], pose[:3, 3])).max() < 1e-12
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = rotation, position
            assert among(pose, listed, 1e-9) and modes.complete()
            checked += 1
    assert checked == 20
    automatic = parakin.load(package, backend="numpy").capabilities.forward_methods["automatic"].homotopy
    assert automatic is not None and automatic.root_count is not None
    proof = automatic.root_count
    assert proof.proven and proof.count == 32 and proof.bezout_paths == 1024
    assert tuple(proof.regular_endpoints) == (32, 32) and "equilibrated" in proof.method
