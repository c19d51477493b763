"""The 3-RPS (``mechanisms/rps3.py``, Lee and Shah 1988), written as joints.

* Its forward pose has 16 complex solutions (Lee and Shah): the generator's proven root count
  is 32 paths, and the start solutions pair up as the two quaternion signs of 16 poses.
* Every mode of random inputs is a configuration this test checks with its own geometry: each
  platform joint C_i at its leg's length from A_i and in the leg's plane, (C_i - A_i) . u_i = 0;
  and the inverse of the mode's pose gives the inputs back.
* The motion is parasitic: tilted modes move the platform's centre sideways.
"""

from __future__ import annotations

import numpy as np
import pytest

import parakin

R_B, R_P = 1.0, 0.5
ETA = np.radians([90.0, 210.0, 330.0])
RADIAL = np.stack([np.cos(ETA), np.sin(ETA), np.zeros(3)], -1)
TANGENT = np.stack([-np.sin(ETA), np.cos(ETA), np.zeros(3)], -1)


@pytest.fixture(scope="module")
def m():
    return parakin.load("rps3", backend="numpy")


def test_sixteen_complex_poses_each_with_two_quaternion_signs(m):
    homotopy = parakin.metadata("rps3").capabilities.forward.homotopy
    assert homotopy is not None and homotopy.root_count is not None
    assert homotopy.root_count.proven and homotopy.root_count.count == 32
    start = np.asarray(homotopy.start)
    assert start.shape[0] == 32
    position, quaternion = start[:, :3], start[:, 3:]
    partners = 0
    for k in range(32):
        twin = np.abs(position - position[k]).max(-1) + np.abs(quaternion + quaternion[k]).max(-1)
        partners += int(np.sum(twin < 1e-8 * (1 + np.abs(start).max())))
    assert partners == 32  # each start solution has exactly one twin: 16 poses


def test_every_mode_closes_in_its_legs_planes_and_inverts_back(m):
    rng = np.random.default_rng(6)
    home = np.array([v.home for v in m.manifest.actuated])
    checked = parasitic = 0
    for _ in range(8):
        lengths = home + 0.15 * rng.uniform(-1, 1, 3)
        modes = m.forward_pose_all(lengths)
        for k in range(int(modes.count)):
            pose = modes.mode(k).pose
            joints = pose[:3, 3] + R_P * RADIAL @ pose[:3, :3].T
            offsets = joints - R_B * RADIAL
            assert np.abs(np.linalg.norm(offsets, axis=-1) - lengths).max() < 1e-10
            assert np.abs((offsets * TANGENT).sum(-1)).max() < 1e-10
            ik = m.inverse_pose(pose, strict=False)
            assert ik.valid[0] and np.abs(ik.actuated[0] - lengths).max() < 1e-10
            if abs(pose[2, 2]) > 0.5 and abs(pose[2, 2]) < 1 - 1e-4:  # tilted, not upside down
                parasitic += int(np.hypot(pose[0, 3], pose[1, 3]) > 1e-6)
            checked += 1
    assert checked >= 16
    assert parasitic >= 4


def test_a_pose_off_the_reachable_set_is_read_onto_it_and_invalid(m):
    """A mode's pose moved 5 cm sideways and turned 0.2 rad about the vertical: every branch
    invalid with the planes its joints leave named (this test's geometry: > 1e-6 of the legs'
    size), and the values returned are the reachable pose with the given height and tilt R^T k
    (the controlled coordinates the manifest names): a configuration that closes, its joints in
    their planes (1e-12), the mode's own values where nothing was moved (1e-12)."""
    assert "controlled: the height p . k and the tilt n = R^T k" in m.manifest.joints.motion.text
    home = np.array([v.home for v in m.manifest.actuated])
    modes = m.forward_pose_all(home + np.array([0.1, -0.05, 0.02]))
    checked = 0
    for k in range(int(modes.count)):
        pose = modes.mode(k).pose
        c, s = np.cos(0.2), np.sin(0.2)
        off = pose.copy()
        off[:3, :3] = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ pose[:3, :3]
        off[:2, 3] += 0.05
        ik = m.inverse_pose(off, strict=False)
        assert not ik.valid.any()
        offsets = np.abs(((off[:3, 3] + R_P * RADIAL @ off[:3, :3].T - R_B * RADIAL) * TANGENT).sum(-1))
        named = [int(n[3]) for n, failed in ik.failures.items() if n.endswith("plane_reachable") and failed.all()]
        assert named and all(offsets[i - 1] > 1e-6 for i in named)
        for branch in range(ik.actuated.shape[0]):
            read = m.platform_pose(ik.actuated[branch], ik.passive[branch])
            joints = read[:3, 3] + R_P * RADIAL @ read[:3, :3].T - R_B * RADIAL
            assert np.abs((joints * TANGENT).sum(-1)).max() < 1e-12
            assert np.abs(m.loop_closure(ik.actuated[branch], ik.passive[branch])["residual"]).max() < 1e-12
            assert abs(read[2, 3] - off[2, 3]) < 1e-12 and np.abs(read[2, :3] - off[2, :3]).max() < 1e-12
        same = m.inverse_pose(pose, strict=False)
        assert np.abs(m.platform_pose(same.actuated[0], same.passive[0]) - pose).max() < 1e-12
        checked += 1
    assert checked >= 2
