"""The Tricept (``mechanisms/tricept.py``): three actuated U-P-S legs and a passive U-P leg fixed to
the platform, which parakin's joint language could not say before the joint graph.

Checked against this test's own NumPy geometry (not the package's expressions):

* the inverse of a pose the passive leg can take (R = Rot_x(a) Rot_y(b), p = s R z_P) is each
  leg's length |p + R c_i - A_i|, computed here directly; a pose the passive leg cannot take
  (the platform moved off the leg's line, or turned about the leg) is invalid, the passive leg's
  condition named;
* the forward pose of those lengths holds the pose among its modes (a round trip from random
  poses), and every mode is a configuration of this geometry: the platform on the passive leg's
  line on the far side of its universal joint, not turned about the leg, at the lengths;
* the forward rates are the central differences of the poses along random input rates;
* the screw analysis gives three degrees of freedom, two rotations and a translation at the
  home (Siciliano 1999: the passive leg's two angles and its length).
"""

from __future__ import annotations

import numpy as np
import pytest

import parakin

R_B, R_P = 0.3, 0.1
ETA = np.radians([0.0, 120.0, 240.0])
BASE = np.stack([R_B * np.cos(ETA), R_B * np.sin(ETA), np.zeros(3)], -1)
PLATFORM = np.stack([R_P * np.cos(ETA), R_P * np.sin(ETA), np.zeros(3)], -1)


@pytest.fixture(scope="module")
def m():
    return parakin.load("tricept", backend="numpy")


def rot_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def pose_of(a: float, b: float, s: float) -> np.ndarray:
    """The passive leg's pose: R = Rot_x(a) Rot_y(b), p = s R z."""
    pose = np.eye(4)
    pose[:3, :3] = rot_x(a) @ rot_y(b)
    pose[:3, 3] = s * pose[:3, 2]
    return pose


def lengths(pose: np.ndarray) -> np.ndarray:
    """|p + R c_i - A_i|, each actuated leg's length."""
    joints = pose[:3, 3] + PLATFORM @ pose[:3, :3].T
    return np.linalg.norm(joints - BASE, axis=-1)


def random_poses(count: int, seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [pose_of(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), rng.uniform(0.4, 0.8)) for _ in range(count)]


def test_inverse_is_each_legs_length_and_off_the_passive_leg_invalid(m):
    checked = 0
    for pose in random_poses(20, 1):
        ik = m.inverse_pose(pose, strict=False)
        assert ik.valid.all()
        assert np.abs(ik.actuated - lengths(pose)).max() < 1e-12
        assert np.abs(m.platform_pose(ik.actuated[0], ik.passive[0]) - pose).max() < 1e-12
        moved = pose.copy()
        moved[:3, 3] += 0.01 * moved[:3, 0]  # off the leg's line
        turned = pose.copy()
        turned[:3, :3] = pose[:3, :3] @ np.array(
            [[np.cos(0.05), -np.sin(0.05), 0], [np.sin(0.05), np.cos(0.05), 0], [0, 0, 1]]
        )
        for off, name in ((moved, "leg4_line_reachable"), (turned, "leg4_u_joint_reachable")):
            found = m.inverse_pose(off, strict=False)
            assert not found.valid.any()
            assert found.failures[name].all()
        checked += 1
    assert checked == 20


def test_forward_pose_round_trips_random_poses(m):
    checked = 0
    for pose in random_poses(6, 2):
        modes = m.forward_pose_all(lengths(pose))
        errors = [np.abs(modes.mode(k).pose - pose).max() for k in range(int(modes.count))]
        assert min(errors) < 1e-9
        for k in range(int(modes.count)):  # every mode a configuration of this test's geometry
            found = modes.mode(k).pose
            line = found[:3, 2]  # the passive leg along R z, the platform on its far side
            assert np.linalg.norm(np.cross(found[:3, 3], line)) < 1e-9 and found[:3, 3] @ line > 0
            assert abs(found[0, 1]) < 1e-9  # no turn about the leg: R y stays normal to x
            assert np.abs(lengths(found) - lengths(pose)).max() < 1e-9
        checked += 1
    assert checked == 6


def test_forward_rates_are_the_central_differences_of_the_poses(m):
    rng = np.random.default_rng(3)
    step, checked = 1e-6, 0
    for pose in random_poses(6, 4):
        state = m.forward_pose(lengths(pose), guess=m.inverse_pose(pose).passive[0])
        rates = rng.normal(size=3)
        ends = [m.forward_pose(state.actuated + s * step * rates, guess=state, tolerance=1e-13).pose for s in (-1, 1)]
        velocity = (ends[1][:3, 3] - ends[0][:3, 3]) / (2 * step)
        spin = (ends[1][:3, :3] - ends[0][:3, :3]) / (2 * step) @ state.pose[:3, :3].T
        twist = np.concatenate([velocity, [spin[2, 1], spin[0, 2], spin[1, 0]]])
        ours = m.forward_rate(state, rates)
        assert np.abs(ours - twist).max() < 1e-6 * np.abs(twist).max()
        checked += 1
    assert checked == 6


@pytest.mark.slow
def test_screw_analysis_finds_two_rotations_and_a_translation():
    from parakin.generator import graph
    from parakin.mechanisms import tricept

    built = tricept.build()
    assert built.joint_graph is not None and built.closure is not None
    found = graph.analyse(
        built.joint_graph, built.closure.residual, built.actuated, built.passive, built.parameters, built.home, count=3
    )
    assert (found.mobility, found.translations, found.rotations) == (3, 1, 2)
    assert found.locked == [0] * found.samples
