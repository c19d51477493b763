"""The adversarial census of issue 31: every certificate of ``forward_pose_all`` held to the exact
oracle of tests/oracle_modes.py, on random geometries and near-fold inputs, at the scales 1e-3, 1
and 1e3, on both backends.

    .venv/bin/python tests/adversarial_census.py --inputs 200
    .venv/bin/python tests/adversarial_census.py --inputs 60 --mechanisms planar_3rrr --backends compiled

prints one row per mechanism x backend x scale: inputs checked, those the oracle decides
(``usable``: not exactly on a fold, a count robust to the rounding of the inputs, and where the
solver disagrees, a count that does not change within a relative 1e-12 of the input), those left
out because the solver disagrees within that distance of a fold (``at a fold``: a double-precision
certificate proves the roots of its rounded coefficients), certificates
complete, false complete (complete, but the listed modes are not the oracle's: a count differs or
a pose is more than TOLERANCE off in the best one-to-one pairing), modes missing and extra modes
in complete certificates (no counterpart within LOOSE), complete certificates wrong only by the
accuracy of a pose (between TOLERANCE and LOOSE, counts equal), certificates not complete,
spurious modes listed by certificates not complete (a mode that is no real root is wrong whatever
the certificate says), and the time per input (median and max, one input per call). Then the same
counts by kind of input (random, and each step off a fold), and the inputs of the first false
certificates, written so that they can be pasted (floats as ``float.hex`` too).

The harness (``corpus``, ``check``) is what tests/test_certificate_adversarial.py runs on a
smaller corpus. It calls the solver under test; the oracle it compares with does not.
"""

from __future__ import annotations

import argparse
import math
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import oracle_modes as om  # noqa: E402

#: the largest distance of a listed mode from its oracle mode: positions relative to the
#: geometry's size (its largest length parameter), angles in radians
TOLERANCE = 1e-6
#: a mode further than this from every listed mode is missing (and a listed mode this far from
#: every oracle mode is extra); between TOLERANCE and LOOSE a pose is inaccurate
LOOSE = 1e-4
SCALES = (1e-3, 1.0, 1e3)
BACKENDS = ("numpy", "compiled")
MECHANISMS = ("planar_3rrr", "planar_3rpr", "five_bar", "linear_delta")
FIXTURES = Path(__file__).resolve().parent / "fixtures"
#: mechanisms that are not shipped: generated from a fixture file for the run
GENERATED = {"linear_delta": FIXTURES / "linear_delta.py"}


@dataclass(frozen=True)
class Case:
    """One input at the metre scale: its geometry's seed, its kind (``random``, or ``fold
    <step> (k)`` / ``(k+2)``: a step off a fold towards the side with k or k + 2 real modes), the
    parameters and the actuated values."""

    name: str
    seed: int
    label: str
    parameters: dict[str, float]
    actuated: np.ndarray

    @property
    def step(self) -> float | None:
        """The step off the fold (None: a random input)."""
        return None if self.label == "random" else float(self.label.split()[1])

    def at(self, scale: float) -> tuple[dict[str, float], np.ndarray]:
        """Parameters and input at a scale (every length and prismatic input times it)."""
        family = om.family(self.name)
        return family.scaled(self.parameters, scale), family.scale_input(self.actuated, scale)

    def describe(self, scale: float) -> str:
        parameters, actuated = self.at(scale)
        values = ", ".join(repr(float(v)) for v in actuated)
        hexes = ", ".join(float(v).hex() for v in actuated)
        return f"{self.name} geometry seed {self.seed} scale {scale:g} {self.label}: actuated [{values}] ({hexes})"


def corpus(name: str, geometries: int, randoms: int, folds: int, first_seed: int = 1) -> list[Case]:
    """Per geometry (seeds first_seed, first_seed + 1, ...): ``randoms`` random inputs and the
    inputs off ``folds`` folds (2 at step 0, 2 at each of 1e-9 and 1e-6)."""
    family = om.family(name)
    out: list[Case] = []
    for seed in range(first_seed, first_seed + geometries):
        parameters = family.geometry(seed)
        out += [Case(name, seed, "random", parameters, a) for a in family.random_inputs(seed, parameters, randoms)]
        for fold in family.folds(seed, parameters, folds):
            out += [Case(name, seed, f"fold {label}", parameters, a) for label, a in fold.steps()]
    return out


