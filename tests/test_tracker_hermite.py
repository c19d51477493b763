"""The path tracker at its floor (issue 33): the cubic Hermite interpolant, which the predictor
falls back to (the predictor is rational, quadratic over linear through the last two points and
slopes, and takes the cubic where that has a pole near the step: ``rational_predict``,
generator/runtime/tracker.h's ``predict``; tests/test_rational_predict.py checks it), the NumPy
reference ``track_hermite`` against the Runge-Kutta tracker ``track`` (an independent algorithm)
and against the generated C driver (the same algorithm: equal endpoints and equal work), the C
tracker's work per path on Dietmaier's 40 modes, and the modes the C pipeline finds against the
NumPy pipeline (which tracks with ``track``) on random inputs near home."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import parakin
from parakin.packages.compiled import CompiledBackend
from parakin.solvers import path_tracking as homotopy
from parakin.solvers.modes import _path_table, _start_rows, compiled_modes, first_instances
from parakin.studies.sampling import sample_configurations

DIETMAIER = np.array([1.0, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071])


def _load(name: str, backend: str) -> parakin.Mechanism:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        return parakin.load(name, backend=backend)


def _system(m: parakin.Mechanism, theta: np.ndarray) -> tuple[homotopy.System, np.ndarray]:
    """The generated homotopy of the inputs theta (k, n_a) from each input's own start (the one
    near home where it is near home, as the C driver chooses), its start solutions per input."""
    info = m.capabilities.forward
    assert info is not None and info.homotopy is not None
    h = info.homotopy
    instance = first_instances(m, info, theta)
    table = _path_table(m, info, theta, instance)
    start = _start_rows(h, instance).reshape(-1, h.start.shape[1])
    return homotopy.sparse_system(table, h.exponents, h.equation, h.start.shape[0]), start


def test_hermite_predict_is_exact_on_cubics() -> None:
    """The cubic Hermite interpolant of two points of a cubic path reproduces it anywhere (here
    beyond both points, as a step extrapolates); Euler reproduces a straight path."""
    rng = np.random.default_rng(3)
    a = rng.standard_normal((4, 5, 3)) + 1j * rng.standard_normal((4, 5, 3))

    def path(s: np.ndarray) -> np.ndarray:  # (k,) -> (k, 3): a_0 + a_1 s + a_2 s^2 + a_3 s^3
        return sum(a[k] * s[:, None] ** k for k in range(4))  # type: ignore[no-any-return]

    def slope(s: np.ndarray) -> np.ndarray:
        return sum(k * a[k] * s[:, None] ** (k - 1) for k in range(1, 4))  # type: ignore[no-any-return]

    s0, s1 = rng.uniform(0.5, 1.0, 5), rng.uniform(0.2, 0.5, 5)
    target = s1 - rng.uniform(0.0, 0.3, 5)
    history = np.ones(5, bool)
    predicted = homotopy.hermite_predict(history, s0, path(s0), slope(s0), s1, path(s1), slope(s1), target)
    np.testing.assert_allclose(predicted, path(target), rtol=1e-11, atol=1e-11)
    a[2:] = 0  # a straight path: Euler without history is exact
    euler = homotopy.hermite_predict(~history, s0, path(s0), slope(s0), s1, path(s1), slope(s1), target)
    np.testing.assert_allclose(euler, path(target), rtol=1e-12, atol=1e-12)


def test_track_hermite_ends_where_runge_kutta_ends() -> None:
    """track_hermite and the Runge-Kutta track (another predictor, another step control) reach the
    same endpoints on planar_3rrr's and prs3's paths, with fewer Newton evaluations per path than
    track's four velocity solves and up to three corrections per step."""
    checked = 0
    for name, count in (("planar_3rrr", 6), ("prs3", 2)):
        m = _load(name, "compiled")
        theta = sample_configurations(m, 3 * count, spread=0.1, seed=7).actuated[:count]
        system, start = _system(m, theta)
        new = homotopy.track_hermite(system, start, 1e-7)
        old = homotopy.track(system, start, 1e-7)
        both = (new.status == homotopy.PATH_REACHED) & (old.status == homotopy.PATH_REACHED)
        assert both.mean() > 0.9
        distance = np.abs(new.z[both] - old.z[both]).max(-1) / (1 + np.abs(old.z[both]).max(-1))
        assert distance.max() < 1e-8, name
        assert np.mean(new.rejected) / np.mean(new.steps) < 0.15
        # each of track's steps costs at least four LUs (Runge-Kutta) and one correction
        assert new.evaluations.mean() < 5 * old.steps.mean()
        checked += int(both.sum())
    assert checked >= 100


