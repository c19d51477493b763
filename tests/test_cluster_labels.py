"""``certify.cluster_labels`` (the clusters of overlapping certified boxes every certificate
counts) against a plain pairwise reference with union-find: boxes overlap where they overlap in
every coordinate (with the rounding margins), a cluster is a connected set of overlapping
boxes and is labelled by its smallest index. The test walks the coordinates until every pair is
apart, so the cases include pairs apart only in the last coordinate, overlapping chains,
boxes that are not certified (NaN centres) and batches of several inputs."""

from __future__ import annotations

import numpy as np

from parakin.solvers.certify import UNIT, cluster_labels

#: random batches checked (each of several inputs)
CASES = 60


def reference(x: np.ndarray, r: np.ndarray, unique: np.ndarray) -> tuple[np.ndarray, bool]:
    """Labels (P,) and disjointness of one input's boxes, pair by pair in Python."""
    count = unique.size
    parent = list(range(count))

    def root(i: int) -> int:
        while parent[i] != i:
            i = parent[i]
        return i

    distinct = True
    for i in range(count):
        for j in range(i + 1, count):
            if not (unique[i] and unique[j]):
                continue
            gap = np.abs(x[i] - x[j]) * (1 - 8 * UNIT)
            if not (gap > (r[i] + r[j]) * (1 + 8 * UNIT)).any():
                distinct = False
                a, b = root(i), root(j)
                parent[max(a, b)] = min(a, b)
    labels = np.array([min(k for k in range(count) if root(k) == root(i)) if unique[i] else -1 for i in range(count)])
    return labels, distinct


def test_cluster_labels_match_a_pairwise_reference():
    rng = np.random.default_rng(7)
    checked = overlapping = last_only = 0
    for case in range(CASES):
        inputs, paths, size = 3, int(rng.integers(2, 12)), int(rng.integers(1, 6))
        # centres on a coarse grid so that boxes often share coordinates and some overlap
        x = rng.integers(0, 3, (inputs, paths, size)) + 1j * rng.integers(0, 2, (inputs, paths, size))
        x = x.astype(complex)
        r = rng.choice([0.1, 0.6], (inputs, paths, size))
        unique = rng.random((inputs, paths)) < 0.85
        if case % 5 == 0 and paths >= 2 and size >= 2:  # a pair apart only in its last coordinate
            x[0, 1] = x[0, 0]
            x[0, 1, -1] += 5.0
            unique[0, :2] = True
            last_only += 1
        x = np.where(unique[..., None], x, np.nan)
        radii = np.where(unique[..., None], r, 0.0)
        labels, distinct = cluster_labels(x, radii, unique)
        for i in range(inputs):
            expected, alone = reference(x[i], radii[i], unique[i])
            np.testing.assert_array_equal(labels[i], expected)
            assert bool(distinct[i]) == alone
            overlapping += not alone
            checked += 1
    assert checked == CASES * 3 and overlapping >= 30 and checked - overlapping >= 30 and last_only >= 10
