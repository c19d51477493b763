"""How often the certificate of ``forward_pose_all`` is complete on benign inputs, and how long the
slowest input takes (issue 31, item 4; issue 33's statistics before and after): per shipped
mechanism and homotopy method, inputs near the home (``parakin.studies.sampling.sample_configurations``:
poses spread about the home, their actuated values), one input per call, CPU time.

    .venv/bin/python tests/completion_census.py --inputs 1000
    .venv/bin/python tests/completion_census.py --inputs 100 --mechanisms stewart prs3

prints per row: inputs, complete (share), not complete, re-tracked, median and max time per
input and their ratio; the goal is >= 99.9 % complete and max <= 20 x median. ``--list`` also
prints each input not certified complete (its index in the sample, certified roots, time).

Machine-readable runs, comparable input by input (``tests/census_compare.py``):

    .venv/bin/python tests/completion_census.py --inputs 10000 --mechanisms prs3 \\
        --inputs-file census_inputs.npz --json census.json --modes-file census_modes.npz

``--inputs-file``: the actuated inputs per mechanism are read from this .npz where it holds the
mechanism (so a later run of other code tracks the very same inputs, whatever its sampler gives),
else sampled and added to it. ``--json``: one entry per mechanism, method and backend (merged
into the file's other entries): inputs, certified complete, not complete by reason, re-tracks,
mode-count histogram, median/p90/max ms per input, and per input its mode count, completeness,
re-track, time and a digest of its sorted modes. ``--modes-file``: the modes themselves (passive
values, NaN-padded) per entry, for a comparison with a tolerance. ``--budget`` stops an entry
after that many seconds of CPU time (the entry says how many inputs it reached). ``--table
census.json`` prints a JSON file's entries as a Markdown table; ``--like census.json`` runs
every entry of that file again (its mechanism, method and backend, on as many inputs as it
reached; with ``--mechanisms``, only theirs).

Measured (issue 31, item 4; compiled backend, OPENBLAS_NUM_THREADS=1, a loaded 2-core machine):
rus6 on 1000 inputs 100 % complete (12 re-tracked), median 233 ms, max 1525 ms (6.5 x), and with
--seed 7 100 % (10 re-tracked), 227 ms, 1286 ms (5.7 x); was 98.67 % on 300 with max 75 x median
(roots near infinity uncertified, 7-20 s NumPy re-tracks). Every other shipped homotopy method:
100 % on 300 (or as many as the sampler gives), max <= 3.7 x median.

Issue 33, "before" at 96a3846 (seed 31, 10^4 inputs unless stopped by --budget; compiled backend,
one loaded core): every entry 100 % complete but rus6, 9997 of 10^4 (3 inputs with 4-8 of 80
roots uncertified, 133 re-tracked); stewart 'homotopy' 9 re-tracked, spm 1; modes per input as the
sampler's spread gives (stewart 4-28, prs3 12-16). Entries: planar_3rrr, tricept, prs3, rps3,
five_bar, delta, stewart (homotopy), sam, planar_3rpr, rus6 on 10^4; sps 6619, spm 6533, gough
2007, stewart (automatic) 1932; NumPy backend planar_3rrr and prs3 on 10^3.
"""

from __future__ import annotations

import argparse
import collections
import hashlib
import json
import subprocess
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import parakin
from parakin.studies.sampling import sample_configurations

DECIMALS = 6  # a mode's passive values (m, rad) in its digest: rounded to 1e-6 (modes are polished to 1e-13)


def mode_digest(passive: np.ndarray) -> str:
    """A short digest of a set of modes, (k, n_p) passive values, independent of their order.

    Values are rounded to ``DECIMALS`` decimals (not significant digits: a value near zero must not
    change its digest with its sign), so two runs whose modes agree to 1e-13 give the same digest
    unless a value lies within 1e-13 of a rounding boundary (about one value in 10^6): the digest is
    a quick check, ``tests/census_compare.py --modes`` the comparison within a tolerance."""
    rows = sorted(tuple(round(float(value), DECIMALS) + 0.0 for value in row) for row in passive)
    return hashlib.sha1(repr(rows).encode()).hexdigest()[:16]


def not_complete_reason(certificate: dict[str, Any]) -> str:
    """Why one input's certificate is not complete, in words ("" when it is)."""
    if bool(certificate["complete"]):
        return ""
    if not bool(certificate.get("root_count_proven", True)):
        return "root count not proven"
    certified, count = int(certificate["certified_roots"]), int(certificate["root_count"])
    if certified < count:
        return f"{count - certified} of {count} roots uncertified"
    return "certified roots of undecided realness"


