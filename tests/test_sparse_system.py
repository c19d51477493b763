"""parakin.solvers.path_tracking.sparse_system: the value, Jacobian and s-rate of a generated homotopy's sparse
form against a direct term-by-term evaluation and complex finite differences, at random points and
at points with coordinates exactly 0 (where the Jacobian cannot divide by z_i)."""

from __future__ import annotations

import numpy as np

from parakin.solvers.path_tracking import sparse_system


def _direct(table, exponents, equation, inputs, z, s):
    """H(z, s) term by term in plain Python loops (the independent reference)."""
    out = np.zeros(z.shape, dtype=complex)
    for p in range(z.shape[0]):
        coefficient = sum(table[inputs[p], d] * s[p] ** d for d in range(table.shape[1]))
        for t in range(exponents.shape[0]):
            out[p, equation[t]] += coefficient[t] * np.prod(z[p] ** exponents[t])
    return out


def test_values_jacobian_and_rate_match_a_direct_evaluation_and_finite_differences():
    rng = np.random.default_rng(3)
    n, terms, powers, inputs, paths = 4, 23, 3, 2, 3
    exponents = rng.integers(0, 3, size=(terms, n))
    exponents[:n] = np.eye(n, dtype=int) * 2  # every unknown appears
    equation = np.concatenate([np.arange(n), rng.integers(0, n, size=terms - n)])
    table = rng.normal(size=(inputs, powers, terms)) + 1j * rng.normal(size=(inputs, powers, terms))
    system = sparse_system(table, exponents, equation, paths)
    count = inputs * paths
    index = np.arange(count)
    z = rng.normal(size=(count, n)) + 1j * rng.normal(size=(count, n))
    z[1, 2] = 0.0  # exact zeros: the product-of-the-others branch
    z[4, [0, 3]] = 0.0
    s = rng.uniform(0, 1, size=count)
    value, jacobian, rate = system(index, z, s)
    owner = index // paths
    assert np.abs(value - _direct(table, exponents, equation, owner, z, s)).max() < 1e-12
    h = 1e-7
    checked = 0
    for i in range(n):
        step = np.zeros(n, dtype=complex)
        step[i] = h
        plus = _direct(table, exponents, equation, owner, z + step, s)
        minus = _direct(table, exponents, equation, owner, z - step, s)
        assert np.abs(jacobian[:, :, i] - (plus - minus) / (2 * h)).max() < 1e-6
        checked += count
    plus = _direct(table, exponents, equation, owner, z, s + h)
    minus = _direct(table, exponents, equation, owner, z, s - h)
    assert np.abs(rate - (plus - minus) / (2 * h)).max() < 1e-6
    assert checked == n * count
