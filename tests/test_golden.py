"""The mechanisms re-expressed in the joint language against their hand-derived versions (golden data).

``tests/golden/NAME.npz`` holds inputs and results of the hand-derived packages (commit 71d1c7d^ =
HAND_COMMIT, before the joint language), evaluated by that commit's own runtime
(``tests/golden/make_golden.py`` says how and at which seeded inputs). The packages derived from
joints must give the same:

- inverse branches, with their numbering: at 1000 sampled poses and at poses farther out (many
  out of reach of some legs), the same branches valid, each validity condition failing at the
  same branches, NaN in the same places and the same actuated values on every branch where they
  are defined (valid, or failing only an actuator range or limit: rus6's 63 branches of 64 near
  home), to 1e-9 (relative to the value, at least 1 m or 1 rad; revolute values modulo 2 pi);
- forward rates: the platform twist for the same actuated rates at the 1000 configurations, to 1e-9
  relative to the twist's largest component (at least 1);
- singularity factors up to a nonzero factor: each factor named in both versions, det A and det B
  included, is a constant nonzero multiple c of the old one over the 1000 configurations
  (|new - c old| <= 1e-9 |c| max |old|), so the two are proportional and their zero sets coincide.
  The ratios are 1 but for spm's leg<i>_axes_coplanar (sin alpha1 = 1/sqrt 2: (u_i x w_i) . v_i
  for the old cos phi_i) and prs3's, written in other forms by hand: leg<i>_link_horizontal now
  in metres (ratio L = 0.35; the old one was divided by L) and platform_moves_with_sliders_locked
  now the determinant of the six leg wrenches (ratio -5.36e-6 to the old det(dg/dt) / (L r_p)^3 of
  the closure in the link angles: different matrices, proportional determinants);
- assembly modes: the same number of real modes per input and the same set of poses, on the first
  1000 sampled inputs by a fingerprint per mode (a fixed random linear functional of the 3 x 4
  pose, compared as sorted sets, to 1e-8 times the functional's norm), on the first 50 pose by pose
  (each new pose within 1e-8 of an old one and each old one of a new one, relative to the pose's
  largest entry, at least 1). rus6 takes about a second per input: its first 2 inputs run by
  default, its other 10 with --run-slow; stewart and prs3 (homotopies, 10-50 ms per input) their
  first 200 by default, the other 800 with --run-slow; the others (milliseconds) all 1000.

What differs by design is compared on what does not: spm's passive values are now a quaternion
(only actuated values, twists, factors and poses are compared, never passive values); spm's
input-independent factors proximal_links_folded, distal_links_folded_a and _b (sin^3 of a link
angle: nonzero constants of the architecture) are no longer listed, so they are checked to be
nonzero constants; the 3-PRS had no rate model by hand, so its twist is not compared and its new
det_A and det_B have no old counterpart (its named factors are compared).

The tests are parametrised by ``mechanism``, not ``name``: tests/conftest.py skips tests
parametrised by ``name`` of the mechanisms whose all-modes solver is heavy (rus6), and only the
modes comparison is; it keeps rus6 short by its own count of inputs.
"""

from __future__ import annotations

import functools
import importlib.util
from pathlib import Path

import numpy as np
import pytest

import parakin

GOLDEN = Path(__file__).parent / "golden"
_spec = importlib.util.spec_from_file_location("make_golden", GOLDEN / "make_golden.py")
assert _spec is not None and _spec.loader is not None
make_golden = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_golden)

NAMES: tuple[str, ...] = make_golden.NAMES
HAND_COMMIT = "a1430e263304588df2add98ea7f84e537b92b692"
TOLERANCE = 1e-9
MODE_TOLERANCE = 1e-8
#: inputs of the all-modes comparison in the default run (all of them for the other mechanisms):
#: rus6 takes about a second per input, stewart and prs3 (homotopies) 10-50 ms
QUICK_MODE_INPUTS = {"rus6": 2, "stewart": 200, "prs3": 200}


@functools.cache
def golden(name: str) -> dict[str, np.ndarray]:
    """The golden arrays of one mechanism (read once)."""
    with np.load(GOLDEN / f"{name}.npz") as data:
        return dict(data)


WIDE = [name for name in NAMES if "wide_pose" in golden(name)]


