"""The solver core against its floor (issue 33): Dietmaier's 40 modes of the general Stewart
platform by parakin's certified ``forward_pose_all`` (with NumPy's certificate, and with the C
certificate ``certify_roots_compiled`` swapped in) and by fkSGP (Martyushev 2025, an elimination
template in NumPy/SciPy: ``../shared/peers/fkSGP``), single thread, CPU time, the contenders
interleaved in one process with their order rotated; the Krawczyk certificate alone, NumPy
against C; forward_pose_all per family with either certificate; and per homotopy family what the
C path tracker does per path (step attempts, rejections, evaluations, LU factorisations).

Run alone: ``python -m bench.floor``; ``make bench`` prints the same table.
"""

from __future__ import annotations

import contextlib
import importlib
import os
import sys
import time
import types
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

import parakin
from parakin.packages.compiled import CompiledBackend
from parakin.solvers import modes as modes_module
from parakin.solvers.certify import certify_roots, certify_roots_compiled
from parakin.solvers.modes import compiled_modes
from parakin.studies.sampling import sample_configurations

PEERS = Path(__file__).resolve().parent.parent.parent / "shared" / "peers"
#: Dietmaier's geometry with 40 real postures (../shared/peers/README.md), fkSGP's arguments
DIETMAIER_BASE = np.array(
    [
        [0, 0, 0],
        [1.107915, 0, 0],
        [0.549094, 0.756063, 0],
        [0.735077, -0.223935, 0.525991],
        [0.514188, -0.526063, -0.368418],
        [0.590473, 0.094733, -0.205018],
    ]
)
DIETMAIER_PLATFORM = np.array(
    [
        [0, 0, 0],
        [0.542805, 0, 0],
        [0.956919, -0.528915, 0],
        [0.665885, -0.353482, 1.402538],
        [0.478359, 1.158742, 0.107672],
        [-0.137087, -0.235121, 0.353913],
    ]
)
DIETMAIER_LEGS = np.array([1, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071])
#: rounds of the interleaved comparison (each times every contender once, order rotated)
ROUNDS = 30
#: inputs near home per family for the tracker counts
COUNT_INPUTS = {"stewart": 20, "prs3": 40, "planar_3rrr": 100, "rus6": 4}


def load_fksgp() -> Callable[..., Any] | None:
    """fkSGP's ``solver66`` where ``../shared/peers/fkSGP`` is present, else None. Its package
    ``__init__`` imports a test module that needs Python >= 3.12, so a package object is
    registered for the folder and only ``solver66`` (and what it imports) is loaded."""
    folder = PEERS / "fkSGP" / "python"
    if not (folder / "solver66.py").is_file():
        return None
    if "fksgp_peer" not in sys.modules:
        package = types.ModuleType("fksgp_peer")
        package.__path__ = [str(folder)]
        sys.modules["fksgp_peer"] = package
    module = importlib.import_module("fksgp_peer.solver66")
    return module.solver66  # type: ignore[no-any-return]


def compiled(m: Any) -> CompiledBackend:
    """The compiled backend of a loaded mechanism (the bench loads with backend='compiled')."""
    backend = m.backend
    assert isinstance(backend, CompiledBackend), backend
    return backend


def interleaved(contenders: dict[str, Callable[[], object]], rounds: int = ROUNDS) -> dict[str, np.ndarray]:
    """CPU seconds of each contender's call over ``rounds`` rounds, the contenders' order rotated
    each round (what one of them leaves in the caches the next one finds)."""
    names = list(contenders)
    times: dict[str, list[float]] = {name: [] for name in names}
    for call in contenders.values():  # warm up: compile, load, first-call allocations
        call()
    for r in range(rounds):
        for name in names[r % len(names) :] + names[: r % len(names)]:
            began = time.process_time()
            contenders[name]()
            times[name].append(time.process_time() - began)
    return {name: np.array(value) for name, value in times.items()}