def test_c_tracker_is_the_numpy_reference() -> None:
    """The generated C driver's tracker and track_hermite on Dietmaier's 40 paths: the same
    endpoints, the same step attempts and rejections, and the same evaluations but for the
    refinement's last rounding-level iterations (the C counts them)."""
    m = _load("stewart", "compiled")
    backend = m.backend
    assert isinstance(backend, CompiledBackend)
    with backend.counting() as counts:
        out = compiled_modes(m, DIETMAIER[None])
    ends = out["endpoints"][0, ..., 0] + 1j * out["endpoints"][0, ..., 1]
    system, start = _system(m, DIETMAIER[None])
    reference = homotopy.track_hermite(system, start, float(m.manifest.tolerances["path_tolerance"]))
    assert (reference.status == homotopy.PATH_REACHED).all()
    assert counts.paths == 40  # no failed path, so no second start system
    distance = np.abs(ends - reference.z).max(-1) / (1 + np.abs(reference.z).max(-1))
    assert distance.max() < 1e-9
    assert counts.steps == reference.steps.sum()
    assert counts.rejected == reference.rejected.sum()
    # the start's slope is one more evaluation per path in both; the refinement at s = 0 stops
    # where the updates reach rounding, which LAPACK's LU and the C LU reach an iteration apart
    # on a few paths
    assert abs(counts.evaluations - reference.evaluations.sum()) <= 0.01 * counts.evaluations
    assert counts.evaluations == counts.factorisations
    # the refinement stops where quadratic convergence puts the error left below REFINE_ERROR
    # (1e-12): LAPACK's Newton update at each C endpoint, far inside what the mode assembly
    # separates (real_endpoint 1e-8, duplicate 1e-7)
    value, jacobian, _ = system(np.arange(40), ends, np.zeros(40))
    update = np.abs(np.linalg.solve(jacobian, value[..., None])[..., 0]).max(-1) / (1 + np.abs(ends).max(-1))
    assert update.max() < 1e-10


def test_c_tracker_work_per_path_on_dietmaier() -> None:
    """The floor's measures on Dietmaier's 40 modes (Stewart's home: its paths begin at the start
    near home): under 28 LU factorisations per path where the Runge-Kutta tracker made 253, the
    two-correction Hermite tracker 113, the one-correction corrector 98 from the first start and
    31.5 from the near start before the step's goal took omega into account (issue 33); under 15 %
    of the step attempts rejected (22 % before: the final steps from s ~ 0.25, where the paths'
    Newton constant grows); all 40 modes, the certificate complete."""
    m = _load("stewart", "compiled")
    backend = m.backend
    assert isinstance(backend, CompiledBackend)
    with backend.counting() as counts:
        modes = m.forward_pose_all(DIETMAIER, strict=False)
    assert int(modes.count) == 40
    assert bool(np.all(modes.certificate()["complete"]))
    assert counts.rejected < 0.15 * counts.steps
    assert counts.factorisations < 28 * counts.paths


def _same_modes(name: str, count: int, seed: int) -> tuple[int, int, float, float]:
    """Inputs near home whose modes (poses) differ between the C pipeline (track_hermite's
    algorithm) and the NumPy pipeline (``track``); inputs checked; each's complete-certificate rate."""
    compiled, numpy = _load(name, "compiled"), _load(name, "numpy")
    # sampled configurations that close are fewer than the samples (stewart: ~27 % at spread 0.3)
    theta = sample_configurations(compiled, 5 * count, spread=0.3, seed=seed).actuated[:count]
    ours, theirs = compiled.forward_pose_all(theta, strict=False), numpy.forward_pose_all(theta, strict=False)
    differ = 0
    for i in range(len(theta)):
        a, b = ours.poses[i][ours.valid[i]], theirs.poses[i][theirs.valid[i]]
        same = a.shape == b.shape and all((np.abs(a - pose).max(axis=(-2, -1)) < 1e-6).any() for pose in b)
        differ += not same
    rate = [float(np.mean(r.certificate()["complete"])) for r in (ours, theirs)]
    return differ, len(theta), rate[0], rate[1]


