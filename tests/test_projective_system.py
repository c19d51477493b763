"""``parakin.solvers.projective.family_system`` (the re-tracks' evaluation of a family over its
distinct monomials) against ``parakin.solvers.path_tracking.sparse_system`` (term by term) and against
central finite differences of itself in z and s, on rus6's projective family and a random one."""

from __future__ import annotations

import numpy as np
import pytest

from parakin.solvers.path_tracking import path_pairs, sparse_system
from parakin.solvers.projective import family_system, projective_family, projective_table, to_projective


def _random_family(seed: int):
    rng = np.random.default_rng(seed)
    n, per_equation = 4, 9
    exponents = rng.integers(0, 3, size=(n * per_equation, n))
    equation = np.repeat(np.arange(n), per_equation)
    shape = (12, 4, exponents.shape[0])  # more inputs than family_system groups one by one
    table = rng.normal(size=shape) + 1j * rng.normal(size=shape)
    return table, exponents, equation


def _rus6_family():
    import warnings

    import parakin
    from parakin.solvers import modes

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = parakin.load("rus6", backend="numpy")
    info = m.capabilities.forward
    homotopy = info.homotopy
    table = modes._path_table(m, info, np.stack([m.home_actuated, m.home_actuated + 0.01]), 1)
    family = projective_family(
        homotopy.exponents, homotopy.equation, path_pairs(homotopy.exponents, homotopy.equation, homotopy.start)
    )
    start = to_projective(family, homotopy.alternative)
    return projective_table(family, table), family.exponents, family.equation, start


@pytest.mark.parametrize("case", ["random", "rus6"])
def test_family_system_equals_the_term_by_term_system_and_its_finite_differences(case):
    rng = np.random.default_rng(7)
    if case == "random":
        table, exponents, equation = _random_family(3)
        z = rng.normal(size=(12, exponents.shape[1])) + 1j * rng.normal(size=(12, exponents.shape[1]))
        z[0, 1] = 0.0  # a coordinate at 0: no division anywhere
    else:
        table, exponents, equation, start = _rus6_family()
        z = np.concatenate([start, start[:8] * (1 + 0.2j)])
    rows = np.arange(z.shape[0])
    paths = -(-z.shape[0] // table.shape[0])
    # every input grouping: all paths of one input, of a few, of each input (12: more than
    # GROUPED_INPUTS for the random family)
    for per_input, index in ((z.shape[0], rows), (paths, rows), (1, rows % table.shape[0])):
        assert index.max() // per_input < table.shape[0]
        s = rng.uniform(0, 1, z.shape[0])
        fast = family_system(table, exponents, equation, per_input)(index, z, s)
        slow = sparse_system(table, exponents, equation, per_input)(index, z, s)
        for a, b in zip(fast, slow, strict=True):
            assert np.abs(a - b).max() <= 1e-12 * max(1.0, np.abs(b).max())
    # H_z and H_s against central differences of H itself
    system = family_system(table, exponents, equation, z.shape[0])
    index, s, h = np.arange(z.shape[0]), rng.uniform(0.1, 0.9, z.shape[0]), 1e-6
    value, jacobian, rate = system(index, z, s)
    ds = (system(index, z, s + h)[0] - system(index, z, s - h)[0]) / (2 * h)
    assert np.abs(ds - rate).max() <= 1e-6 * max(1.0, np.abs(rate).max())
    for i in range(z.shape[1]):
        step = np.zeros(z.shape[1], complex)
        step[i] = h
        dz = (system(index, z + step, s)[0] - system(index, z - step, s)[0]) / (2 * h)
        assert np.abs(dz - jacobian[:, :, i]).max() <= 1e-6 * max(1.0, np.abs(jacobian).max())
