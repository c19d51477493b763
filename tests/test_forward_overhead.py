"""The Python around forward_pose_all's C (issue 33): the shortcuts taken for speed give what the
plain definitions give. Pose repeats (``modes._same_pose_one``, ``modes._repeats_earlier_mode``)
and clusters of overlapping boxes (``certify.cluster_labels``) against double loops over the pairs;
the C certificate's per-thread reused job (``certify._ReusedJob``) against roots known in closed
form, its results never aliased by a later call, nor by another thread's."""

from __future__ import annotations

import threading
from typing import Any

import numpy as np
import pytest

import parakin
from parakin.solvers import certify as certify_module
from parakin.solvers import modes
from parakin.solvers.certify import UNIT, certify_roots_compiled, cluster_labels

MODE, DUPLICATE, OTHER = 0, 7, 3


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.diag(r))


def poses_with_repeats(rng: np.random.Generator, slots: int) -> tuple[np.ndarray, np.ndarray]:
    """Outcomes (slots,) and poses (slots, 4, 4): random poses, some slots repeating an earlier
    slot's pose to 1e-12, some moved only in position or only in rotation (by 1e-6: not one pose)."""
    poses = np.tile(np.eye(4), (slots, 1, 1))
    for s in range(slots):
        poses[s, :3, :3] = random_rotation(rng)
        poses[s, :3, 3] = rng.normal(size=3)
    for s in range(1, slots):
        kind = rng.integers(4)
        source = rng.integers(s)
        if kind == 0:  # a repeat to rounding
            poses[s] = poses[source] + 1e-12 * rng.normal(size=(4, 4))
        elif kind == 1:  # same rotation, position 1e-6 away
            poses[s, :3, :3] = poses[source, :3, :3]
            poses[s, :3, 3] = poses[source, :3, 3] + 1e-6
        elif kind == 2:  # same position, rotation 1e-6 away
            poses[s, :3, 3] = poses[source, :3, 3]
            poses[s, :3, :3] = poses[source, :3, :3] + 1e-6
    outcome = np.where(rng.random(slots) < 0.8, MODE, OTHER).astype(np.int32)
    return outcome, poses


