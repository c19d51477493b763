"""The compiled tracker step (NAME_forward_pose_step: the inputs' ranges, the Newton step and the
mode checks in one foreign call) against the NumPy backend's tracker, which runs every check in
Python: the same solutions and the same flags along a path, the same named errors for bad inputs
with nothing changed, and trust_step set after construction taking effect in the C."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError


def _trackers(name: str, strict: bool = True) -> tuple:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        compiled, numpy = parakin.load(name, backend="compiled"), parakin.load(name, backend="numpy")
    start = compiled.forward_pose(compiled.home_actuated)
    return compiled.tracker(start, strict=strict), numpy.tracker(start, strict=strict), compiled


@pytest.mark.parametrize("name", ["stewart", "planar_3rrr"])
def test_compiled_step_follows_as_the_python_checks(name: str) -> None:
    fast, reference, m = _trackers(name)
    assert fast._step is not None  # the package's library has the step
    rng = np.random.default_rng(5)
    direction = rng.standard_normal(m.home_actuated.shape) * np.maximum(np.abs(m.home_actuated), 0.1) * 2e-3
    steps = 0
    for k in range(40):
        target = m.home_actuated + np.sin(k / 6) * direction
        passive, pose = fast.solve(target)
        expected, expected_pose = reference.solve(target)
        np.testing.assert_allclose(passive, expected, atol=1e-9)
        np.testing.assert_allclose(pose, expected_pose, atol=1e-9)
        assert (fast.mode_change == reference.mode_change).all()
        steps += 1
    assert steps == 40


def test_bad_inputs_are_named_and_change_nothing() -> None:
    fast, reference, m = _trackers("stewart")
    fast.solve(m.home_actuated * 1.001)
    before = fast.actuated.copy(), fast.passive.copy(), fast.pose.copy()
    low = np.array([v.limits[0] for v in m.manifest.actuated], dtype=float)
    bad = [m.home_actuated * np.nan, np.where(np.arange(low.size) == 2, low - 1.0, m.home_actuated), np.ones(7)]
    for value in bad:
        for tracker in (fast, reference):
            with pytest.raises(BadInputError) as raised:
                tracker.solve(value)
        assert str(raised.value)  # named in the user's terms, as the NumPy tracker names it
        for now, then in zip((fast.actuated, fast.passive, fast.pose), before, strict=True):
            np.testing.assert_array_equal(now, then)


def test_trust_step_set_later_reaches_the_c() -> None:
    """A trust_step far below any step flags every step as too coarse, in C as in Python."""
    fast, reference, m = _trackers("planar_3rrr", strict=False)
    fast.trust_step = reference.trust_step = 1e-12
    target = m.home_actuated + 1e-3
    fast.solve(target)
    reference.solve(target)
    assert reference.mode_change[0] != 0
    assert (fast.mode_change == reference.mode_change).all()
