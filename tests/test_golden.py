"""The re-expressed mechanisms against their hand-derived versions (golden data).

``tests/golden/NAME.npz`` holds inputs and results of the hand-derived packages (commit 71d1c7d^,
before the joint language), evaluated by that commit's runtime (``tests/golden/make_golden.py``).
The packages derived from joints must give the same:

- inverse branches, with their numbering: the actuated values of every valid branch, to 1e-9;
  the same branches valid (a branch at the edge of validity, within 1e-9 of it, may differ);
- forward rates: the platform twist for the same actuated rates, to 1e-9 relative;
- singularity factors up to a nonzero factor: each determinant (det A, det B) and each factor
  named in both versions has a ratio new/old of one sign over every sample, bounded away from 0
  and infinity (its spread, max/min of |ratio|, below 1e6): the zero sets coincide;
- assembly modes: the same set of poses per input, to 1e-8 (on 200 of the inputs: every mode's pose
  is stored, which dominates the files' size; 12 for rus6, seconds per input).

What differs by design is compared on what does not: spm's passive values are now a quaternion
(only actuated values, twists and poses are compared); the 3-PRS had no rate model by hand (its
twist is not compared, its factors are).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import parakin

GOLDEN = Path(__file__).parent / "golden"
NAMES = sorted(p.stem for p in GOLDEN.glob("*.npz"))
TOLERANCE = 1e-9


def golden(name: str) -> dict[str, np.ndarray]:
    with np.load(GOLDEN / f"{name}.npz") as data:
        return dict(data)


def actuated_difference(m, a, b):
    """|a - b| per actuated variable, revolute ones modulo 2 pi."""
    revolute = np.array([v.kind == "revolute" for v in m.manifest.actuated])
    difference = a - b
    return np.abs(np.where(revolute, np.angle(np.exp(1j * difference)), difference))


def configuration(m, data):
    """The golden poses as configurations of the new package (passive values from its inverse on
    the branch that reproduces the golden actuated values)."""
    inverse = m.inverse_pose(data["pose"], strict=False)
    match = np.nan_to_num(actuated_difference(m, inverse.actuated, data["actuated"][:, None, :]), nan=np.inf).max(-1)
    branch = match.argmin(-1)
    rows = np.arange(branch.size)
    assert (match[rows, branch] < 1e-9).all()
    return parakin.Configuration(data["actuated"], inverse.passive[rows, branch], data["pose"])


def test_there_is_golden_data_for_every_mechanism_in_the_joint_language():
    assert len(NAMES) >= 10


@pytest.mark.parametrize("name", NAMES)
def test_inverse_branches_and_their_numbering(name):
    m, data = parakin.load(name), golden(name)
    inverse = m.inverse_pose(data["pose"], strict=False)
    old, new = data["inverse_actuated"], inverse.actuated
    assert new.shape == old.shape
    both = data["inverse_valid"] & inverse.valid
    assert actuated_difference(m, new, old)[both].max() < TOLERANCE
    # validity: the same branches, but for those at the edge (closing to rounding either way)
    disagree = data["inverse_valid"] != inverse.valid
    assert disagree.sum() <= 0.001 * disagree.size
    assert both.sum() >= 1000


@pytest.mark.parametrize("name", [n for n in NAMES if "twist" in golden(n)])
def test_forward_rates(name):
    m, data = parakin.load(name), golden(name)
    twist = m.forward_rate(configuration(m, data), data["actuated_rates"])
    scale = np.abs(data["twist"]).max(-1, keepdims=True)
    assert (np.abs(twist - data["twist"]) <= TOLERANCE * np.maximum(scale, 1.0)).all()
    assert twist.shape[0] >= 1000


@pytest.mark.parametrize("name", NAMES)
def test_singularity_factors_up_to_a_nonzero_factor(name):
    m, data = parakin.load(name), golden(name)
    values = m.singularities(configuration(m, data))
    old = dict(zip(data["singularity_names"].tolist(), np.moveaxis(data["singularity_values"], -1, 0), strict=True))
    shared = sorted(set(old) & set(values))
    assert {"det_A", "det_B"} & set(shared) or len(shared) >= 3, shared
    for key in shared:
        ratio = values[key] / old[key]
        live = np.abs(old[key]) > 1e-12 * np.abs(old[key]).max()
        assert live.sum() >= 900, key
        ratio = ratio[live]
        assert (np.sign(ratio) == np.sign(ratio[0])).all(), key
        spread = np.abs(ratio).max() / np.abs(ratio).min()
        assert spread < 1e6, (key, spread)


@pytest.mark.parametrize("name", NAMES)
def test_assembly_modes_are_the_same_poses(name):
    m, data = parakin.load(name), golden(name)
    modes = m.forward_pose_all(data["mode_actuated"], strict=False)
    assert (np.asarray(modes.count) == data["mode_count"]).all()
    checked = 0
    ends = np.cumsum(data["mode_count"])
    for i in range(data["mode_actuated"].shape[0]):
        new = modes.poses[i][np.nonzero(modes.valid[i])[0]][:, :3, :]
        old = data["mode_poses"][ends[i] - data["mode_count"][i] : ends[i]]
        distance = np.abs(new[:, None] - old[None, :]).max((-2, -1))
        assert (distance.min(0) < 1e-8).all() and (distance.min(1) < 1e-8).all()
        checked += new.shape[0]
    assert checked >= data["mode_actuated"].shape[0]
