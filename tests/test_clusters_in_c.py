"""The clusters of overlapping certified boxes in C (krawczyk.h's ``kw_clusters``, every homotopy
package's ``NAME_certify_clusters``; issue 33) against the NumPy reference ``cluster_labels`` and a
plain search of the definition: labels and flags bit for bit, on random boxes on a grid (ties
between a gap and the radii's sum, overlapping chains, NaN rows, candidates that are not unique)
and on the certificate's own boxes of a system with known roots."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import parakin
from parakin.solvers.certify import UNIT, certify_roots_compiled, cluster_labels


@pytest.fixture(scope="module")
def library() -> Any:
    backend: Any = parakin.load("planar_3rrr", backend="compiled").backend
    assert backend.certify_clusters is not None
    return backend


def searched(x: np.ndarray, r: np.ndarray, unique: np.ndarray) -> tuple[np.ndarray, bool]:
    """One system's clusters by the definition, a depth-first search over "not apart" pairs."""
    count = unique.size
    near = np.zeros((count, count), bool)
    for p in range(count):
        for q in range(count):
            if p != q and unique[p] and unique[q]:
                gap = np.hypot((x[p] - x[q]).real, (x[p] - x[q]).imag) * (1 - 8 * UNIT)
                near[p, q] = not (gap > (r[p] + r[q]) * (1 + 8 * UNIT)).any()
    labels = np.full(count, -1)
    for p in range(count):
        if unique[p] and labels[p] < 0:
            stack, labels[p] = [p], p
            while stack:
                for q in np.nonzero(near[stack.pop()] & (labels < 0))[0].tolist():
                    labels[q] = p
                    stack.append(q)
    return labels, not near.any()


def test_clusters_in_c_are_the_numpy_reference_bit_for_bit(library: Any) -> None:
    rng = np.random.default_rng(7)
    checked = touching = 0
    for _ in range(400):
        systems, count, n = (int(v) for v in rng.integers(1, [4, 12, 5]))
        # centres and radii on a grid of halves and quarters: many gaps equal to a sum of radii
        x = rng.integers(-3, 4, (systems, count, n)) * 0.5 + 1j * rng.integers(-2, 3, (systems, count, n)) * 0.5
        r = rng.choice([0.0, 0.25, 0.5, 1.0, 0.3], (systems, count, n))
        unique = rng.random((systems, count)) < 0.8
        x[rng.random((systems, count)) < 0.1] = np.nan  # NaN rows, unique or not
        r = np.where(unique[..., None], r, 0.0)
        expected = cluster_labels(x, r, unique)
        labels, distinct = cluster_labels(x, r, unique, library)
        assert labels.dtype == expected[0].dtype == np.int64 and distinct.dtype == np.bool_
        assert np.array_equal(labels, expected[0]) and np.array_equal(distinct, expected[1])
        for s in range(systems):
            plain = searched(x[s], r[s], unique[s])
            assert np.array_equal(labels[s], plain[0]) and bool(distinct[s]) == plain[1]
        checked += systems
        touching += int((~distinct).sum())
    assert checked >= 600 and touching >= 200  # overlapping boxes were exercised
    one = cluster_labels(x[0], r[0], unique[0], library)  # one system: a NumPy bool flag, as the reference
    assert type(one[1]) is type(cluster_labels(x[0], r[0], unique[0])[1]) is np.bool_


def test_repeated_candidates_are_one_cluster(library: Any) -> None:
    # x^2 + y^2 = 5, x y = 2: the four real roots (1, 2), (2, 1), (-1, -2), (-2, -1), each given twice
    roots = np.array([[1, 2], [2, 1], [-1, -2], [-2, -1]], dtype=complex)
    candidates = np.concatenate([roots, roots[::-1] * (1 + 1e-13)])
    exponents, equation = np.array([[2, 0], [0, 2], [0, 0], [1, 1], [0, 0]]), np.array([0, 0, 0, 1, 1])
    c = np.array([1.0, 1.0, -5.0, 1.0, -2.0], dtype=complex)
    result = certify_roots_compiled(library, c, exponents, equation, candidates)
    assert result.unique.all() and result.certified_distinct == 4 and not result.distinct
    assert result.labels is not None and result.labels.tolist() == [0, 1, 2, 3, 3, 2, 1, 0]
    numpy = cluster_labels(result.center, result.radii, result.unique)
    assert np.array_equal(numpy[0], result.labels) and numpy[1] == result.distinct
