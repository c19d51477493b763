"""Two runs of ``tests/completion_census.py`` on the same inputs, compared input by input (issue 33:
"all modes identical to today's on 10^4 inputs per mechanism, certificates at least as often
complete").

    .venv/bin/python tests/census_compare.py before.json after.json
    .venv/bin/python tests/census_compare.py before.json after.json \\
        --modes before_modes.npz after_modes.npz --tolerance 1e-7 --markdown compare.md

prints per entry (mechanism/method/backend) present in both: the inputs compared (the first n
of both runs), certified complete before and after, inputs newly incomplete and newly complete,
inputs whose mode count changed, inputs whose mode set changed (digest of the sorted modes, or
with ``--modes`` the modes themselves matched within ``--tolerance``), re-tracks and median/p90/max
ms before and after. Exit status 1 where an input became incomplete or changed its modes.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np


def turns(difference: np.ndarray) -> np.ndarray:
    """A difference less its nearest whole number of turns (2 pi) where that is smaller."""
    wrapped = difference - 2 * np.pi * np.round(difference / (2 * np.pi))
    return np.where(np.abs(wrapped) < np.abs(difference), wrapped, difference)


def same_modes(first: np.ndarray, second: np.ndarray, tolerance: float) -> bool:
    """Whether two sets of modes, (k, n) NaN-padded rows in any order, are the same within
    ``tolerance`` (max-norm, relative to max(1, |value|), a difference of a whole turn 2 pi in a
    coordinate (an angle) taken as none): equal counts and a one-to-one match."""
    a = first[~np.isnan(first).all(-1)]
    b = second[~np.isnan(second).all(-1)]
    if a.shape != b.shape:
        return False
    unused = list(range(len(b)))
    for row in a:
        scale = np.maximum(1.0, np.abs(row))
        close = [j for j in unused if np.max(np.abs(turns(b[j] - row)) / scale) <= tolerance]
        if not close:
            return False
        unused.remove(close[0])
    return True


def compare_entry(
    before: dict[str, Any],
    after: dict[str, Any],
    modes_before: np.ndarray | None = None,
    modes_after: np.ndarray | None = None,
    tolerance: float = 1e-7,
) -> dict[str, Any]:
    """One entry of each run compared over the inputs both reached."""
    first, second = before["per_input"], after["per_input"]
    n = min(len(first["complete"]), len(second["complete"]))
    complete_before = np.asarray(first["complete"][:n], bool)
    complete_after = np.asarray(second["complete"][:n], bool)
    count_changed = np.asarray(first["count"][:n]) != np.asarray(second["count"][:n])
    if modes_before is not None and modes_after is not None:
        changed = np.array([not same_modes(modes_before[k], modes_after[k], tolerance) for k in range(n)], bool)
    else:
        changed = np.asarray(first["digest"][:n]) != np.asarray(second["digest"][:n])
    ms_before = np.asarray(first["ms"][:n], float)
    ms_after = np.asarray(second["ms"][:n], float)
    return {
        "inputs": n,
        "complete_before": int(complete_before.sum()),
        "complete_after": int(complete_after.sum()),
        "newly_incomplete": np.flatnonzero(complete_before & ~complete_after).tolist(),
        "newly_complete": np.flatnonzero(~complete_before & complete_after).tolist(),
        "count_changed": np.flatnonzero(count_changed).tolist(),
        "modes_changed": np.flatnonzero(changed).tolist(),
        "retracked_before": int(np.sum(first["retracked"][:n])),
        "retracked_after": int(np.sum(second["retracked"][:n])),
        "ms_before": [float(np.median(ms_before)), float(np.percentile(ms_before, 90)), float(ms_before.max())]
        if n
        else [],
        "ms_after": [float(np.median(ms_after)), float(np.percentile(ms_after, 90)), float(ms_after.max())]
        if n
        else [],
        "revision_before": before.get("revision", ""),
        "revision_after": after.get("revision", ""),
    }


def table(rows: dict[str, dict[str, Any]]) -> str:
    """The comparison as a Markdown table, with the first few changed inputs listed under it."""
    lines = [
        "| entry | inputs | complete before | complete after | newly incomplete | modes changed "
        "| count changed | re-tracks before/after | median/p90/max ms before | median/p90/max ms after |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    notes = []
    for key, row in rows.items():
        ms = ["/".join(f"{t:.2f}" for t in row[side]) for side in ("ms_before", "ms_after")]
        lines.append(
            f"| {key} | {row['inputs']} | {row['complete_before']} | {row['complete_after']} "
            f"| {len(row['newly_incomplete'])} | {len(row['modes_changed'])} | {len(row['count_changed'])} "
            f"| {row['retracked_before']}/{row['retracked_after']} | {ms[0]} | {ms[1]} |"
        )
        for name in ("newly_incomplete", "newly_complete", "modes_changed"):
            if row[name]:
                notes.append(f"- {key}: {name.replace('_', ' ')}: inputs {row[name][:10]}")
    return "\n".join(lines + ([""] + notes if notes else [])) + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--modes", nargs=2, type=Path, default=None, help="the two runs' --modes-file")
    parser.add_argument("--tolerance", type=float, default=1e-7)
    parser.add_argument("--markdown", type=Path, default=None, help="also write the table here")
    parser.add_argument("--json", type=Path, default=None, help="also write the comparison here")
    args = parser.parse_args()
    before = json.loads(args.before.read_text())
    after = json.loads(args.after.read_text())
    stored: list[Any] = [None, None]
    if args.modes is not None:
        stored = [np.load(path) for path in args.modes]
    rows = {}
    for key in before:
        if key not in after:
            continue
        name = key.replace("/", "__")
        pair = [None if s is None or name not in s.files else s[name] for s in stored]
        rows[key] = compare_entry(before[key], after[key], pair[0], pair[1], args.tolerance)
    text = table(rows)
    print(text, end="")
    if args.markdown is not None:
        args.markdown.write_text(text)
    if args.json is not None:
        args.json.write_text(json.dumps(rows, indent=1))
    worse = any(row["newly_incomplete"] or row["modes_changed"] for row in rows.values())
    return 1 if worse else 0


if __name__ == "__main__":
    sys.exit(main())