@contextlib.contextmanager
def numpy_certificate() -> Iterator[None]:
    """Inside the block, ``forward_pose_all`` certifies its endpoints with NumPy's
    ``certify_roots`` instead of the package's C (``certify_roots_compiled``, what the compiled
    backend uses): a bench-only swap of the name ``parakin.solvers.modes`` calls, to measure
    what the C certificate gains."""
    original = modes_module.certify_roots_compiled

    def in_numpy(backend: Any, *args: Any, clusters: bool = True, **kwargs: Any) -> Any:
        # looked up here: certify_calls spies on it; NumPy's counts the clusters whether asked or not
        return modes_module.certify_roots(*args, **kwargs)

    modes_module.certify_roots_compiled = in_numpy  # type: ignore[assignment]
    try:
        yield
    finally:
        modes_module.certify_roots_compiled = original  # type: ignore[assignment]


def certify_calls(m: Any, theta: np.ndarray) -> list[tuple[tuple, dict]]:
    """The arguments of every ``certify_roots`` call that ``forward_pose_all(theta)`` makes."""
    calls: list[tuple[tuple, dict]] = []
    original = modes_module.certify_roots

    def spy(*args: Any, **kwargs: Any) -> Any:
        calls.append((args, kwargs))
        return original(*args, **kwargs)

    modes_module.certify_roots = spy  # type: ignore[assignment]
    try:
        with numpy_certificate():
            m.forward_pose_all(theta, strict=False)
    finally:
        modes_module.certify_roots = original  # type: ignore[assignment]
    return calls


def certificate_rows() -> list[str]:
    """The Krawczyk certificate of one input's endpoints, NumPy (``certify_roots``) against C
    (``certify_roots_compiled``), interleaved, CPU ms per input: Dietmaier's input of the
    Stewart platform (homogeneous, the real chart) and an input of rus6 near home (affine,
    scaled); candidates certified unique and real by each."""
    rows = []
    inputs = {"stewart": DIETMAIER_LEGS.copy()}
    if "rus6" in parakin.available():
        rus6 = parakin.load("rus6", backend="compiled")
        inputs["rus6"] = sample_configurations(rus6, 3, spread=0.05, seed=5).actuated[0]
    for name, theta in inputs.items():
        m = parakin.load(name, backend="compiled")
        backend = compiled(m)
        calls = certify_calls(m, theta)

        def numpy_side(calls: list = calls) -> None:
            for args, kwargs in calls:
                certify_roots(*args, **kwargs)

        def c_side(calls: list = calls, backend: CompiledBackend = backend) -> None:
            for args, kwargs in calls:
                certify_roots_compiled(backend, *args, **kwargs)

        times = interleaved({"NumPy": numpy_side, "C": c_side})
        reference = [certify_roots(*args, **kwargs) for args, kwargs in calls]
        ours = [certify_roots_compiled(backend, *args, **kwargs) for args, kwargs in calls]
        candidates = sum(int(np.isfinite(args[3]).all(-1).sum()) for args, _ in calls)
        for label, result in (("NumPy", reference), ("C", ours)):
            unique = sum(int(r.unique.sum()) for r in result)
            real = sum(int((r.real == 1).sum()) for r in result)
            ms = times[label] * 1e3
            rows.append(
                f"{name:8s} {label:6s} {np.median(ms):9.3f} {np.percentile(ms, 10):9.3f} {np.percentile(ms, 90):9.3f} "
                f"{np.median(times[label]) / np.median(times['NumPy']):8.3f} {candidates:5d} {unique:6d} {real:5d}"
            )
    return rows


#: rounds of the interleaved forward_pose_all comparison with either certificate (rus6 is slow)
SWAP_ROUNDS = 3


def swap_rows() -> list[str]:
    """Per homotopy family: forward_pose_all (certified, one input per call, the inputs near home
    of the tracker rows) with NumPy's certificate swapped in against the same with the C
    certificate (the compiled backend's), interleaved: CPU ms per input, their ratio, and the inputs certified complete by
    each (the exact-arithmetic fallback runs where the double-precision test leaves a root)."""
    rows = []
    for name, count in COUNT_INPUTS.items():
        if name not in parakin.available():
            continue
        m = parakin.load(name, backend="compiled")
        inputs = sample_configurations(m, 3 * count, spread=0.05, seed=5).actuated[:count]

        def numpy_side(m: Any = m, inputs: np.ndarray = inputs) -> list:
            with numpy_certificate():
                return [m.forward_pose_all(theta, strict=False) for theta in inputs]

        def c_side(m: Any = m, inputs: np.ndarray = inputs) -> list:
            return [m.forward_pose_all(theta, strict=False) for theta in inputs]

        times = interleaved({"NumPy": numpy_side, "C": c_side}, rounds=SWAP_ROUNDS)
        complete = {
            label: sum(bool(np.all(r.certificate().get("complete", False))) for r in side())
            for label, side in (("NumPy", numpy_side), ("C", c_side))
        }
        ms = {label: float(np.median(value)) * 1e3 / len(inputs) for label, value in times.items()}
        rows.append(
            f"{name:12s} {len(inputs):4d} {ms['NumPy']:10.3f} {ms['C']:10.3f} {ms['C'] / ms['NumPy']:8.3f} "
            f"{complete['NumPy']:9d} {complete['C']:9d}"
        )
    return rows


