"""The tracker's rational predictor (``rational_predict``, generator/runtime/tracker.h's
``predict``) against closed-form paths: exact on a simple pole and on a quadratic where the
cubic Hermite is not, the cubic where the pole lies in the step, Euler without history."""

from __future__ import annotations

import numpy as np
import pytest

from parakin.solvers import path_tracking as tracking


def _points(path, slope, s0, s1):  # type: ignore[no-untyped-def]
    return path(s0), slope(s0), path(s1), slope(s1)


def test_rational_predict_follows_a_simple_pole_exactly() -> None:
    """z_i(s) = c_i / (s - p_i) + b_i with poles just off the real segment (a path passing a
    near-singular point): the rational interpolant of two points and slopes is z itself."""
    rng = np.random.default_rng(11)
    k, n = 50, 3
    c = rng.standard_normal((k, n)) + 1j * rng.standard_normal((k, n))
    b = rng.standard_normal((k, n)) + 1j * rng.standard_normal((k, n))
    s1 = rng.uniform(0.3, 0.9, k)
    s0 = s1 + rng.uniform(0.01, 0.1, k)
    target = s1 - rng.uniform(0.01, 0.1, k)
    # poles beyond the target, 1e-3 .. 1e-1 off the real line
    pole = (target - rng.uniform(0.02, 0.2, k))[:, None] + 1j * rng.uniform(1e-3, 1e-1, (k, n))

    def path(s: np.ndarray) -> np.ndarray:
        return c / (s[:, None] - pole) + b  # type: ignore[no-any-return]

    def slope(s: np.ndarray) -> np.ndarray:
        return -c / (s[:, None] - pole) ** 2  # type: ignore[no-any-return]

    z0, v0, z1, v1 = _points(path, slope, s0, s1)
    history = np.ones(k, bool)
    predicted = tracking.rational_predict(history, s0, z0, v0, s1, z1, v1, target)
    exact = path(target)
    error = np.abs(predicted - exact) / np.abs(exact)
    assert error.max() < 1e-9
    cubic = tracking.hermite_predict(history, s0, z0, v0, s1, z1, v1, target)
    assert (np.abs(cubic - exact) / np.abs(exact)).max() > 1e3 * error.max()  # what the rational gains


def test_rational_predict_is_exact_on_quadratics_and_euler_without_history() -> None:
    rng = np.random.default_rng(12)
    a = rng.standard_normal((3, 20, 2)) + 1j * rng.standard_normal((3, 20, 2))

    def path(s: np.ndarray) -> np.ndarray:
        return a[0] + a[1] * s[:, None] + a[2] * s[:, None] ** 2  # type: ignore[no-any-return]

    def slope(s: np.ndarray) -> np.ndarray:
        return a[1] + 2 * a[2] * s[:, None]  # type: ignore[no-any-return]

    s1 = rng.uniform(0.3, 0.9, 20)
    s0, target = s1 + 0.05, s1 - 0.08
    z0, v0, z1, v1 = _points(path, slope, s0, s1)
    predicted = tracking.rational_predict(np.ones(20, bool), s0, z0, v0, s1, z1, v1, target)
    np.testing.assert_allclose(predicted, path(target), rtol=1e-9, atol=1e-9)
    euler = tracking.rational_predict(np.zeros(20, bool), s0, z0, v0, s1, z1, v1, target)
    np.testing.assert_allclose(euler, z1 + (target - s1)[:, None] * v1, rtol=1e-15, atol=1e-15)