@pytest.mark.parametrize(("name", "count"), [("planar_3rrr", 20), ("prs3", 3)])
def test_modes_as_the_runge_kutta_pipeline(name: str, count: int) -> None:
    """A few inputs per family: the same modes as the NumPy pipeline, certificates as complete."""
    differ, checked, ours, theirs = _same_modes(name, count, seed=31)
    assert checked >= count
    assert differ == 0
    assert ours >= theirs


@pytest.mark.slow
@pytest.mark.parametrize(("name", "count"), [("stewart", 1000), ("prs3", 1000), ("planar_3rrr", 1000), ("rus6", 60)])
def test_modes_as_the_runge_kutta_pipeline_many(name: str, count: int) -> None:
    """>= 1000 inputs near home (60 for rus6, 2 s each in NumPy): the same modes as the NumPy
    pipeline, and certificates complete at least as often."""
    differ, checked, ours, theirs = _same_modes(name, count, seed=47)
    assert checked >= 0.9 * count
    assert differ == 0
    assert ours >= theirs


# rps3 at spread 0.5 (sample_configurations(seed=23), input 7037 of 10^4): four symmetric paths
# run to a far endpoint (|z| ~ 5e3) whose H_z has condition ~1e14, and their Newton updates near
# s = 0 wander along the path by rounding (1e-5 of |z| at s = 7e-5, across it 1e-13): the
# tracker accepts such a step by the updates across the path (ACROSS_NOISE; issue 33)
RPS3_FAR = np.array([1.602715774784246, 0.9912383960712283, 0.9392043964066665])


def _exact_root(table: np.ndarray, exponents: np.ndarray, equation: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The root of the target system (the coefficients ``table`` (terms,) at s = 0) that Newton
    in 40-digit arithmetic (mpmath) reaches from z, to 1e-25."""
    import mpmath

    with mpmath.workdps(40):
        c = [mpmath.mpc(complex(x)) for x in table]
        n = exponents.shape[1]
        point = mpmath.matrix([mpmath.mpc(complex(x)) for x in z])
        for _ in range(20):
            value, jacobian = mpmath.matrix(n, 1), mpmath.matrix(n, n)
            for t, (e, k) in enumerate(zip(exponents.tolist(), equation.tolist(), strict=True)):
                powers = [point[i] ** e[i] for i in range(n)]
                value[k] += c[t] * mpmath.fprod(powers)
                for i in range(n):
                    if e[i]:
                        rest = [point[j] ** (e[j] - (j == i)) for j in range(n)]
                        jacobian[k, i] += c[t] * e[i] * mpmath.fprod(rest)
            update = mpmath.lu_solve(jacobian, value)
            point -= update
            if mpmath.norm(update, mpmath.inf) < 1e-25 * (1 + mpmath.norm(point, mpmath.inf)):
                return np.array([complex(x) for x in point])
    raise AssertionError("Newton in 40 digits did not converge")


def test_tracker_reaches_far_ill_conditioned_roots() -> None:
    """RPS3_FAR's 32 paths all reach s = 0, in the NumPy reference and in the C driver (before
    ACROSS_NOISE four stalled at s ~ 7e-5, and the re-tracks too); the four far endpoints each lie
    within 1e-3 of |z| of a root that 40-digit Newton confirms (the double-precision floor there:
    H_z's condition ~1e14), four distinct roots (apart by 4 % of |z|: no two paths on one)."""
    m = _load("rps3", "compiled")
    info = m.capabilities.forward
    assert info is not None and info.homotopy is not None
    theta = RPS3_FAR[None]
    system, start = _system(m, theta)
    reference = homotopy.track_hermite(system, start, float(m.manifest.tolerances["path_tolerance"]))
    assert (reference.status == homotopy.PATH_REACHED).all()
    out = compiled_modes(m, theta)
    ends = out["endpoints"][0, ..., 0] + 1j * out["endpoints"][0, ..., 1]
    table = _path_table(m, info, theta, first_instances(m, info, theta))[0, 0]
    far = np.nonzero(np.abs(reference.z).max(-1) > 1e3)[0]
    assert far.size == 4
    roots = np.array([_exact_root(table, info.homotopy.exponents, info.homotopy.equation, reference.z[p]) for p in far])
    scale = 1 + np.abs(roots).max(-1)
    apart = np.abs(roots[:, None] - roots[None]).max(-1) / scale[:, None] + np.eye(4)
    assert apart.min() > 0.03
    for found in (reference.z[far], ends[far]):
        assert (np.abs(found - roots).max(-1) / scale < 1e-3).all()