@dataclass(frozen=True)
class Verdict:
    """One case solved at one scale on one backend, and what the oracle says."""

    case: Case
    backend: str
    scale: float
    oracle: om.Modes
    listed: np.ndarray  # the listed modes' passive coordinates, (count, n_passive)
    complete: bool | None  # None: no certificate (an error, or a method without one)
    seconds: float = math.nan
    error: str = ""
    missing: int = 0  # oracle modes with no listed mode within LOOSE
    extra: int = 0  # listed modes with no oracle mode within LOOSE
    distance: float = math.inf  # the best one-to-one pairing's largest distance (inf: counts differ)

    #: None: not asked (the solver agrees with the oracle); False: the oracle's count changes
    #: within STABLE of the input (within rounding of a fold: no double-precision certificate can
    #: be held to the exact count there)
    stable: bool | None = None

    @property
    def usable(self) -> bool:
        return self.oracle.usable and not self.error and self.stable is not False

    @property
    def at_fold(self) -> bool:
        """Decided by the oracle but within rounding of a fold (``stable`` False)."""
        return self.oracle.usable and not self.error and self.stable is False

    @property
    def wrong(self) -> bool:
        """The listed modes are not the oracle's: a count, or a pose beyond TOLERANCE in the best
        one-to-one pairing."""
        return self.usable and not self.distance <= TOLERANCE

    @property
    def inaccurate(self) -> bool:
        """Wrong only by the accuracy of poses: the count right, every pose within LOOSE."""
        return self.wrong and self.distance <= LOOSE

    @property
    def false_complete(self) -> bool:
        return bool(self.complete) and self.wrong

    def explain(self) -> str:
        oracle = self.oracle
        text = (
            f"{self.case.describe(self.scale)} [{self.backend}]: listed {len(self.listed)} modes, "
            f"complete {self.complete}; the oracle: {oracle.count} real modes"
        )
        if self.missing or self.extra:
            text += f" ({self.missing} missing, {self.extra} extra)"
        elif self.inaccurate:
            text += f" (a pose {self.distance:.2g} off)"
        return text + (f"; error {self.error}" if self.error else "")


def source(name: str, workdir: Path | None = None) -> str:
    """What ``parakin.load`` takes for a mechanism: its name, or the folder a fixture file is
    generated into (once per workdir) with ``parakin generate``."""
    if name not in GENERATED:
        return name
    if workdir is None:
        workdir = Path(tempfile.mkdtemp(prefix="parakin-census-"))
    out = workdir / name
    if not (out / "manifest.json").is_file():
        subprocess.run(
            [sys.executable, "-m", "parakin", "generate", str(GENERATED[name]), "--out", str(out)],
            check=True,
            capture_output=True,
        )
    return str(out)


def _solve(mechanism, actuated: np.ndarray, method: str):  # noqa: ANN001, ANN202
    modes = mechanism.forward_pose_all(actuated, strict=False, method=method)
    certificate = modes.certificate()
    complete = certificate.get("complete")
    rows = []
    for k in range(actuated.shape[0]):
        listed = modes.passive[k][modes.valid[k]]
        rows.append((listed, None if complete is None else bool(np.asarray(complete)[k])))
    return rows


def check(
    name: str, backend: str, scale: float, cases: Sequence[Case], where: str | None = None, timed: bool = False
) -> list[Verdict]:
    """Every case at ``scale`` on ``backend``, against the oracle. A batch per geometry (one input
    per call, after one warm-up call, when ``timed``)."""
    import parakin

    family = om.family(name)
    where = where or name
    groups: dict[int, list[Case]] = defaultdict(list)
    for case in cases:
        groups[case.seed].append(case)
    out: list[Verdict] = []
    for group in groups.values():
        parameters, _ = group[0].at(scale)
        actuated = np.array([case.at(scale)[1] for case in group])
        seconds = [math.nan] * len(group)
        error = ""
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                mechanism = parakin.load(where, backend=backend, **family.load_arguments(parameters))
                if timed:
                    _solve(mechanism, actuated[:1], family.method)
                    rows = []
                    for k in range(len(group)):
                        start = time.perf_counter()
                        rows += _solve(mechanism, actuated[k : k + 1], family.method)
                        seconds[k] = time.perf_counter() - start
                else:
                    rows = _solve(mechanism, actuated, family.method)
        except Exception as exception:  # noqa: BLE001 - a census counts errors, it does not stop on them
            error = f"{type(exception).__name__}: {exception}"[:300]
            rows = [(np.zeros((0, len(family.angular))), None)] * len(group)
        size = family.size(parameters)
        for case, (listed, complete), elapsed, values in zip(group, rows, seconds, actuated, strict=True):
            oracle = om.cached(name, parameters, values)
            missing = extra = 0
            distance = math.inf
            if oracle.count is not None:
                missing, extra = om.unmatched(listed, oracle.array(), family.angular, size, LOOSE)
                distance = om.match(listed, oracle.array(), family.angular, size)
            stable = None
            if oracle.usable and not error and (extra or not distance <= TOLERANCE):
                stable = family.stable(parameters, values)
            out.append(
                Verdict(
                    case, backend, scale, oracle, listed, complete, elapsed, error, missing, extra, distance, stable
                )
            )
    return out