def dietmaier_row() -> list[str]:
    """Dietmaier's 40 modes: parakin (certified) and fkSGP, CPU ms per input (median, 10th and
    90th percentile), their ratio in this run, modes each finds, and the tracker's counts."""
    m = parakin.load("stewart", backend="compiled")
    theta = DIETMAIER_LEGS.copy()
    solver = load_fksgp()

    def with_numpy_certificate() -> object:
        with numpy_certificate():
            return m.forward_pose_all(theta, strict=False)

    contenders: dict[str, Callable[[], object]] = {
        # the endpoints certified in C (certify_roots_compiled), as the compiled backend does
        "parakin": lambda: m.forward_pose_all(theta, strict=False),
        # the same with the endpoints certified in NumPy (certify_roots; bench-only swap)
        "NumPy c.": with_numpy_certificate,
        # the generated C pipeline alone: tracking, settling; no certificate, no Python
        "C only": lambda: compiled_modes(m, theta[None]),
    }
    squared = DIETMAIER_LEGS**2
    if solver is not None:
        np.random.seed(1)  # fkSGP randomises internally
        contenders["fkSGP"] = lambda: solver(DIETMAIER_BASE, DIETMAIER_PLATFORM, squared, 1)
    times = interleaved(contenders)
    modes = m.forward_pose_all(theta, strict=False)
    complete = bool(np.all(modes.certificate().get("complete", False)))
    with compiled(m).counting() as counts:
        m.forward_pose_all(theta, strict=False)
    rows = []
    ours = float(np.median(times["parakin"]))
    for name, value in times.items():
        if name == "fkSGP":
            assert solver is not None
            found = len(solver(DIETMAIER_BASE, DIETMAIER_PLATFORM, squared, 1)[0])
            extra = f"{found:5d} {'-':>8s}"
        elif name == "NumPy c.":
            with numpy_certificate():
                swapped = m.forward_pose_all(theta, strict=False)
            swapped_complete = bool(np.all(swapped.certificate().get("complete", False)))
            extra = f"{int(swapped.count):5d} {str(swapped_complete):>8s}"
        elif name == "C only":
            extra = f"{int((compiled_modes(m, theta[None])['outcome'] == 0).sum()):5d} {'-':>8s}"
        else:
            extra = f"{int(modes.count):5d} {str(complete):>8s}"
        ms = value * 1e3
        rows.append(
            f"{name:8s} {np.median(ms):9.2f} {np.percentile(ms, 10):9.2f} {np.percentile(ms, 90):9.2f} "
            f"{np.median(value) / ours:8.2f} {extra}"
        )
    if solver is None:
        rows.append(f"fkSGP: not found in {PEERS} (the peer is a bench baseline outside the repository)")
    per_path = counts_line(counts)
    rows.append(f"parakin's tracker on this input, per path: {per_path}")
    return rows


def counts_line(counts: Any) -> str:
    paths = max(counts.paths, 1)
    accepted = max(counts.steps - counts.rejected, 1)
    return (
        f"{counts.paths} paths, {counts.steps / paths:.1f} steps ({counts.rejected / max(counts.steps, 1):.1%} "
        f"rejected), {counts.evaluations / paths:.1f} evaluations, {counts.factorisations / paths:.1f} LU, "
        f"{counts.factorisations / accepted:.2f} LU per accepted step"
    )