def census_inputs(name: str, inputs: int, seed: int, store: dict[str, np.ndarray]) -> np.ndarray:
    """The actuated inputs of ``name``: from ``store`` where it has them, else sampled (and stored);
    ``inputs`` of them where the sampler gives that many from at most a few times more draws."""
    if name not in store:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = parakin.load(name, backend="numpy")
            count = inputs
            for _ in range(4):  # the sampler drops inputs out of range: ask for more until it gives enough
                theta = sample_configurations(m, count, spread=0.05, seed=seed).actuated
                if len(theta) >= inputs or len(theta) == 0:
                    break
                count = int(np.ceil(1.1 * count * inputs / len(theta)))
            store[name] = theta
    return store[name][:inputs]


def census(
    name: str,
    method: str,
    theta: np.ndarray,
    backend: str,
    listed: bool = False,
    budget: float = float("inf"),
) -> tuple[dict[str, Any], np.ndarray]:
    """One entry: every input of ``theta`` through ``forward_pose_all``; its summary and its modes."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = parakin.load(name, backend=backend)
    counts: list[int] = []
    complete: list[bool] = []
    retracked: list[bool] = []
    reasons: list[str] = []
    times: list[float] = []
    digests: list[str] = []
    found: list[np.ndarray] = []
    if len(theta):  # a first call, untimed: loading the library and first-use caches are not an input's time
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                m.forward_pose_all(theta[0], strict=False, method=method)
            except parakin.errors.ParakinError:
                pass
    begin = time.process_time()
    for index, row in enumerate(theta):
        if time.process_time() - begin > budget:
            break
        start = time.process_time()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                modes = m.forward_pose_all(row, strict=False, method=method)
            certificate = modes.certificate()
        except parakin.errors.ParakinError as error:  # recorded, not fatal: the census goes on
            times.append(time.process_time() - start)
            counts.append(-1)
            complete.append(False)
            retracked.append(False)
            reasons.append(f"error: {type(error).__name__}")
            digests.append("")
            found.append(np.zeros((0, m.home_passive.size)))
            continue
        times.append(time.process_time() - start)
        passive = np.asarray(modes.passive)[np.asarray(modes.valid, bool)]
        counts.append(int(modes.count))
        complete.append(bool(certificate["complete"]))
        retracked.append(bool(certificate.get("retracked", False)))
        reasons.append(not_complete_reason(certificate))
        digests.append(mode_digest(passive))
        found.append(passive)
        if listed and not complete[-1]:
            print(f"  {name} {method} input {index}: {reasons[-1]}, {times[-1]:.2f} s", flush=True)
    ms = 1e3 * np.asarray(times)
    width = max([len(p) for p in found] + [1])
    padded = np.full((len(found), width, m.home_passive.size), np.nan)
    for k, passive in enumerate(found):
        padded[k, : len(passive)] = passive
    entry = {
        "mechanism": name,
        "method": method,
        "backend": backend,
        "inputs": len(times),
        "inputs_requested": len(theta),
        "complete": int(sum(complete)),
        "not_complete": dict(collections.Counter(r for r in reasons if r)),
        "retracked": int(sum(retracked)),
        "mode_counts": {str(k): v for k, v in sorted(collections.Counter(counts).items())},
        "median_ms": float(np.median(ms)) if len(ms) else float("nan"),
        "p90_ms": float(np.percentile(ms, 90)) if len(ms) else float("nan"),
        "max_ms": float(ms.max()) if len(ms) else float("nan"),
        "cpu_s": float(sum(times)),
        "per_input": {
            "count": counts,
            "complete": complete,
            "retracked": retracked,
            "reason": reasons,
            "ms": [round(float(t), 4) for t in ms],
            "digest": digests,
        },
    }
    return entry, padded


def entry_key(name: str, method: str, backend: str) -> str:
    return f"{name}/{method}/{backend}"


def revision() -> str:
    """The checkout's commit (with '+dirty' for uncommitted changes under parakin/ or generated/)."""
    root = Path(parakin.__file__).resolve().parent.parent
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--", "parakin", "generated", "generator"],
            cwd=root,
            capture_output=True,
            text=True,
        ).stdout.strip()
    except OSError:
        return "unknown"
    return head + ("+dirty" if dirty else "")


