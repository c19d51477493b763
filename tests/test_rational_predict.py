"""The tracker's rational predictor (``rational_predict``, generator/runtime/tracker.h's
``predict``) against closed-form paths: exact on a simple pole and on a quadratic where the
cubic Hermite is not, the cubic where the pole lies in the step, Euler without history."""

from __future__ import annotations

import numpy as np

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
