"""The census's comparison of two runs (tests/census_compare.py, tests/completion_census.py: issue
33's statistics before and after): synthetic runs whose differences are known by construction."""

import numpy as np
from census_compare import compare_entry, same_modes
from completion_census import mode_digest


def entry(complete, count, digest, ms):
    return {
        "per_input": {"complete": complete, "count": count, "digest": digest, "ms": ms, "retracked": [False] * len(ms)}
    }


def test_mode_digest_ignores_order_and_rounding_noise_not_a_moved_mode():
    modes = np.array([[0.1, -2.0, 3.0], [1.5, 0.25, -0.75]])
    digest = mode_digest(modes)
    assert mode_digest(modes[::-1]) == digest
    assert mode_digest(modes * (1 + 1e-13)) == digest  # polishing noise far below the 8 digits kept
    assert mode_digest(modes + [[0, 0, 1e-5], [0, 0, 0]]) != digest
    assert mode_digest(modes[:1]) != digest
    near_zero = np.array([[1e-13, 0.5], [-0.25, 2.0]])  # a coordinate at zero, its sign noise
    assert mode_digest(near_zero) == mode_digest(near_zero * [[-1, 1], [1, 1]])


def test_same_modes_matches_one_to_one_within_tolerance_and_whole_turns():
    a = np.array([[0.1, 1.0], [0.2, 2.0], [np.nan, np.nan]])
    assert same_modes(a, np.array([[0.2, 2.0 + 1e-9], [0.1, 1.0]]), 1e-7)
    assert same_modes(a, np.array([[0.2 - 2 * np.pi, 2.0], [0.1, 1.0 + 4 * np.pi]]), 1e-7)
    assert not same_modes(a, np.array([[0.2, 2.0 + 1e-5], [0.1, 1.0]]), 1e-7)
    assert not same_modes(a, np.array([[0.1, 1.0], [0.1, 1.0]]), 1e-7)  # one mode twice, another lost
    assert not same_modes(a, np.array([[0.1, 1.0]]), 1e-7)


def test_compare_entry_counts_newly_incomplete_and_changed_inputs_over_the_common_prefix():
    before = entry([True, True, False, True], [2, 2, 2, 4], ["a", "b", "c", "d"], [1.0, 2.0, 3.0, 4.0])
    after = entry([True, False, True], [2, 3, 2], ["a", "x", "c"], [0.5, 0.5, 0.5])
    row = compare_entry(before, after)
    assert row["inputs"] == 3
    assert (row["complete_before"], row["complete_after"]) == (2, 2)
    assert row["newly_incomplete"] == [1] and row["newly_complete"] == [2]
    assert row["count_changed"] == [1] and row["modes_changed"] == [1]
    assert row["ms_before"][0] == 2.0 and row["ms_after"][2] == 0.5
