"""``parakin demo`` numbers modes as the mode table does (issue 31 item 16, demo part). At 44aede2
it printed "printed pose 1 (mode 74)" for rus6, which has 40 modes: 74 was the slot, not the mode.
Mode k is ``modes.mode(k)``, row k of the table: the k-th slot that holds a mode, 0 to count - 1."""

from __future__ import annotations

import re
import subprocess
import sys

import numpy as np
import pytest

import parakin
from parakin.interfaces.demo import _forward_example, format_results, run_examples
from parakin.packages.manifest import Example


@pytest.fixture(scope="module")
def spm_modes():
    """spm at its paper example: 8 modes in 16 slots, the first in slot 1 (slot != mode)."""
    m = parakin.load("spm", backend="numpy")
    example = next(e for e in m.manifest.examples if e.actuated is not None)
    modes = m.forward_pose_all(np.asarray(example.actuated, dtype=float))
    slots = np.flatnonzero(modes.valid)
    assert len(modes) == 8 and (slots != np.arange(8)).any()  # the case that tells slots from modes
    return modes


def _example(poses) -> Example:
    return Example("check", "", None, (0.0,), None, {}, {"poses": [np.asarray(p).tolist() for p in poses]}, 1e-9)


def _numbers(comparisons) -> list[int]:
    return [int(re.fullmatch(r"printed pose \d+ \(mode (\d+)\)", c.quantity).group(1)) for c in comparisons]


def test_a_printed_pose_is_matched_to_a_mode_numbered_as_mode_k(spm_modes):
    """Every mode's pose, printed in reverse order: each is found, named by its mode number,
    and that mode (``modes.mode(k)``) is the pose compared."""
    count = len(spm_modes)
    poses = [spm_modes.mode(k).pose for k in reversed(range(count))]
    comparisons = _forward_example(spm_modes, _example(poses))
    assert _numbers(comparisons) == list(reversed(range(count)))  # at 44aede2: slots, up to 14
    for k, comparison in zip(reversed(range(count)), comparisons, strict=True):
        np.testing.assert_array_equal(comparison.ours, spm_modes.mode(k).pose)
        assert comparison.holds


def test_the_mode_number_is_the_row_of_the_printed_table(spm_modes):
    """The demo's table (``mode_table``) lists mode k in row k: the number in the comparison
    line leads to the row with that pose."""
    from parakin.interfaces.demo import mode_table
    from parakin.pose import xyz_euler_deg_from_pose

    rows = mode_table(spm_modes)[3:]
    k = 5
    (comparison,) = _forward_example(spm_modes, _example([spm_modes.mode(k).pose]))
    assert _numbers([comparison]) == [k]
    row = rows[k].split()
    assert row[0] == str(k)
    # a spherical platform's table shows its Z-Y-X angles only (x, y, z are 0 by construction)
    expected = xyz_euler_deg_from_pose(spm_modes.mode(k).pose)[3:]
    np.testing.assert_allclose([float(v) for v in row[1:4]], expected, rtol=1e-5, atol=1e-5)


def test_no_mode_is_said_so_not_a_slot(spm_modes):
    """An input without modes: the printed pose is compared with nothing (it fails), and no
    slot number is shown as a mode."""
    from dataclasses import replace

    empty = replace(spm_modes, valid=np.zeros_like(spm_modes.valid), count=np.int32(0))
    (comparison,) = _forward_example(empty, _example([spm_modes.mode(0).pose]))
    assert comparison.quantity == "printed pose 1 (no mode found)"
    assert not comparison.holds and np.isnan(comparison.ours).all()


def test_every_shipped_demo_numbers_modes_below_the_count():
    """Each cheap mechanism's demo output: every 'mode k' it prints is < that example's count."""
    for name in ("five_bar", "sps", "delta", "planar_3rrr"):
        results = run_examples(name, backend="numpy")
        text = format_results(name, results)
        for result in results:
            if not result.modes:
                continue
            count = len(result.modes) - 3
            for comparison in result.comparisons:
                found = re.search(r"\(mode (\d+)\)", comparison.quantity)
                if found:
                    assert int(found.group(1)) < count, (name, comparison.quantity, count)
        assert "(mode " in text or name == "delta"


def test_rus6_demo_prints_a_mode_number_below_40():
    """The line of the report: rus6 (40 modes in 80 slots) as `parakin demo rus6` prints it (on
    NumPy: about 13 s, where compiling the C library first could take a minute)."""
    done = subprocess.run(
        [sys.executable, "-m", "parakin", "demo", "rus6", "--backend", "numpy"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    numbers = [int(k) for k in re.findall(r"printed pose \d+ \(mode (\d+)\)", done.stdout)]
    assert numbers and "40 assembly modes:" in done.stdout
    assert all(0 <= k < 40 for k in numbers), numbers  # at 44aede2: "mode 74"