def test_rational_predict_falls_back_to_the_cubic_at_a_pole_in_the_step() -> None:
    """A real pole between s1 and the target: the rational interpolant's denominator vanishes in
    the step, so that unknown takes the cubic Hermite value; the other unknown (pole off the
    step) keeps the rational, exact value."""
    c, pole = np.array([[1.0 + 0.5j, -0.25 + 2j]]), np.array([[0.3 + 0.02j, 0.52 + 0j]])
    s0, s1, target = np.array([0.9]), np.array([0.7]), np.array([0.45])

    def path(s: np.ndarray) -> np.ndarray:
        return c / (s[:, None] - pole)  # type: ignore[no-any-return]

    def slope(s: np.ndarray) -> np.ndarray:
        return -c / (s[:, None] - pole) ** 2  # type: ignore[no-any-return]

    z0, v0, z1, v1 = _points(path, slope, s0, s1)
    history = np.ones(1, bool)
    predicted = tracking.rational_predict(history, s0, z0, v0, s1, z1, v1, target)
    cubic = tracking.hermite_predict(history, s0, z0, v0, s1, z1, v1, target)
    assert predicted[0, 1] == cubic[0, 1]
    np.testing.assert_allclose(predicted[0, 0], path(target)[0, 0], rtol=1e-12)


def _homotopy(name: str, theta: np.ndarray | None, count: int) -> tuple[tracking.System, np.ndarray, float]:
    """The generated homotopy of ``count`` inputs near home (or ``theta``), one path per pair
    where the family has a sign symmetry."""
    import warnings

    import parakin
    from parakin.solvers.modes import _path_table
    from parakin.studies.sampling import sample_configurations

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        m = parakin.load(name, backend="numpy")
    info = m.capabilities.forward
    assert info is not None and info.homotopy is not None
    h = info.homotopy
    if theta is None:
        theta = sample_configurations(m, 3 * count, spread=0.05, seed=5).actuated[:count]
    pairs = tracking.path_pairs(h.exponents, h.equation, h.start)
    start = h.start if pairs is None else h.start[pairs.first]
    system = tracking.sparse_system(_path_table(m, info, theta, 0), h.exponents, h.equation, start.shape[0])
    return system, np.tile(start, (len(theta), 1)), float(m.manifest.tolerances["path_tolerance"])


DIETMAIER = np.array([[1.0, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071]])


def _fewer_steps(monkeypatch: pytest.MonkeyPatch, name: str, theta: np.ndarray | None, count: int) -> int:
    """track_hermite with the rational predictor against the same tracker with the cubic Hermite
    predictor it replaced: the same ends and endpoints, at least 15 % fewer step attempts and 10 %
    fewer evaluations (most steps take one correction either way since the corrector stops after
    one where the path's Newton constant allows: planar_3rrr 15 % fewer), rejections under
    15 %; returns the paths compared."""
    system, start, tolerance = _homotopy(name, theta, count)
    rational = tracking.track_hermite(system, start, tolerance)
    with monkeypatch.context() as patch:
        patch.setattr(tracking, "rational_predict", tracking.hermite_predict)
        cubic = tracking.track_hermite(system, start, tolerance)
    assert (rational.status == cubic.status).all()
    reached = rational.status == tracking.PATH_REACHED
    distance = np.abs(rational.z - cubic.z)[reached].max(-1) / (1 + np.abs(cubic.z[reached]).max(-1))
    assert distance.max() < 1e-8
    assert rational.steps.sum() < 0.85 * cubic.steps.sum()
    assert rational.evaluations.sum() < 0.9 * cubic.evaluations.sum()
    assert rational.rejected.sum() < 0.15 * rational.steps.sum()
    return int(reached.sum())


def test_rational_predictor_takes_fewer_steps_than_the_cubic(monkeypatch: pytest.MonkeyPatch) -> None:
    """12 planar 3-RRR inputs near home (cubic: ~41 step attempts per path, rational ~30)."""
    assert _fewer_steps(monkeypatch, "planar_3rrr", None, 12) >= 40


@pytest.mark.slow
def test_rational_predictor_takes_fewer_steps_on_dietmaier(monkeypatch: pytest.MonkeyPatch) -> None:
    """Dietmaier's 40 modes of the Stewart platform (40 paths, all real endpoints): issue 33
    measured the cubic at 63.2 step attempts and 138 evaluations per path."""
    assert _fewer_steps(monkeypatch, "stewart", DIETMAIER, 1) == 40