# ------------------------------------------------------------------ the table
COLUMNS = (
    "inputs", "usable", "at a fold", "complete", "false complete", "missing", "extra", "inaccurate", "not complete",
    "spurious (not complete)", "errors",
)  # fmt: skip


def tally(verdicts: Sequence[Verdict]) -> dict[str, int]:
    out = dict.fromkeys(COLUMNS, 0)
    for v in verdicts:
        out["inputs"] += 1
        out["errors"] += bool(v.error)
        out["usable"] += v.usable
        out["at a fold"] += v.at_fold
        out["complete"] += bool(v.complete)
        out["not complete"] += v.complete is False
        if v.usable and v.complete:
            out["false complete"] += v.wrong
            out["missing"] += v.missing
            out["extra"] += v.extra
            out["inaccurate"] += v.inaccurate
        if v.usable and not v.complete:
            out["spurious (not complete)"] += v.extra
    return out


def _format(header: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    text = [[str(c) for c in header]] + [[str(c) for c in row] for row in rows]
    widths = [max(len(row[k]) for row in text) for k in range(len(header))]
    lines = ["  ".join(cell.rjust(w) if k else cell.ljust(w) for k, (cell, w) in enumerate(zip(row, widths, strict=True)))
             for row in text]  # fmt: skip
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def table(verdicts: Sequence[Verdict]) -> str:
    """One row per mechanism x backend x scale (``COLUMNS``, then the time per input)."""
    groups: dict[tuple[str, str, float], list[Verdict]] = defaultdict(list)
    for v in verdicts:
        groups[(v.case.name, v.backend, v.scale)].append(v)
    rows = []
    for (name, backend, scale), group in groups.items():
        counts = tally(group)
        times = [v.seconds for v in group if math.isfinite(v.seconds)]
        timing = (f"{1e3 * statistics.median(times):.2f}", f"{1e3 * max(times):.2f}") if times else ("-", "-")
        rows.append([name, backend, f"{scale:g}", *counts.values(), *timing])
    return _format(["mechanism", "backend", "scale", *COLUMNS, "median ms", "max ms"], rows)


def by_kind(verdicts: Sequence[Verdict]) -> str:
    """The counts by kind of input (random, step off a fold), over backends and scales."""
    groups: dict[tuple[str, str], list[Verdict]] = defaultdict(list)
    for v in verdicts:
        kind = v.case.label if v.case.label == "random" else "fold step " + v.case.label.split()[1]
        groups[(v.case.name, kind)].append(v)
    rows = [[name, kind, *tally(group).values()] for (name, kind), group in sorted(groups.items())]
    return _format(["mechanism", "input", *COLUMNS], rows)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawTextHelpFormatter
    )
    parser.add_argument("--inputs", type=int, default=90, help="inputs per mechanism (metre scale; each is "
                        "solved at every scale on every backend): 3 random and 6 near one fold per geometry")  # fmt: skip
    parser.add_argument("--mechanisms", nargs="+", default=list(MECHANISMS), choices=MECHANISMS)
    parser.add_argument("--backends", nargs="+", default=list(BACKENDS), choices=BACKENDS)
    parser.add_argument("--scales", nargs="+", type=float, default=list(SCALES))
    parser.add_argument("--first-seed", type=int, default=1, help="seed of the first random geometry")
    parser.add_argument("--examples", type=int, default=5, help="false certificates printed per mechanism")
    args = parser.parse_args(argv)
    geometries = max(1, math.ceil(args.inputs / 9))
    workdir = Path(tempfile.mkdtemp(prefix="parakin-census-"))
    verdicts: list[Verdict] = []
    for name in args.mechanisms:
        start = time.perf_counter()
        cases = corpus(name, geometries, 3, 1, args.first_seed)
        where = source(name, workdir)
        print(f"{name}: {len(cases)} inputs on {geometries} geometries ({time.perf_counter() - start:.1f} s to "
              "find the folds)", file=sys.stderr, flush=True)  # fmt: skip
        for backend in args.backends:
            for scale in args.scales:
                verdicts += check(name, backend, scale, cases, where, timed=True)
    print(table(verdicts))
    print()
    print(by_kind(verdicts))
    for name in args.mechanisms:
        bad = [v for v in verdicts if v.case.name == name and v.false_complete]
        if bad:
            print(f"\n{name}: the first false complete certificates of {len(bad)}")
            for v in bad[: args.examples]:
                print("  " + v.explain())
    return 0


if __name__ == "__main__":
    sys.exit(main())
