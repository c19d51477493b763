"""The ``conditioning`` of a mode is one measure on every backend (issue 33: "the same input
behaves the same on every backend"): parakin.singularity's type II distance, sigma_min /
sigma_max of the closure Jacobian d closure / d passive at the mode. It was a pivot ratio of the
last Newton step, which gave mirror-image modes of prs3's home 0.461 on one backend and 0.589 on
the other where both are 0.0967 by SVD. Checked here against the SVD of a central-difference
Jacobian of the closure residual (an independent derivative: the kernel's residual only)."""

from __future__ import annotations

import numpy as np
import pytest

import parakin

BACKENDS = ("compiled", "numpy")
#: central-difference step (rad and m): truncation ~h^2, rounding ~1e-16 / h
STEP = 1e-6


def svd_of_finite_differences(m, actuated, passive) -> float:
    """sigma_min / sigma_max of d closure / d passive by central differences of the residual."""
    columns = []
    for k in range(passive.size):
        step = np.zeros(passive.size)
        step[k] = STEP
        ahead = m.loop_closure(actuated, passive + step)["residual"]
        behind = m.loop_closure(actuated, passive - step)["residual"]
        columns.append((ahead - behind) / (2 * STEP))
    values = np.linalg.svd(np.stack(columns, axis=-1), compute_uv=False)
    return float(values[-1] / values[0])


@pytest.fixture(scope="module")
def home_modes():
    found = {}
    for backend in BACKENDS:
        m = parakin.load("prs3", backend=backend)
        found[backend] = m, m.forward_pose_all(m.home_actuated, strict=False)
    return found


def test_prs3_home_modes_have_one_conditioning_on_both_backends(home_modes):
    """Every mode of prs3 at its home: the compiled and NumPy backends report the same
    conditioning to 1e-12 (modes paired by pose), and it is the SVD ratio of a central-difference
    closure Jacobian at the mode to 1e-7; slots that are no mode hold NaN."""
    (m, compiled), (_, reference) = home_modes["compiled"], home_modes["numpy"]
    assert compiled.count == reference.count >= 8
    checked = 0
    for slot in np.nonzero(compiled.valid)[0]:
        distance = np.abs(reference.poses - compiled.poses[slot]).max((-2, -1))
        other = int(np.argmin(np.where(reference.valid, distance, np.inf)))
        assert distance[other] < 1e-9
        value = float(compiled.conditioning[slot])
        assert abs(value - float(reference.conditioning[other])) <= 1e-12, (slot, value, reference.conditioning[other])
        independent = svd_of_finite_differences(m, compiled.actuated, compiled.passive[slot])
        assert abs(value - independent) <= 1e-7, (slot, value, independent)
        checked += 1
    assert checked == int(compiled.count)
    for modes in (compiled, reference):
        assert np.isnan(modes.conditioning[~modes.valid]).all()
        assert np.isfinite(modes.conditioning[modes.valid]).all()
    # the mirror images the pivot ratio told apart (0.461 against 0.589) read alike: 0.0967
    assert np.isclose(compiled.conditioning[compiled.valid], 0.0967, atol=5e-5).sum() >= 2


@pytest.mark.parametrize("backend", BACKENDS)
def test_tracker_reads_the_same_measure(backend):
    """A tracker on prs3 after a step reports, for its solution, the SVD ratio of the
    central-difference closure Jacobian there (1e-7), and the all-modes solver reports the same
    number for that mode at that input (1e-12)."""
    m = parakin.load("prs3", backend=backend)
    tracker = m.tracker(m.forward_pose(m.home_actuated))
    target = m.home_actuated + np.array([0.01, -0.005, 0.002])
    passive, pose = tracker.solve(target)
    reading = tracker.conditioning
    assert reading.shape == ()
    independent = svd_of_finite_differences(m, target, passive)
    assert abs(float(reading) - independent) <= 1e-7, (reading, independent)
    modes = m.forward_pose_all(target, strict=False)
    distance = np.where(modes.valid, np.abs(modes.poses - pose).max((-2, -1)), np.inf)
    slot = int(np.argmin(distance))
    assert distance[slot] < 1e-9
    assert abs(float(modes.conditioning[slot]) - float(reading)) <= 1e-12


@pytest.mark.parametrize("backend", BACKENDS)
def test_count_modes_min_conditioning_is_the_smallest_type_ii_distance(backend):
    """A closed-form mechanism (five_bar's elimination, not a homotopy): count_modes'
    ``min_conditioning`` per input is the smallest SVD ratio of a central-difference closure
    Jacobian over that input's modes (1e-7), so a sweep's map reads on the scale of
    parakin.singularity.NEAR_SINGULAR."""
    m = parakin.load("five_bar", backend=backend)
    inputs = m.home_actuated + np.array([[0.0, 0.0], [0.05, -0.03], [-0.04, 0.02]])
    summary = m.count_modes(inputs)
    modes = m.forward_pose_all(inputs)
    checked = 0
    for i, theta in enumerate(inputs):
        values = [svd_of_finite_differences(m, theta, modes.passive[i, s]) for s in np.nonzero(modes.valid[i])[0]]
        assert len(values) == int(summary["count"][i]) >= 2
        assert abs(float(summary["min_conditioning"][i]) - min(values)) <= 1e-7, (i, summary["min_conditioning"][i])
        checked += 1
    assert checked == 3