def tracker_rows() -> list[str]:
    """Per homotopy family: CPU ms per input of forward_pose_all (certified, one at a time) on
    inputs sampled near home, and the tracker's work per path on them."""
    rows = []
    for name, count in COUNT_INPUTS.items():
        if name not in parakin.available():
            continue
        m = parakin.load(name, backend="compiled")
        sample = sample_configurations(m, 3 * count, spread=0.05, seed=5)
        inputs = sample.actuated[:count]
        began = time.process_time()
        for theta in inputs:
            m.forward_pose_all(theta, strict=False)
        seconds = (time.process_time() - began) / len(inputs)
        with compiled(m).counting() as counts:
            m.forward_pose_all(inputs, strict=False)
        rows.append(f"{name:12s} {len(inputs):4d} {seconds * 1e3:9.3f}   {counts_line(counts)}")
    return rows


#: tracker.solve calls per timing (the best of SOLVE_REPEATS)
SOLVE_CALLS, SOLVE_REPEATS = 5000, 5


def tracker_solve_rows() -> list[str]:
    """The 1 kHz loop: ``tracker.solve`` of one input from Python (inputs alternating by a small
    step, so that every call runs Newton), against the same Newton step called bare (the input
    written into the tracker's buffer and the foreign call alone): microseconds per call, best of
    SOLVE_REPEATS, and their difference, what Python adds."""
    rows = []
    for name in ("stewart", "planar_3rrr", "prs3"):
        if name not in parakin.available():
            continue
        m = parakin.load(name, backend="compiled")
        tracker = m.tracker(m.forward_pose(m.home_actuated))
        step = np.where([v.revolute for v in m.manifest.actuated], np.radians(0.01), 1e-4)
        targets = [m.home_actuated.copy(), m.home_actuated + step]
        solve, bare = [], []
        for _ in range(SOLVE_REPEATS):
            began = time.perf_counter()
            for i in range(SOLVE_CALLS):
                tracker.solve(targets[i & 1])
            solve.append((time.perf_counter() - began) / SOLVE_CALLS)
            began = time.perf_counter()
            for i in range(SOLVE_CALLS):
                tracker.actuated[...] = targets[i & 1]
                tracker.call()
            bare.append((time.perf_counter() - began) / SOLVE_CALLS)
        best, floor = min(solve) * 1e6, min(bare) * 1e6
        rows.append(f"{name:12s} {best:9.2f} {floor:9.2f} {best - floor:9.2f}")
    return rows


def main() -> None:
    warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
    os.environ["PARAKIN_THREADS"] = "1"
    print("\nDietmaier's 40 modes (issue 33): CPU ms per input, single thread, contenders interleaved")
    header = f"{'solver':8s} {'median':>9s} {'p10':>9s} {'p90':>9s} {'/parakin':>8s} {'modes':>5s} {'complete':>8s}"
    print(header)
    print("-" * len(header))
    for line in dietmaier_row():
        print(line)
    print(
        "\nKrawczyk's certificate of one input's endpoints: NumPy (certify_roots) against C "
        "(certify_roots_compiled), CPU ms per input, interleaved"
    )
    header = (
        f"{'input':8s} {'engine':6s} {'median':>9s} {'p10':>9s} {'p90':>9s} {'/NumPy':>8s} {'cand.':>5s} "
        f"{'unique':>6s} {'real':>5s}"
    )
    print(header)
    print("-" * len(header))
    for line in certificate_rows():
        print(line)
    print(
        "\nforward_pose_all (certified, one input per call, inputs near home) with NumPy's certificate swapped in "
        f"(bench only) and with the C certificate (the compiled backend's), interleaved ({SWAP_ROUNDS} rounds): CPU ms per input"
    )
    header = (
        f"{'mechanism':12s} {'n':>4s} {'NumPy ms':>10s} {'C ms':>10s} {'C/NumPy':>8s} {'complete':>9s} {'complete':>9s}"
    )
    print(header)
    print("-" * len(header))
    for line in swap_rows():
        print(line)
    print("\nThe C path tracker per homotopy family (inputs near home, certified, one input per call)")
    header = f"{'mechanism':12s} {'n':>4s} {'ms/input':>9s}   work per path"
    print(header)
    print("-" * len(header))
    for line in tracker_rows():
        print(line)
    print("\ntracker.solve of one input from Python against its Newton step called bare (us per call, best of 5)")
    header = f"{'mechanism':12s} {'solve':>9s} {'C step':>9s} {'Python':>9s}"
    print(header)
    print("-" * len(header))
    for line in tracker_solve_rows():
        print(line)


if __name__ == "__main__":
    main()  # single-threaded BLAS: set in bench/__init__.py, before NumPy loads
