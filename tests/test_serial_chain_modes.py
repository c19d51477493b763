"""A serial chain (no passive joint) has exactly one forward pose, a function of its joints:
``forward_pose_all`` returns that one mode and says it is complete, on every backend, and the
command line's JSON says the same."""

from __future__ import annotations

import json

import numpy as np
import pytest

import parakin
from parakin.interfaces.cli import main


def rotate(axis: np.ndarray, angle: float, vector: np.ndarray) -> np.ndarray:
    """Rodrigues' formula, axis a unit vector."""
    c, s = np.cos(angle), np.sin(angle)
    return c * vector + s * np.cross(axis, vector) + (1 - c) * axis.dot(vector) * axis


def pointing_axis(theta1: float, theta2: float, alpha1: float, alpha2: float) -> np.ndarray:
    """w of the 2R chain by the report's eqs 1-4 (sphere2r's docstring), written out here."""
    u, k = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    m = rotate(u, theta1, k)
    v = rotate(m, alpha1, u)
    n = rotate(v, theta2, m)
    return rotate(n, alpha2, v)


@pytest.mark.parametrize("backend", ["numpy", "compiled"])
def test_a_serial_chain_has_one_mode_certified_complete(backend):
    m = parakin.load("sphere2r", backend=backend)
    alpha1, alpha2 = m.parameters["alpha1"], m.parameters["alpha2"]
    inputs = np.random.default_rng(7).uniform(-np.pi, np.pi, (12, 2))
    modes = m.forward_pose_all(inputs)
    assert modes.count.tolist() == [1] * 12 and modes.complete().all()
    found = modes.certificate()
    # no polynomial, so no root slot (root_kind -1, as documented); the one configuration is the
    # certified count
    assert found["certified_roots"].tolist() == found["root_count"].tolist() == [1] * 12
    assert (modes.root_kind == -1).all() and found["uncertified_paths"].tolist() == [0] * 12
    checked = 0
    for theta, pose in zip(inputs, modes.mode(0).pose, strict=True):
        assert np.allclose(pose[:3, 2], pointing_axis(*theta, alpha1, alpha2), atol=1e-12)
        checked += 1
    assert checked == 12
    assert "certified complete" in repr(m.forward_pose_all(m.home_actuated)).splitlines()[0]


def test_fk_json_of_a_serial_chain_says_certified_complete(capsys):
    assert main(["fk", "sphere2r", "--actuated", "0.1", "0.2", "--json"]) == 0
    lines = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert len(lines) == 1 and lines[0]["modes"] == 1 and lines[0]["certified_complete"] is True