def actuated_difference(m: parakin.Mechanism, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|a - b| per actuated variable (last axis), revolute ones modulo 2 pi, relative to |b| where
    |b| > 1."""
    revolute = np.array([v.kind == "revolute" for v in m.manifest.actuated])
    difference = np.where(revolute, np.angle(np.exp(1j * (a - b))), a - b)
    return np.abs(difference) / np.maximum(np.abs(b), 1.0)


def configuration(m: parakin.Mechanism, data: dict[str, np.ndarray]) -> parakin.Configuration:
    """The golden configurations in the new package: the golden actuated values and pose, with the
    passive values of the new inverse on the branch that gives those actuated values."""
    inverse = m.inverse_pose(data["pose"], strict=False)
    match = np.nan_to_num(actuated_difference(m, inverse.actuated, data["actuated"][:, None, :]), nan=np.inf)
    branch = match.max(-1).argmin(-1)
    rows = np.arange(branch.size)
    assert match.max(-1)[rows, branch].max() < TOLERANCE
    return parakin.Configuration(data["actuated"], inverse.passive[rows, branch], data["pose"])


def test_golden_data_for_every_re_expressed_mechanism_from_the_hand_derived_commit():
    for name in NAMES:
        data = golden(name)
        assert str(data["source_commit"]) == HAND_COMMIT, name
        assert data["pose"].shape[0] == make_golden.SAMPLES, name


@pytest.mark.parametrize(("mechanism", "prefix"), [(name, "") for name in NAMES] + [(name, "wide_") for name in WIDE])
def test_inverse_branches_their_numbering_and_validity(mechanism, prefix):
    m, data = parakin.load(mechanism), golden(mechanism)
    inverse = m.inverse_pose(data[f"{prefix}pose"], strict=False)
    old, valid = data[f"{prefix}inverse_actuated"], data[f"{prefix}inverse_valid"]
    assert inverse.actuated.shape == old.shape
    assert (inverse.valid == valid).all(), f"{(inverse.valid != valid).sum()} branches differ in validity"
    assert (np.isnan(inverse.actuated) == np.isnan(old)).all()
    names = data[f"{prefix}inverse_failure_names"].tolist()
    failures = dict(zip(names, np.moveaxis(data[f"{prefix}inverse_failures"], -1, 0), strict=True))
    for key in set(failures) | set(inverse.failures):
        # a condition added by the new version never fails here (sps's leg<i>_length)
        before = failures.get(key, np.zeros_like(valid))
        assert (inverse.failures[key] == before).all(), f"{key} fails at other branches"
    # a branch whose leg has no solution holds a placeholder (spm: acos clipped), defined only
    # where nothing but a range failed
    undefined = [failed for key, failed in failures.items() if key not in ("limits", "actuator_range")]
    defined = ~np.any(undefined, axis=0) & ~np.isnan(old).any(-1)
    worst = actuated_difference(m, inverse.actuated, old)[defined].max()
    assert worst < TOLERANCE, worst
    assert defined.sum() >= 1000  # branches compared
    if prefix:  # the wide poses exercise validity: at least 5 % with a valid branch, 5 % with an invalid one
        poses = valid.shape[0]
        assert valid.any(-1).sum() >= 0.05 * poses and (~valid).any(-1).sum() >= 0.05 * poses


@pytest.mark.parametrize("mechanism", [name for name in NAMES if "twist" in golden(name)])
def test_forward_rates(mechanism):
    m, data = parakin.load(mechanism), golden(mechanism)
    twist = m.forward_rate(configuration(m, data), data["actuated_rates"])
    scale = np.maximum(np.abs(data["twist"]).max(-1, keepdims=True), 1.0)
    worst = (np.abs(twist - data["twist"]) / scale).max()
    assert worst <= TOLERANCE, worst
    assert twist.shape[0] >= 1000


@pytest.mark.parametrize("mechanism", NAMES)
def test_singularity_factors_up_to_a_nonzero_factor(mechanism):
    m, data = parakin.load(mechanism), golden(mechanism)
    values = m.singularities(configuration(m, data))
    old = dict(zip(data["singularity_names"].tolist(), np.moveaxis(data["singularity_values"], -1, 0), strict=True))
    # the new version adds det A and det B only where the hand-derived one had no rate model (prs3)
    assert set(values) - set(old) <= ({"det_A", "det_B"} if "twist" not in data else set())
    shared = [key for key in old if key in values]
    assert len(shared) >= 3
    for key, before in old.items():
        if key not in values:  # dropped: a nonzero constant of the architecture
            assert np.ptp(before) <= TOLERANCE * np.abs(before).max() and (before != 0).all(), key
            continue
        after = values[key]
        ratio = before @ after / (before @ before)
        assert ratio != 0, key
        worst = np.abs(after - ratio * before).max() / (abs(ratio) * np.abs(before).max())
        assert worst <= TOLERANCE, (key, ratio, worst)
        assert before.size >= 1000


def _modes_agree(mechanism: str, inputs: slice) -> int:
    """Compare the assembly modes of the golden mode inputs in ``inputs``; return how many inputs."""
    m, data = parakin.load(mechanism), golden(mechanism)
    counts = data["mode_count"]
    index = np.arange(counts.size)[inputs]
    modes = m.forward_pose_all(data["actuated"][index], strict=False)
    assert (np.asarray(modes.count) == counts[index]).all(), "mode counts differ"
    starts = np.concatenate([[0], np.cumsum(counts)])
    weights = data["fingerprint_weights"]
    with_poses = int(np.searchsorted(starts, data["mode_poses"].shape[0]))
    assert starts[with_poses] == data["mode_poses"].shape[0]
    for i, k in enumerate(index):
        new = modes.poses[i][np.nonzero(modes.valid[i])[0]][:, :3, :]
        scale = max(1.0, np.abs(new).max(initial=0.0))
        fingerprint = np.sort((new * weights).sum((-2, -1)))
        before = np.sort(data["mode_fingerprint"][starts[k] : starts[k + 1]])
        worst = np.abs(fingerprint - before).max(initial=0.0)
        assert worst <= MODE_TOLERANCE * np.abs(weights).sum() * scale, (k, worst)
        if k < with_poses:
            old = data["mode_poses"][starts[k] : starts[k + 1]]
            distance = np.abs(new[:, None] - old[None, :]).max((-2, -1)) / scale
            assert (distance.min(0) < MODE_TOLERANCE).all() and (distance.min(1) < MODE_TOLERANCE).all(), k
    return index.size


@pytest.mark.parametrize("mechanism", NAMES)
def test_assembly_modes_are_the_same_poses(mechanism):
    inputs = QUICK_MODE_INPUTS.get(mechanism, make_golden.SAMPLES)
    assert golden(mechanism)["mode_count"].size >= inputs
    assert _modes_agree(mechanism, slice(0, inputs)) == inputs


@pytest.mark.slow
@pytest.mark.parametrize("mechanism", sorted(QUICK_MODE_INPUTS))
def test_assembly_modes_of_the_remaining_inputs(mechanism):
    start = QUICK_MODE_INPUTS[mechanism]
    remaining = golden(mechanism)["mode_count"].size - start
    assert remaining >= 10
    assert _modes_agree(mechanism, slice(start, None)) == remaining
