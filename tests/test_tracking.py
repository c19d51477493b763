"""The tracker never changes assembly mode silently: coarse steps along random smooth input paths
are compared with a fine continuation of the same path (40 substeps); wherever the coarse step
ends elsewhere, the tracker has flagged it, and in strict mode it raises and keeps its solution.
Path amplitudes are in units of each mechanism's reach (``_reach``: how far its inputs go from home
and still assemble), so that coarse steps stay inside the workspace on every mechanism."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import parakin
from parakin.pose import wrap_angle
from parakin.studies.sampling import sample_configurations

TRACKED = [n for n in parakin.available() if parakin.metadata(n).passive_names]


def _load(name: str, backend: str) -> parakin.Mechanism:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        return parakin.load(name, backend=backend)


def _scale(m: parakin.Mechanism) -> np.ndarray:
    """The unit of an input path's amplitude: 1 rad, or 0.2 x the actuator's home value."""
    revolute = np.array([v.revolute for v in m.manifest.actuated])
    return np.where(revolute, 1.0, np.abs(m.home_actuated) * 0.2 + 1e-3)


def _reach(m: parakin.Mechanism) -> float:
    """The workspace's extent in the inputs, in units of ``_scale``: the largest of 2, 1, 0.5, ...
    at which 3/4 of 32 random input offsets from home (within the actuator ranges) still assemble
    (forward pose from home). A path amplitude beyond it leaves the workspace at its first step
    (gough, legs of 4-14 m: 0 of 12 coarse paths at 2.0, where delta still assembles 61 of 64)."""
    rng = np.random.default_rng(0)
    offsets = rng.standard_normal((32, m.home_actuated.size)) * _scale(m)
    low, high = (np.array([v.limits[k] for v in m.manifest.actuated]) for k in (0, 1))
    reach = 2.0
    while reach > 2.0**-6:
        actuated = m.home_actuated + reach * offsets
        inside = ((actuated >= low) & (actuated <= high)).all(-1)
        guess = np.broadcast_to(m.home_passive, (int(inside.sum()), m.home_passive.size))
        assembled = np.asarray(m.forward_pose(actuated[inside], guess, strict=False).converged).sum()
        if assembled >= 0.75 * offsets.shape[0]:
            break
        reach /= 2
    return reach


def _paths(m: parakin.Mechanism, count: int, steps: int, amplitude: float, seed: int, reach: float = 2.0):
    """Smooth input paths from sampled configurations (inside the actuator ranges); starts spread
    0.05 (sampling's unit), less in proportion where the reach is under 0.5."""
    rng = np.random.default_rng(seed)
    starts = sample_configurations(m, count, spread=0.05 * min(1.0, reach / 0.5), seed=seed)
    scale = _scale(m)
    low = np.array([v.limits[0] for v in m.manifest.actuated])
    for j in range(starts.actuated.shape[0]):
        a0 = starts.actuated[j]
        direction = rng.standard_normal(a0.shape) * scale * amplitude
        t = np.linspace(0.0, 1.0, steps + 1)[:, None]
        path = a0 + direction * (np.sin(np.pi * t) + 0.3 * np.sin(3 * t))
        if (path >= low).all():
            yield parakin.Configuration(a0, starts.passive[j], starts.pose[j]), path


def _fine(m: parakin.Mechanism, start: parakin.Configuration, a0: np.ndarray, a1: np.ndarray) -> np.ndarray | None:
    """The reference: the same segment in 40 substeps (None where even that changes mode)."""
    try:
        fine = m.tracker(start, strict=False)
        for s in np.linspace(0.0, 1.0, 41)[1:]:
            fine.solve(a0 + s * (a1 - a0))
            if fine.mode_change.any():
                return None
    except parakin.ParakinError:
        return None
    return fine.passive[0].copy()


def _census(
    m: parakin.Mechanism,
    count: int,
    steps: int,
    amplitude: float,
    oracle: parakin.Mechanism | None = None,
    reach: float = 2.0,
) -> dict[str, int]:
    """Coarse steps of m's tracker against the fine continuation of `oracle` (default: m itself;
    the same mechanism on another backend gives the same reference, to 1e-12)."""
    stats = {"steps": 0, "silent": 0, "flagged_changes": 0, "flags": 0}
    for start, path in _paths(m, count, steps, amplitude, seed=5, reach=reach):
        current = start
        for k in range(1, steps + 1):
            reference = _fine(m if oracle is None else oracle, current, path[k - 1], path[k])
            if reference is None:
                break
            coarse = m.tracker(current, strict=False)
            try:
                coarse.solve(path[k])
            except parakin.ParakinError:
                break
            difference = coarse.passive[0] - reference
            difference = np.where(m._angular_passive, wrap_angle(difference), difference)
            changed = np.abs(difference).max() > 1e-6
            flagged = bool(coarse.mode_change[0])
            stats["steps"] += 1
            stats["silent"] += changed and not flagged
            stats["flagged_changes"] += changed and flagged
            stats["flags"] += flagged
            current = parakin.Configuration(path[k], reference, m.platform_pose(path[k], reference))
    return stats


@pytest.mark.parametrize("name", TRACKED)
@pytest.mark.parametrize("backend", ["compiled", "numpy"])
def test_coarse_steps_never_change_mode_silently(name, backend):
    m = _load(name, backend)
    if m.is_architecturally_singular():
        pytest.skip(f"{name}'s default geometry is architecturally singular: no isolated configurations to track")
    # the reference (40 substeps for each coarse step) comes from the compiled tracker on both
    # backends: the NumPy loop is ~10x slower per step, and only its coarse steps are under test
    oracle = _load(name, "compiled")
    # amplitudes in units of the mechanism's own reach (2.0 and 0.6 where the workspace allows)
    reach = _reach(oracle)
    coarse = _census(m, 12, 3, reach, oracle, reach)
    smooth = _census(m, 6, 12, 0.3 * reach, oracle, reach)
    assert coarse["steps"] >= 6 and coarse["steps"] + smooth["steps"] >= 20, (reach, coarse, smooth)
    assert coarse["silent"] == 0 and smooth["silent"] == 0, (coarse, smooth)
    # smooth paths sampled at 12 steps are followed without a flag (almost always)
    assert smooth["flags"] <= max(1, smooth["steps"] // 20), smooth


def test_coarse_steps_are_caught_on_some_mechanism():
    """Not vacuous: coarse steps do leave the branch, and the tracker says so."""
    caught = sum(_census(_load(name, "compiled"), 12, 3, 2.0)["flagged_changes"] for name in ("five_bar", "delta"))
    assert caught >= 5


@pytest.mark.parametrize("backend", ["compiled", "numpy"])
def test_strict_tracker_raises_and_keeps_its_solution(backend):
    m = _load("five_bar", backend)
    raised = 0
    for start, path in _paths(m, 12, 3, 2.0, seed=5):
        tracker = m.tracker(start)
        for k in range(1, path.shape[0]):
            before = tracker.passive.copy()
            try:
                tracker.solve(path[k])
            except parakin.AssemblyModeChangeError as error:
                raised += 1
                assert error.change in ("crossed_singularity", "left_branch", "step_too_coarse")
                np.testing.assert_array_equal(tracker.passive, before)
                break
            except parakin.ParakinError:
                break
    assert raised >= 3


@pytest.mark.parametrize("backend", ["compiled", "numpy"])
def test_a_refused_step_leaves_the_whole_tracker_consistent(backend):
    """A strict refusal and a failed entry in a batch both put every entry back: inputs, solution
    and pose still close the loop, and the advised smaller step then works."""
    m = _load("planar_3rpr", backend)
    start = m.forward_pose(m.home_actuated)
    direction = np.array([1.0, -0.5, 0.3])
    tracker = m.tracker(start)
    with pytest.raises(parakin.AssemblyModeChangeError):
        tracker.solve(m.home_actuated + 1.6 * direction)
    np.testing.assert_array_equal(tracker.actuated[0], m.home_actuated)
    assert np.abs(m.loop_closure(tracker.actuated, tracker.passive)["residual"]).max() < 1e-12
    np.testing.assert_allclose(tracker.pose[0], start.pose, atol=1e-12)
    tracker.solve(m.home_actuated + 0.2 * direction)
    assert tracker.mode_change[0] == 0
    bar = _load("five_bar", backend)
    home = bar.home_actuated
    batch = bar.tracker(bar.forward_pose(np.stack([home, home])))
    with pytest.raises(parakin.ConvergenceError):
        batch.solve(np.stack([home + [0.05, 0.0], home + [1.5, 0.0]]))
    assert np.abs(bar.loop_closure(batch.actuated, batch.passive)["residual"]).max() < 1e-12


@pytest.mark.parametrize("backend", ["compiled", "numpy"])
def test_one_input_gives_one_result_and_a_batch_stays_a_batch(backend):
    """As ``forward_pose`` treats a leading batch axis: a tracker started from one configuration
    and given one input (n_a,) answers one result, (n_p,) and (4, 4); a batch of one, in the
    start or in the input, answers (1, n_p) and (1, 4, 4); three starts given one input answer
    three rows. Every answer is the forward pose by Newton from the same start."""
    m = _load("five_bar", backend)
    n_p = len(m.passive_names)
    home = m.home_actuated
    start = m.forward_pose(home)
    step = home + np.array([0.01, -0.02])
    expected = m.forward_pose(step, guess=start)
    assert expected.passive.shape == (n_p,) and bool(expected.converged)
    cases = [
        (start, step, ()),
        (start, step[None], (1,)),
        (m.forward_pose(home[None]), step, (1,)),
        (m.forward_pose(np.stack([home] * 3)), step, (3,)),
    ]
    for begin, actuated, batch in cases:
        tracker = m.tracker(begin)
        passive, pose = tracker.solve(actuated)
        assert tracker.single == (begin is start)  # started from one configuration
        assert passive.shape == batch + (n_p,) and pose.shape == batch + (4, 4)
        np.testing.assert_allclose(passive, np.broadcast_to(expected.passive, passive.shape), rtol=0, atol=1e-12)
        np.testing.assert_allclose(pose, np.broadcast_to(expected.pose, pose.shape), rtol=0, atol=1e-12)
    # the single result is a view of the tracker's buffers, like the batched one
    tracker = m.tracker(start)
    passive, pose = tracker.solve(step)
    assert np.shares_memory(passive, tracker.passive) and np.shares_memory(pose, tracker.pose)
