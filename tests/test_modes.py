"""forward_pose_all: the generated C pipeline against the same algorithm in NumPy, the
certificate, near-singular inputs with no silent loss, and bounded memory."""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np
import pytest

import parakin
from parakin.studies.sampling import near_singular_configurations, sample_configurations

WITH_MODES = [n for n in parakin.available() if parakin.metadata(n).capabilities.forward is not None]
#: forward pose by a parameter homotopy: ~0.15 s an input on NumPy (a univariate polynomial: ~0.1 ms)
HOMOTOPY = [n for n in WITH_MODES if parakin.metadata(n).capabilities.forward.homotopy is not None]
LEVELS = (1e-4, 1e-6, 1e-8, 1e-10)


def _load(name: str, backend: str) -> parakin.Mechanism:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        return parakin.load(name, backend=backend)


def _inputs(m: parakin.Mechanism, count: int, seed: int) -> np.ndarray:
    """``count`` inputs inside the actuated ranges (the manifest's limits: every solver refuses
    values outside them): closed configurations near home and wide random inputs (many with fewer
    or no modes). A wide draw below a range is reflected into it, one beyond it is drawn again."""
    rng = np.random.default_rng(seed)
    near = sample_configurations(m, count // 2, spread=0.3, seed=seed).actuated
    revolute = np.array([v.revolute for v in m.manifest.actuated])
    scale = np.where(revolute, 1.0, np.abs(m.home_actuated) + 1e-3)
    low, high = (np.array([v.limits[k] for v in m.manifest.actuated]) for k in (0, 1))
    wide = np.zeros((0, revolute.size))
    for _ in range(100):
        missing = count - near.shape[0] - wide.shape[0]
        if missing == 0:
            break
        draw = m.home_actuated + 0.5 * scale * rng.standard_normal((missing, revolute.size))
        draw = np.where(draw < low, 2 * low - draw, draw)  # reflected into the actuator ranges
        wide = np.concatenate([wide, draw[((draw >= low) & (draw <= high)).all(-1)]])
    inputs = np.concatenate([near, wide])
    assert inputs.shape[0] == count, f"{m.name}: only {inputs.shape[0]} of {count} inputs inside the ranges"
    assert ((inputs >= low) & (inputs <= high)).all()
    return inputs


def _check_backends_agree(name: str, count: int) -> None:
    compiled, numpy_m = _load(name, "compiled"), _load(name, "numpy")
    actuated = _inputs(compiled, count, seed=17)
    a = compiled.forward_pose_all(actuated, strict=False)
    b = numpy_m.forward_pose_all(actuated, strict=False)
    assert actuated.shape[0] == count
    np.testing.assert_array_equal(a.count, b.count)
    np.testing.assert_array_equal(a.status, b.status)
    both = a.valid & b.valid
    assert np.abs(a.poses[both] - b.poses[both]).max(initial=0.0) < 1e-8
    # every isolated root is accounted for: a mode or a rejection with its reason
    for modes in (a, b):
        certificate = modes.certificate()
        rejected = sum(certificate["rejected"].values())
        np.testing.assert_array_equal(certificate["roots"], certificate["with_modes"] + rejected)
        expected = np.minimum(modes.real_roots + modes.near_roots + modes.at_infinity, modes.outcome.shape[-1])
        if name in HOMOTOPY:  # every path ends somewhere: also at a complex solution, or failed
            kinds = list(compiled.manifest.abi.root_kinds)
            others = np.isin(modes.root_kind, [kinds.index("complex"), kinds.index("failed")]).sum(-1)
            expected = expected + others
            assert (expected[modes.status != 1] == modes.outcome.shape[-1]).all()
        np.testing.assert_array_equal(certificate["roots"][modes.status != 1], expected[modes.status != 1])


@pytest.mark.parametrize("name", WITH_MODES)
def test_compiled_and_numpy_pipelines_agree_and_account_for_every_root(name):
    """1000 inputs; 100 for a homotopy, 25 for one of more than 16 paths (1000 in the next test)."""
    paths = parakin.load(name, backend="numpy").capabilities.forward.degree
    _check_backends_agree(name, (25 if paths > 16 else 100) if name in HOMOTOPY else 1000)


@pytest.mark.slow
@pytest.mark.parametrize("name", HOMOTOPY)
def test_homotopy_pipelines_agree_on_a_thousand_inputs(name):
    _check_backends_agree(name, 1000)


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n in WITH_MODES if n not in HOMOTOPY])
def test_pipelines_agree_on_ten_thousand_inputs(name):
    """(a homotopy mechanism: the previous test; 10^4 NumPy homotopy inputs take most of an hour)"""
    _check_backends_agree(name, 10_000)


@pytest.mark.parametrize("backend", ["compiled", "numpy"])
def test_the_issue_example_near_a_type_ii_singularity_returns_its_mode(backend):
    """sps, default parameters: these inputs, made by inverse_pose from R, used to give 0 modes."""
    rotation = np.array(
        [
            [0.9499792976117337, -0.26892405960108123, 0.1588054919604204],
            [0.31007873517291756, 0.8728613308892044, -0.37678146853566263],
            [-0.03728957096401976, 0.40717680091822644, 0.912587826289239],
        ]
    )
    m = _load("sps", backend)
    actuated = m.inverse_pose(rotation).actuated[m.inverse_pose(rotation).valid][0]
    np.testing.assert_allclose(actuated, [0.7732693240490566, 0.7718322457078688, 1.889221935461398], atol=1e-12)
    modes = m.forward_pose_all(actuated)
    error = np.abs(modes.poses[..., :3, :3] - rotation).max(axis=(-2, -1))
    # a near-double root: the pose is determined to about sqrt(closure tolerance), and says so
    best = int(np.argmin(np.where(modes.valid, error, np.inf)))
    assert error[best] < 1e-6
    assert modes.conditioning[best] < 1e-6