def markdown(entries: dict[str, Any]) -> str:
    """A census JSON file's entries as a Markdown table (per input statistics left out)."""
    lines = [
        "| mechanism | method | backend | inputs | certified complete | not complete (why) | re-tracked "
        "| modes per input: inputs | median ms | p90 ms | max ms | revision |",
        "|---|---|---|---:|---:|---|---:|---|---:|---:|---:|---|",
    ]
    for entry in entries.values():
        share = entry["complete"] / max(entry["inputs"], 1)
        why = ", ".join(f"{count} {reason}" for reason, count in entry["not_complete"].items()) or "-"
        histogram = ", ".join(f"{k}: {v}" for k, v in entry["mode_counts"].items())
        reached = "" if entry["inputs"] == entry["inputs_requested"] else f" of {entry['inputs_requested']}"
        lines.append(
            f"| {entry['mechanism']} | {entry['method']} | {entry['backend']} | {entry['inputs']}{reached} "
            f"| {entry['complete']} ({share:.2%}) | {why} | {entry['retracked']} | {histogram} "
            f"| {entry['median_ms']:.2f} | {entry['p90_ms']:.2f} | {entry['max_ms']:.1f} | {entry['revision'][:7]} |"
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--inputs", type=int, default=200)
    parser.add_argument("--seed", type=int, default=31)
    parser.add_argument("--backend", default="compiled")
    parser.add_argument("--mechanisms", nargs="*", default=None)
    parser.add_argument("--methods", nargs="*", default=None, help="only these homotopy methods")
    parser.add_argument("--list", action="store_true", help="print each input not certified complete")
    parser.add_argument("--inputs-file", type=Path, default=None, help=".npz of actuated inputs per mechanism")
    parser.add_argument("--json", type=Path, default=None, help="merge the entries into this JSON file")
    parser.add_argument("--modes-file", type=Path, default=None, help=".npz of the modes per entry")
    parser.add_argument("--budget", type=float, default=float("inf"), help="CPU seconds per entry at most")
    parser.add_argument("--table", type=Path, default=None, help="print this JSON file's entries as Markdown, run none")
    parser.add_argument("--like", type=Path, default=None, help="run every entry of this census JSON file again")
    args = parser.parse_args()
    if args.table is not None:
        print(markdown(json.loads(args.table.read_text())), end="")
        return
    store: dict[str, np.ndarray] = {}
    if args.inputs_file is not None and args.inputs_file.exists():
        with np.load(args.inputs_file) as saved:
            store = {key: saved[key] for key in saved.files}
    print(f"{'mechanism':12s} {'method':10s} {'inputs':>6s} {'complete':>9s} {'retracked':>9s} "
          f"{'median ms':>9s} {'p90 ms':>8s} {'max ms':>8s} {'max/med':>7s}")  # fmt: skip
    jobs: list[tuple[str, str, str, int]] = []  # mechanism, method, backend, inputs
    if args.like is not None:  # every entry of an earlier run, on as many inputs as it reached
        for entry in json.loads(args.like.read_text()).values():
            if args.mechanisms is None or entry["mechanism"] in args.mechanisms:
                jobs.append((entry["mechanism"], entry["method"], entry["backend"], entry["inputs"]))
    else:
        for name in args.mechanisms or parakin.available():
            methods = parakin.load(name, backend="numpy").capabilities.forward_methods
            jobs += [(name, k, args.backend, args.inputs) for k, info in methods.items() if info.homotopy is not None]
    for name, method, backend, inputs in jobs:
        if args.methods and method not in args.methods:
            continue
        sampled = name not in store
        theta = census_inputs(name, inputs, args.seed, store)
        if args.inputs_file is not None and sampled:  # the file is only ever added to
            np.savez(args.inputs_file, **dict[str, Any](store))
        entry, padded = census(name, method, theta, backend, args.list, args.budget)
        entry["seed"] = args.seed
        entry["revision"] = revision()
        entry["date"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        share = entry["complete"] / max(entry["inputs"], 1)
        print(
            f"{name:12s} {method:10s} {entry['inputs']:6d} {share:9.2%} {entry['retracked']:9d} "
            f"{entry['median_ms']:9.2f} {entry['p90_ms']:8.2f} {entry['max_ms']:8.1f} "
            f"{entry['max_ms'] / entry['median_ms']:7.1f}",
            flush=True,
        )
        key = entry_key(name, method, backend)
        if args.json is not None:
            merged = json.loads(args.json.read_text()) if args.json.exists() else {}
            merged[key] = entry
            args.json.write_text(json.dumps(merged, indent=1))
        if args.modes_file is not None:
            modes: dict[str, np.ndarray] = {}
            if args.modes_file.exists():
                with np.load(args.modes_file) as saved:
                    modes = {k: saved[k] for k in saved.files}
            modes[key.replace("/", "__")] = padded
            np.savez_compressed(args.modes_file, **dict[str, Any](modes))


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