def same_pose_by_pairs(line: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """The rule of ``_same_pose`` written out: slot by slot in order, a mode whose pose equals an
    earlier mode's (rotation entries within SAME_POSE, position within SAME_POSE times the largest
    position coordinate of the input's modes) becomes a duplicate."""
    line = line.copy()
    modes_at = [s for s in range(line.size) if line[s] == MODE]
    largest = max((abs(float(v)) for s in modes_at for v in poses[s, :3, 3]), default=0.0)
    for s in modes_at:
        for t in modes_at:
            if t >= s or line[t] != MODE or line[s] != MODE:
                continue
            moved = max(abs(float(poses[s, i, 3] - poses[t, i, 3])) for i in range(3))
            turned = max(abs(float(poses[s, i, j] - poses[t, i, j])) for i in range(3) for j in range(3))
            if moved <= modes.SAME_POSE * largest and turned <= modes.SAME_POSE:
                line[s] = DUPLICATE
    return line


def test_same_pose_one_equals_the_pairwise_rule() -> None:
    rng = np.random.default_rng(3)
    checked = repeats = 0
    for trial in range(60):
        outcome, poses = poses_with_repeats(rng, int(rng.integers(1, 41)))
        expected = same_pose_by_pairs(outcome, poses)
        line = outcome.copy()
        modes._same_pose_one(line, poses, MODE, DUPLICATE)
        np.testing.assert_array_equal(line, expected, err_msg=f"trial {trial}")
        checked += 1
        repeats += int((expected == DUPLICATE).sum())
    assert checked == 60 and repeats >= 100  # the planted repeats are found, the near ones are not


def test_repeats_earlier_mode_equals_the_pairwise_rule() -> None:
    rng = np.random.default_rng(4)
    found = 0
    for _ in range(40):
        outcome, poses = poses_with_repeats(rng, 24)
        valid = (outcome == MODE)[None]
        columns = rng.choice(24, size=8, replace=False)
        rows = np.zeros(8, dtype=np.int64)
        candidate = poses[columns] + 1e-12 * rng.normal(size=(8, 4, 4))  # each near its own slot's pose
        candidate[::2] = poses[rng.integers(24, size=4)]  # or exactly another slot's
        result = modes._repeats_earlier_mode(valid, poses[None], rows, columns, candidate)
        modes_at = np.nonzero(valid[0])[0]
        for k, column in enumerate(columns):
            largest = max([abs(poses[s, :3, 3]).max() for s in modes_at] + [abs(candidate[k, :3, 3]).max()])
            expected = any(
                abs(poses[s, :3, 3] - candidate[k, :3, 3]).max() <= modes.SAME_POSE * largest
                and abs(poses[s, :3, :3] - candidate[k, :3, :3]).max() <= modes.SAME_POSE
                for s in modes_at
                if s < column
            )
            assert result[k] == expected
            found += int(expected)
    assert found >= 20


def clusters_by_pairs(x: np.ndarray, r: np.ndarray, unique: np.ndarray) -> tuple[list[int], bool]:
    """Connected clusters of boxes that overlap in every coordinate (the margins of
    ``cluster_labels``), by a union of pairs: each certified box's label is its cluster's first
    member, -1 for the others; and whether no two certified boxes overlap."""
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
            gap = abs(x[i] - x[j]) * (1 - 8 * UNIT)
            if not (gap > (r[i] + r[j]) * (1 + 8 * UNIT)).any():
                distinct = False
                a, b = root(i), root(j)
                parent[max(a, b)] = min(a, b)
    return [root(i) if unique[i] else -1 for i in range(count)], distinct


@pytest.mark.parametrize("unknowns", [1, 4, 8])
def test_cluster_labels_equal_a_union_of_overlapping_pairs(unknowns: int) -> None:
    rng = np.random.default_rng(unknowns)
    batch, paths = 30, 12
    x = rng.normal(size=(batch, paths, unknowns)) + 1j * rng.normal(size=(batch, paths, unknowns))
    r = np.full((batch, paths, unknowns), 1e-3)
    # chains of boxes that touch their neighbour only (a transitive cluster), and exact repeats
    for b in range(0, batch, 3):
        x[b, 3] = x[b, 2] + 1.5e-3
        x[b, 4] = x[b, 3] + 1.5e-3 * 1j
        x[b, 7] = x[b, 1]
    x[1, :, 0] = 0.25  # equal in the first coordinate: decided by the others
    unique = rng.random((batch, paths)) < 0.85
    unique[0] = True
    labels, distinct = cluster_labels(x, np.where(unique[..., None], r, 0.0), unique)
    overlapping = 0
    for b in range(batch):
        expected, apart = clusters_by_pairs(x[b], np.where(unique[b][:, None], r[b], 0.0), unique[b])
        assert labels[b].tolist() == expected, b
        assert bool(distinct[b]) == apart
        alone, alone_distinct = cluster_labels(x[b], np.where(unique[b][:, None], r[b], 0.0), unique[b])
        assert alone.tolist() == expected and bool(alone_distinct) == apart  # no batch axis
        overlapping += not apart
    assert overlapping >= 8


@pytest.fixture(scope="module")
def library() -> Any:
    return parakin.load("planar_3rrr", backend="compiled").backend


def quadratic(a: complex) -> tuple:
    """z^2 - a: roots +-sqrt(a), the candidates given 1e-10 away."""
    root = np.sqrt(complex(a))
    return [1.0, -a], [[2], [0]], [0, 0], [[root + 1e-10], [-root - 1e-10]]


def test_reused_certificate_job_gives_each_call_its_own_roots(library: Any) -> None:
    """One system per call reuses this thread's job: each call certifies its own roots (+-sqrt(a),
    real for a > 0, non-real for a < 0), and an earlier call's arrays are not overwritten by a
    later call's."""
    values = [4.0, 9.0, -1.0, 2.0, -16.0, 0.25]
    results = [certify_roots_compiled(library, *quadratic(a)) for a in values]
    for a, result in zip(values, results, strict=True):
        root = np.sqrt(complex(a))
        assert result.unique.all() and int(result.certified_distinct) == 2
        np.testing.assert_allclose(result.center[:, 0], [root, -root], rtol=1e-15, atol=1e-15)
        assert (result.real == (1 if a > 0 else -1)).all()
        assert (result.radii > 0).all() and (result.radii < 1e-6).all()
    # a batch above REUSED_SYSTEMS takes fresh buffers and gives the same boxes, system by system
    batch = [quadratic(a) for a in values]
    together = certify_roots_compiled(
        library, [b[0] for b in batch], batch[0][1], batch[0][2], [b[3] for b in batch]
    )  # fmt: skip
    assert len(values) > certify_module.REUSED_SYSTEMS
    for k, result in enumerate(results):
        np.testing.assert_array_equal(together.center[k], result.center)
        np.testing.assert_array_equal(together.radii[k], result.radii)
        np.testing.assert_array_equal(together.real[k], result.real)


def test_reused_certificate_job_is_per_thread(library: Any) -> None:
    """Two threads certifying at once keep their own buffers: every call's centres are its roots."""
    errors: list[str] = []
    calls = [0, 0]

    def work(index: int, values: list[float]) -> None:
        for _ in range(150):
            for a in values:
                result = certify_roots_compiled(library, *quadratic(a))
                root = np.sqrt(complex(a))
                if not np.allclose(result.center[:, 0], [root, -root], rtol=1e-15, atol=1e-15):
                    errors.append(f"thread {index}, a = {a}: {result.center[:, 0]}")
                calls[index] += 1

    threads = [
        threading.Thread(target=work, args=(0, [4.0, 9.0])),
        threading.Thread(target=work, args=(1, [25.0, -4.0])),
    ]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors, errors[:3]
    assert calls == [300, 300]
