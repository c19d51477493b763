"""inverse_pose(onto_reachable=True): a lower-mobility platform asked for a pose answers with the
configuration of the pose it reaches (issue 32 item 2).

Independent facts: the mechanism files' geometry (base and platform joints, revolute axes, leg
ranges) evaluated by hand here; the 3-PRS's parasitic motion by the hand formula of
mechanisms/prs3.py (docs/derivations/prs3.md); the 3-RPS's by the same formula turned with its
legs: both platforms keep each joint C_i in the vertical plane through the axis z and e_i, the
3-RPS's legs at eta_i = 90, 210, 330 deg, the 3-PRS's at 0, 120, 240 deg, a quarter turn apart.
Turning the design by phi about z turns the parasitic position by phi and the tilt's azimuth
alpha by phi: x + i y = -c e^(-2 i alpha) e^(3 i phi), c = r_p (1 - cos beta) / 2, for the tilt
R0 = Rot_z(alpha) Rot_y(beta) Rot_z(-alpha); phi = 90 deg: x = c sin(2 alpha), y = c cos(2 alpha).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError, BrokenPackageError, UnsupportedOperationError
from parakin.interfaces import cli
from parakin.packages.manifest import Manifest

R_B, R_P = 1.0, 0.5  # mechanisms/rps3.py's defaults (m)
LENGTHS = (0.25, 3.0)  # its leg limits (m)
ETA = np.radians([90.0, 210.0, 330.0])
RADIAL = np.stack([np.cos(ETA), np.sin(ETA), np.zeros(3)], axis=-1)
TANGENT = np.stack([-np.sin(ETA), np.cos(ETA), np.zeros(3)], axis=-1)  # the revolute axes u_i


def rot_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_y(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def transform(rotation: np.ndarray, position) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = rotation, position
    return out


def rps3_reached(alpha: float, beta: float, height: float) -> np.ndarray:
    """The 3-RPS's reachable pose of tilt Rot_z(alpha) Rot_y(beta) Rot_z(-alpha) at the height
    (module docstring: the 3-PRS's formula turned by a quarter turn)."""
    c = R_P * (1.0 - math.cos(beta)) / 2.0
    tilt = rot_z(alpha) @ rot_y(beta) @ rot_z(-alpha)
    return transform(tilt, [c * math.sin(2 * alpha), c * math.cos(2 * alpha), height])


@pytest.fixture(scope="module")
def rps3():
    return parakin.load("rps3", backend="numpy")


def test_rps3_tilted_poses_answer_with_the_reached_configuration(rps3):
    rng = np.random.default_rng(20261129)
    checked = 0
    for _ in range(12):
        alpha, beta = rng.uniform(-np.pi, np.pi), rng.uniform(0.05, 0.5)
        height, turn = rng.uniform(0.6, 1.5), rng.uniform(-1.0, 1.0)  # |turn| < pi / 2: the nearer reading
        offset = rng.uniform(-0.05, 0.05, size=2)
        tilt = rot_z(alpha) @ rot_y(beta) @ rot_z(-alpha)
        # asked: the tilt and height, with a turn about the vertical and x, y off the set
        asked = transform(rot_z(turn) @ tilt, [offset[0], offset[1], height])
        assert not rps3.inverse_pose(asked, strict=False).valid.any()  # off the set, as declared
        result = rps3.inverse_pose(asked, onto_reachable=True)
        assert result.valid.all()
        expected = rps3_reached(alpha, beta, height)
        np.testing.assert_allclose(result.pose, expected, atol=1e-12)
        # the controlled coordinates are the asked ones: the height p . k and the tilt R^T k
        k = np.array([0.0, 0.0, 1.0])
        assert result.pose[2, 3] == pytest.approx(height, abs=1e-14)
        np.testing.assert_allclose(result.pose[:3, :3].T @ k, asked[:3, :3].T @ k, atol=1e-14)
        # the configuration closes and puts the platform at the pose it carries
        branch = result.branch(0)
        residual = rps3.loop_closure(branch.actuated, branch.passive)["residual"]
        assert np.abs(residual).max() < 1e-12
        np.testing.assert_allclose(rps3.platform_pose(branch.actuated, branch.passive), result.pose, atol=1e-12)
        # by hand: each platform joint in its leg's plane, each leg's length |C_i - A_i|
        joints = expected[:3, 3] + (expected[:3, :3] @ (R_P * RADIAL).T).T
        assert np.abs(np.einsum("ij,ij->i", joints, TANGENT)).max() < 1e-14
        np.testing.assert_allclose(branch.actuated, np.linalg.norm(joints - R_B * RADIAL, axis=-1), atol=1e-12)
        checked += 1
    assert checked == 12


def test_the_manifest_names_the_reading_and_its_conditions(rps3):
    reading = rps3.manifest.capabilities.inverse.reading
    assert reading.axis == ("0", "0", "1")  # rps3.py: the legs' planes share the vertical axis
    assert reading.unreachable == "invalid"
    assert reading.reachable == ("leg1_plane_reachable", "leg2_plane_reachable", "leg3_plane_reachable")
    assert "controlled: the height" in reading.controlled
    prs3 = parakin.load("prs3", backend="numpy").manifest.capabilities.inverse.reading
    assert (prs3.unreachable, prs3.reachable) == ("read", ())
    for name in ("stewart", "tricept"):  # full mobility; an inverse that takes the pose as given
        assert parakin.load(name, backend="numpy").manifest.capabilities.inverse.reading is None


def test_prs3_reads_already_and_matches_its_hand_formula():
    m = parakin.load("prs3", backend="numpy")
    r_p = m.parameters["r_p"]
    checked = 0
    for alpha, beta, turn in [(0.3, 0.2, 0.4), (-1.2, 0.35, -0.7), (2.5, 0.1, 0.0)]:
        tilt = rot_z(alpha) @ rot_y(beta) @ rot_z(-alpha)
        asked = transform(rot_z(turn) @ tilt, [0.03, -0.02, 0.6])
        plain = m.inverse_pose(asked)
        onto = m.inverse_pose(asked, onto_reachable=True)  # declared unreachable="read": no change
        np.testing.assert_array_equal(onto.valid, plain.valid)
        np.testing.assert_array_equal(onto.actuated, plain.actuated)
        np.testing.assert_array_equal(onto.pose, plain.pose)
        x0 = r_p * (math.cos(beta) - 1) * math.cos(2 * alpha) / 2  # mechanisms/prs3.py's docstring
        y0 = r_p * (1 - math.cos(beta)) * math.sin(2 * alpha) / 2
        np.testing.assert_allclose(onto.pose, transform(tilt, [x0, y0, 0.6]), atol=1e-12)
        checked += 1
    assert checked == 3


@pytest.mark.parametrize(("name", "words"), [("stewart", "full mobility"), ("tricept", "takes the pose as given")])
def test_no_reading_refuses_the_option(name, words):
    m = parakin.load(name, backend="numpy")
    pose = m.platform_pose(m.home_actuated, m.home_passive)
    assert m.inverse_pose(pose).valid.any()  # the plain call works at the home
    with pytest.raises(UnsupportedOperationError, match=words) as error:
        m.inverse_pose(pose, onto_reachable=True)
    assert "onto_reachable" in str(error.value)


def test_the_option_is_a_bool(rps3):
    pose = rps3.platform_pose(rps3.home_actuated, rps3.home_passive)
    with pytest.raises(BadInputError, match="onto_reachable must be True or False"):
        rps3.inverse_pose(pose, onto_reachable="yes")


def test_a_reading_naming_no_validity_condition_is_a_broken_package(rps3):
    data = json.loads((rps3.package.path / "manifest.json").read_text())
    data["capabilities"]["inverse"]["reading"]["reachable"] = ["leg9_plane_reachable"]
    with pytest.raises(BrokenPackageError, match="capabilities.inverse.reading.reachable"):
        Manifest.from_dict(data)
    del data["capabilities"]["inverse"]["reading"]  # optional: an older manifest reads as no reading
    assert Manifest.from_dict(data).capabilities.inverse.reading is None


def test_sweep_height_and_tilt_of_a_3rps(rps3):
    pytest.importorskip("xarray")
    pytest.importorskip("dask")
    heights, tilts = np.linspace(2.6, 3.2, 5), np.linspace(-0.4, 0.4, 5)
    axes = {"z": heights, "beta": tilts}
    quantities = ["reachable", "branches", "type_ii_distance"]
    plain = parakin.sweep(rps3, ["reachable"], axes, fixed={"x": 0.0, "y": 0.0}, scheduler="synchronous")
    # x = y = 0 is on the set only level (the new-user review): reachable at beta = 0 at most
    assert not plain["reachable"].values[:, tilts != 0].any()
    onto = parakin.sweep(
        rps3, quantities, axes, fixed={"x": 0.0, "y": 0.0}, scheduler="synchronous", onto_reachable=True
    )
    # by hand: the reached pose of each (z, beta) (alpha = gamma = 0), its legs' lengths in range
    expected = np.zeros((5, 5), dtype=bool)
    for i, height in enumerate(heights):
        for j, beta in enumerate(tilts):
            pose = rps3_reached(0.0, beta, height)
            joints = pose[:3, 3] + (pose[:3, :3] @ (R_P * RADIAL).T).T
            lengths = np.linalg.norm(joints - R_B * RADIAL, axis=-1)
            expected[i, j] = bool(((lengths >= LENGTHS[0]) & (lengths <= LENGTHS[1])).all())
    assert 0 < expected.sum() < expected.size  # the grid crosses the legs' range
    np.testing.assert_array_equal(onto["reachable"].values, expected)
    np.testing.assert_array_equal(onto["branches"].values, expected.astype(int))  # one branch: prismatic legs
    distances = onto["type_ii_distance"].values
    assert np.isfinite(distances[expected]).all() and (distances[expected] > 0).all()
    assert np.isnan(distances[~expected]).all()
    with pytest.raises(UnsupportedOperationError, match="full mobility"):
        parakin.sweep("stewart", ["reachable"], {"z": [1.0]}, backend="numpy", onto_reachable=True)


def test_cli_ik_onto_reachable(capsys):
    argv = ["ik", "rps3", "--backend", "numpy", "--pose", "0", "0", "1", "0", "0.2", "0", "--json"]
    assert cli.main(argv) == 1  # off the set as asked: no valid branch
    capsys.readouterr()
    assert cli.main([*argv, "--onto-reachable"]) == 0
    record = json.loads(capsys.readouterr().out.splitlines()[0])
    assert record["valid"] is True
    reached = rps3_reached(0.0, 0.2, 1.0)
    assert record["reached_pose"]["y [m]"] == pytest.approx(reached[1, 3], abs=1e-12)
    assert record["reached_pose"]["z [m]"] == pytest.approx(1.0, abs=1e-12)
    assert (
        cli.main(["ik", "stewart", "--backend", "numpy", "--pose", "0", "0", "1", "0", "0", "0", "--onto-reachable"])
        == 2
    )


def test_a_pose_past_the_actuators_ranges_is_invalid_not_an_error():
    # prs3's rails are 1 m long: at z = 1.5 m every stroke leaves its range; the reached pose was
    # evaluated from branch 0's out-of-range strokes, which platform_pose refuses (BadInputError)
    m = parakin.load("prs3", backend="numpy")
    far, near = (transform(rot_y(0.2), [0.0, 0.0, height]) for height in (1.5, 0.6))
    result = m.inverse_pose(np.stack([far, near]), strict=False)
    assert result.valid.any(-1).tolist() == [False, True]
    assert result.failures["actuator_range"][0].all()
    np.testing.assert_array_equal(result.pose[0], far)  # no branch: the given pose