@pytest.mark.parametrize("name", WITH_MODES)
def test_near_singular_inputs_lose_no_mode_silently(name):
    """Inputs made by inverse pose at poses where the closure Jacobian's normalised determinant is
    1e-4 ... 1e-10: the generating pose is among the modes, or the input is flagged (an
    ill-conditioned mode, a near-real root candidate, or a degenerate status). The generating
    pose is the configuration's own (prs3's inverse reads only height and tilt: the pose asked
    for is not the one reached, which once made this test report modes lost that were not)."""
    m = _load(name, "compiled")
    if m.capabilities.inverse is None:
        pytest.skip("no closed-form inverse to make inputs from poses")
    states, measures = near_singular_configurations(m, LEVELS, 8, seed=5, spread=1.5)
    if states.actuated.shape[0] == 0:
        pytest.skip(f"{name}: no type II crossing between sampled poses (spread 1.5)")
    assert np.abs(m.platform_pose(states.actuated, states.passive) - states.pose).max() < 1e-9
    modes = m.forward_pose_all(states.actuated, strict=False)
    distance = np.abs(modes.poses - states.pose[:, None]).max(axis=(-2, -1))
    found = (np.where(modes.valid, distance, np.inf).min(-1) < 1e-5) & (np.abs(measures) > 0)
    flagged = modes.ill_conditioned(1e-6).any(-1) | (modes.near_roots > 0) | (modes.status != 0)
    # or the input lies just past the fold in floating point: the pose is the real part of a
    # certified non-real pair (imaginary parts ~1e-9 here), never a mode (issue 31, item 3)
    if modes.path_certified is not None:
        complex_code = modes.outcomes.index("complex")
        pair = (modes.outcome == complex_code) & modes.path_certified & (distance < 1e-5)
        flagged |= pair.sum(-1) >= 2
    lost = ~found & ~flagged
    assert not lost.any(), (measures[lost], states.actuated[lost])
    assert states.actuated.shape[0] >= 4


def _count_modes_peak(count: int, chunk: int) -> None:
    """count_modes on `count` inputs in chunks of `chunk`: peak traced memory below 20 kB per
    input of a chunk (measured: about 6.3 kB per input of a chunk, plus the inputs and counts;
    the whole batch at once would take that per input of the batch)."""
    m = _load("spm", "compiled")
    home = m.home_actuated + 0.05 * np.random.default_rng(0).standard_normal((count, 3))
    tracemalloc.start()
    counts = m.count_modes(home, chunk=chunk)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert peak < 20_000 * chunk, peak
    assert counts["count"].shape == (count,) and (counts["count"] > 0).mean() > 0.9


def test_a_hundred_thousand_inputs_in_chunks_stay_under_100_megabytes():
    """The default-run size of the next test: 20 chunks of 5,000 (measured peak ~38 MB; the
    100,000 inputs in one chunk would take ~630 MB)."""
    _count_modes_peak(100_000, 5_000)


@pytest.mark.slow
def test_a_million_inputs_stay_under_a_gigabyte():
    _count_modes_peak(1_000_000, 50_000)


@pytest.mark.parametrize("name", [HOMOTOPY[0], next(n for n in WITH_MODES if n not in HOMOTOPY)])
def test_a_batch_split_over_threads_equals_one_thread(name, monkeypatch):
    """The compiled batch spreads over PARAKIN_THREADS threads (slices of the same buffers):
    bit-equal to one thread, and a bad setting is a named error."""
    from parakin.solvers import modes as modes_module

    m = _load(name, "compiled")
    actuated = _inputs(m, 64, seed=5)
    monkeypatch.setattr(modes_module, "THREAD_PATHS", 1)
    monkeypatch.setattr(modes_module, "THREAD_INPUTS", 1)
    monkeypatch.setenv("PARAKIN_THREADS", "1")
    assert len(modes_module._thread_parts(m, 64)) == 1
    one = m.forward_pose_all(actuated, strict=False)
    monkeypatch.setenv("PARAKIN_THREADS", "3")
    parts = modes_module._thread_parts(m, 64)
    assert len(parts) == 3 and parts[0][0] == 0 and parts[-1][1] == 64
    assert all(a[1] == b[0] for a, b in zip(parts[:-1], parts[1:], strict=True))
    three = m.forward_pose_all(actuated, strict=False)
    for field in ("count", "status", "valid", "outcome", "root_kind"):
        np.testing.assert_array_equal(getattr(one, field), getattr(three, field))
    np.testing.assert_array_equal(np.nan_to_num(one.poses), np.nan_to_num(three.poses))
    assert one.valid.sum() >= 16  # the near-home half has its generating modes
    monkeypatch.setenv("PARAKIN_THREADS", "many")
    with pytest.raises(parakin.errors.BadInputError, match="PARAKIN_THREADS"):
        m.forward_pose_all(actuated, strict=False)
