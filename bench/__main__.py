"""``make bench``: every mechanism in ``parakin.available()`` x every backend, on inputs sampled
from its manifest, next to a baseline measured in the same run: ``sympy.lambdify`` of the same
symbolic equations solved by ``scipy.optimize.root`` (what a user without parakin would write).

Ratios are baseline time / parakin time (higher is faster than the baseline).
"""

from __future__ import annotations

import os
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.optimize
import sympy as sp
from parakin.generator.build import discover, generate

import bench.floor
import parakin
from bench.timing import best_time
from parakin.solvers.path_tracking import path_pairs
from parakin.studies.sampling import sample_configurations

BATCHES = [1, 1000]
#: seconds one forward_pose_all batch may take (it runs 4 times): above it, the row runs on fewer inputs
FORWARD_ALL_BUDGET = 5.0
BASELINE_POSES = 50  # the scipy baseline loops in Python: timed on this many, reported per pose


class Baseline:
    """sympy.lambdify of parakin's own symbolic loop closure, solved by scipy.optimize.root."""

    def __init__(self, name: str) -> None:
        objects = parakin.symbolic(name)
        manifest = parakin.metadata(name)
        symbols = {s.name: s for obj in objects.values() if isinstance(obj, sp.Basic) for s in obj.free_symbols}

        def symbol(n: str) -> sp.Symbol:
            return symbols.get(n, sp.Symbol(n, real=True))

        actuated = [symbol(n) for n in manifest.actuated_names]
        passive = [symbol(n) for n in manifest.passive_names]
        params = [symbol(p.name) for p in manifest.parameters]
        self.params = [p.default for p in manifest.parameters]
        self.residual = sp.lambdify([actuated, passive, params], list(objects["loop_closure"]), "numpy")
        self.jacobian = sp.lambdify([actuated, passive, params], objects["loop_closure"].jacobian(passive), "numpy")

    def forward(self, actuated: np.ndarray, guess: np.ndarray) -> None:
        for a, g in zip(actuated, guess, strict=True):
            scipy.optimize.root(
                lambda q, a=a: self.residual(a, q, self.params),
                g,
                jac=lambda q, a=a: self.jacobian(a, q, self.params),
                tol=1e-12,
            )


def mechanism_rows(name: str, record) -> str | None:
    """Timings of one mechanism; a note instead when its defaults give no closed configuration."""
    reference = parakin.load(name, backend="compiled")
    sample = sample_configurations(reference, max(BATCHES), seed=2026)
    if sample.actuated.shape[0] < max(BATCHES) // 2:
        return f"{name}: no closed configurations near home with the default parameters (skipped)"
    rng = np.random.default_rng(7)
    guess = sample.passive + rng.normal(0, 0.01, sample.passive.shape)  # a tracking-quality guess
    n = BASELINE_POSES
    if reference.passive_names:
        baseline = Baseline(name)
        base_forward = best_time(lambda: baseline.forward(sample.actuated[:n], guess[:n]), budget=0.5) / n
    else:
        base_forward = float("nan")
    caps = reference.capabilities
    for backend in ["numpy", "casadi", "compiled"]:
        m = parakin.load(name, backend=backend)
        single_all = 0.0
        for batch in BATCHES:
            pick = slice(0, batch) if batch > 1 else 0
            a, g, p = sample.actuated[pick], guess[pick], sample.pose[pick]
            if caps.inverse is not None:
                record(
                    name,
                    "inverse_pose",
                    backend,
                    batch,
                    best_time(lambda m=m, p=p: m.inverse_pose(p, strict=False)),
                    None,
                )
            if reference.passive_names:
                seconds = best_time(lambda m=m, a=a, g=g: m.forward_pose(a, g, strict=False))
                record(name, "forward_pose (Newton)", backend, batch, seconds, base_forward)
            if caps.forward is not None:
                if batch > 1 and single_all * batch > FORWARD_ALL_BUDGET:
                    # a costly family (NumPy-orchestrated paths): a smaller batch, named in the row
                    batch = max(2, int(FORWARD_ALL_BUDGET / single_all))
                    a = sample.actuated[:batch]
                seconds = best_time(lambda m=m, a=a: m.forward_pose_all(a, strict=False), budget=0.2)
                record(name, f"forward_pose_all (deg {caps.forward.degree})", backend, batch, seconds, None)
                single_all = seconds / batch if batch == 1 else single_all
    if reference.passive_names:
        for batch in [1, 1000]:
            tracker = reference.tracker(
                parakin.Configuration(sample.actuated[:batch], sample.passive[:batch], sample.pose[:batch])
            )
            targets = [sample.actuated[:batch] + 1e-5, sample.actuated[:batch]]
            flip = iter(range(10**9))

            def solve(tracker=tracker, targets=targets, flip=flip) -> None:
                tracker.solve(targets[next(flip) % 2])

            record(name, "tracker.solve (small step)", "compiled", batch, best_time(solve), base_forward)
    return None


MODES_BATCH = 2000
MULTISTART_INPUTS = 5  # the scipy multi-start baseline is slow: timed on this many inputs
MULTISTART_STARTS = 40


def multistart_modes(
    name: str, actuated: np.ndarray, seed: int = 3, starts: int = MULTISTART_STARTS
) -> tuple[float, list[list[np.ndarray]]]:
    """Baseline: scipy.optimize.root on the lambdified closure from random passive starts;
    returns seconds per input and the poses of the distinct genuine modes found per input."""
    baseline = Baseline(name)
    m = parakin.load(name, backend="numpy")
    rng = np.random.default_rng(seed)
    scale = np.where([v.revolute for v in m.manifest.passive], np.pi, np.maximum(np.abs(m.home_passive), 0.1))
    found = []
    start = time.perf_counter()
    for a in actuated:
        solutions: list[np.ndarray] = []
        for _ in range(starts):
            guess = m.home_passive + scale * rng.uniform(-1, 1, m.home_passive.shape)
            result = scipy.optimize.root(
                lambda q, a=a: baseline.residual(a, q, baseline.params),
                guess,
                jac=lambda q, a=a: baseline.jacobian(a, q, baseline.params),
                tol=1e-12,
            )
            residual = np.abs(baseline.residual(a, result.x, baseline.params)).max()
            # a genuine mode, as forward_pose_all counts one: closed, aligned (no half-turn
            # between legs), within the joint limits
            aligned = bool((m.loop_closure(a, result.x)["alignment"] > 0).all())
            if result.success and residual < 1e-9 and aligned and m.within_limits(result.x):
                pose = m.platform_pose(a, result.x)
                if all(np.abs(pose - other).max() > 1e-6 for other in solutions):
                    solutions.append(pose)
        found.append(solutions)
    return (time.perf_counter() - start) / len(actuated), found


def modes_rows(name: str) -> str | None:
    """forward_pose_all: the generated C pipeline (batched and single), the same algorithm
    orchestrated in Python over the NumPy kernels, one batched tracker step, scipy multi-start."""
    compiled = parakin.load(name, backend="compiled")
    if compiled.capabilities.forward is None:
        return None
    sample = sample_configurations(compiled, MODES_BATCH, seed=11)
    if sample.actuated.shape[0] < MODES_BATCH // 2:
        return None
    a = sample.actuated
    single = best_time(lambda: compiled.forward_pose_all(a[0], strict=False), budget=0.3)
    # an expensive pipeline (the Stewart homotopy) is timed on fewer inputs
    scale = max(1, int(single / 2e-4))
    a = a[: max(20, MODES_BATCH // scale)]
    n = a.shape[0]
    batched = best_time(lambda: compiled.forward_pose_all(a, strict=False), budget=1.0) / n
    numpy_m = parakin.load(name, backend="numpy")
    few = max(1, 200 // scale)
    orchestrated = best_time(lambda: numpy_m.forward_pose_all(a[:few], strict=False), budget=1.0) / few
    tracker = compiled.tracker(parakin.Configuration(a, sample.passive[:n], sample.pose[:n]))
    step = np.where([v.revolute for v in compiled.manifest.actuated], np.radians(0.1), 1e-3)
    targets = [a + step, a]
    flip = iter(range(10**9))
    tracked = best_time(lambda: tracker.solve(targets[next(flip) % 2])) / n
    counts = compiled.forward_pose_all(a, strict=False).count
    multistart, poses = multistart_modes(name, a[:MULTISTART_INPUTS])
    found = [len(p) for p in poses]
    ours = [int(c) for c in counts[:MULTISTART_INPUTS]]
    return (
        f"{name:12s} {compiled.capabilities.forward.degree:4d} {batched * 1e6:10.2f} {single * 1e6:10.1f} "
        f"{orchestrated * 1e6:12.1f} {orchestrated / batched:7.1f} {tracked * 1e6:9.2f} {batched / tracked:8.1f} "
        f"{multistart * 1e6:12.0f} {multistart / batched:9.0f}   ours {ours} multi-start {found}"
    )


EXAMPLE_REPEATS = 30
METHOD_INPUTS = 40


def tracked_paths(info) -> int:
    """Paths tracked per input: a homotopy with a sign symmetry tracks one path of each pair
    (``parakin.solvers.path_tracking.path_pairs``); a closed form has one slot per root."""
    homotopy = info.homotopy
    if homotopy is None:
        return int(info.degree)
    pairs = path_pairs(homotopy.exponents, homotopy.equation, homotopy.start)
    return int(info.degree) if pairs is None else int(info.degree) // 2


def method_rows(name: str) -> list[str]:
    """forward_pose_all by every method of a mechanism on the same sampled inputs: time per input
    (single-threaded; the default method through the generated C pipeline, the others through
    the NumPy orchestration over the compiled kernels), paths tracked per input, the ratio to the default
    in this run, and the share of inputs certified complete (homotopy methods)."""
    compiled = parakin.load(name, backend="compiled")
    methods = compiled.capabilities.forward_methods
    if not methods:
        return []
    sample = sample_configurations(compiled, 3 * METHOD_INPUTS, spread=0.05, seed=23)
    inputs = sample.actuated[:METHOD_INPUTS]
    if inputs.shape[0] < METHOD_INPUTS // 2:
        return []
    default = compiled.capabilities.forward
    assert default is not None
    timings = {}
    rows = []
    for method, info in methods.items():
        few = inputs if info is default else inputs[: max(4, METHOD_INPUTS // 4)]
        seconds = best_time(
            lambda few=few, method=method: compiled.forward_pose_all(few, strict=False, method=method), budget=0.5
        )
        timings[method] = seconds / few.shape[0]
        threaded = float("nan")
        if info is default:  # the same batch spread over every core (the generated C pipeline)
            os.environ["PARAKIN_THREADS"] = str(os.cpu_count() or 1)
            try:
                threaded = best_time(lambda few=few: compiled.forward_pose_all(few, strict=False), budget=0.5)
            finally:
                os.environ["PARAKIN_THREADS"] = "1"
        modes = compiled.forward_pose_all(few, strict=False, method=method)
        certificate = modes.certificate()
        complete = (
            f"{np.mean(certificate['complete']) * 100:9.0f}%" if "complete" in certificate else f"{'closed form':>10s}"
        )
        proof = info.homotopy.root_count if info.homotopy else None
        rows.append(
            f"{name:12s} {method + (' *' if info is default else ''):13s} {tracked_paths(info):6d} "
            f"{timings[method] * 1e6:12.1f} {timings[method] / timings.get(default.method, timings[method]):9.2f} "
            f"{complete} {proof.witnesses if proof else 0:10d} {seconds / threaded:9.2f}"
        )
    return rows


def example_rows() -> list[str]:
    """forward_pose_all on every named example with printed actuated values (e.g. Dietmaier's 40
    modes of the general Stewart platform): time per call over repeated single-threaded calls
    (median, 10th and 90th percentile), modes, the worst conditioning, and the scipy multi-start
    baseline on the same input in the same run (time and modes it finds)."""
    rows = []
    for name in parakin.available():
        m = parakin.load(name, backend="compiled")
        if m.capabilities.forward is None:
            continue
        for example in m.manifest.examples:
            if example.actuated is None:
                continue
            actuated = np.array(example.actuated)
            modes = m.forward_pose_all(actuated, strict=False)
            times = []
            for _ in range(EXAMPLE_REPEATS):
                began = time.perf_counter()
                m.forward_pose_all(actuated, strict=False)
                times.append(time.perf_counter() - began)
            us = np.array(times) * 1e6
            worst = np.nanmin(np.where(modes.valid, modes.conditioning, np.nan)) if modes.count else np.nan
            base, found = multistart_modes(name, actuated[None], starts=EXAMPLE_STARTS)
            rows.append(
                f"{name:10s} {example.name:16s} {int(modes.count):5d} {np.median(us):10.0f} {np.percentile(us, 10):9.0f} "
                f"{np.percentile(us, 90):9.0f} {worst:10.1e} {base * 1e6:12.0f} {base / (np.median(us) * 1e-6):7.0f} "
                f"{len(found[0]):6d}"
            )
    return rows


EXAMPLE_STARTS = 400
STATISTICS_INPUTS = 10_000
STATISTICS_ORACLE = 20  # inputs checked against the multi-start search (slow)
#: seconds of forward_pose_all per mechanism in the statistics: a costly family (rus6) gets fewer
#: inputs than STATISTICS_INPUTS, and its row says how many
STATISTICS_BUDGET = 60.0


def solver_statistics_row(name: str) -> str | None:
    """ikfast-style statistics of forward_pose_all on inputs made by inverse pose from sampled
    configurations: success = the generating pose is among the modes; wrong = a mode that does
    not close the loop (checked here with the loop-closure kernel); missing = modes the multi-start
    search finds that we do not (on the first inputs); time per input and its spread."""
    m = parakin.load(name, backend="compiled")
    if m.capabilities.forward is None:
        return None
    sample = sample_configurations(m, STATISTICS_INPUTS, spread=0.3, seed=21)
    inside = m.within_limits(sample.passive)  # a generating pose outside the joint limits is no mode
    sample = parakin.Configuration(sample.actuated[inside], sample.passive[inside], sample.pose[inside])
    n = sample.actuated.shape[0]
    if n < STATISTICS_INPUTS // 4:
        return f"{name:12s} {n:7d} (too few closed configurations sampled near home with default parameters)"
    times, counts, success, wrong, first, start, chunk, spent = [], [], 0, 0, None, 0, STATISTICS_ORACLE, 0.0
    while start < n and spent < STATISTICS_BUDGET:  # the first chunk small: a costly family stops early
        stop = min(n, start + chunk)
        began = time.perf_counter()
        modes = m.forward_pose_all(sample.actuated[start:stop], strict=False)
        seconds = time.perf_counter() - began
        spent = spent + seconds
        times.append(seconds / (stop - start))
        # the next chunk what the budget left allows at this chunk's pace, 1000 at most
        chunk = int(min(1000, max(1, (STATISTICS_BUDGET - spent) / times[-1])))
        first = modes if first is None else first
        distance = np.abs(modes.poses - sample.pose[start:stop, None]).max(axis=(-2, -1))
        success += int((np.where(modes.valid, distance, np.inf).min(-1) < 1e-6).sum())
        theta = np.broadcast_to(
            sample.actuated[start:stop, None], modes.passive.shape[:-1] + sample.actuated.shape[-1:]
        )
        closure = m.loop_closure(theta[modes.valid], modes.passive[modes.valid])
        wrong += int(((np.abs(closure["residual"]).max(-1) > 1e-9) | ~(closure["alignment"] > 0).all(-1)).sum())
        counts.append(modes.count)
        start = stop
    n = start
    assert first is not None
    _, oracle = multistart_modes(name, sample.actuated[:STATISTICS_ORACLE])
    missing = 0
    for k, found in enumerate(oracle):
        ours = first.poses[k][first.valid[k]]
        missing += sum(1 for pose in found if not (np.abs(ours - pose).max(axis=(-2, -1), initial=0.0) < 1e-6).any())
    times_us = np.array(times) * 1e6
    return (
        f"{name:12s} {n:7d} {success / n:9.4%} {wrong:6d} {missing:4d}/{sum(len(f) for f in oracle):<4d} "
        f"{np.concatenate(counts).mean():6.2f} {np.median(times_us):9.2f} {times_us.min():7.2f} {times_us.max():7.2f}"
    )


SWEEP_POINTS = (400, 500)  # a 200,000-pose reachability and singularity map per mechanism


def sweep_cases(count: int = 3) -> list[str]:
    """Mechanisms for the sweep table, picked from the manifests: one per pose kind (the first by
    name with an inverse and passive joints, so that both quantities are defined), ``count`` kinds."""
    chosen: dict[str, str] = {}
    for name in parakin.available():
        manifest = parakin.metadata(name)
        if manifest.capabilities.inverse and manifest.passive and manifest.pose_kind not in chosen:
            chosen[manifest.pose_kind] = name
    return list(chosen.values())[:count]


def sweep_rows() -> list[str]:
    """Throughput of ``parakin.sweep`` (reachable + type II distance over a pose grid): in one
    process without dask (the chunk function called directly), on dask's local threads, and on a
    2-worker LocalCluster; scaling = local threads (or cluster) / one process."""
    import distributed

    from parakin.studies.sweep import POSE_COORDINATES, sweep

    rows = []
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        for name in sweep_cases():
            m = parakin.load(name, backend="compiled")
            first, second = POSE_COORDINATES[m.manifest.pose_kind][:2]
            span = 0.3 if first == "x" else 0.8
            # a grid centred on the home pose (x y z, Z-Y-X Euler; a planar turn phi is alpha)
            pose = parakin.xyz_euler_from_pose(m.forward_pose(m.home_actuated).pose)
            home = dict(zip(("x", "y", "z", "alpha", "beta", "gamma"), pose, strict=True))
            home["phi"] = home["alpha"]
            axes = {
                axis: home[axis] + np.linspace(-span, span, points)
                for axis, points in zip((first, second), SWEEP_POINTS, strict=True)
            }
            count = SWEEP_POINTS[0] * SWEEP_POINTS[1]
            quantities = ["reachable", "type_ii_distance"]
            timings = {}
            for label, scheduler in (("one process", "synchronous"), ("local threads", None)):
                began = time.perf_counter()
                sweep(m, quantities, axes, chunk=20_000, scheduler=scheduler)
                timings[label] = time.perf_counter() - began
            sweep(m, quantities, axes, chunk=20_000, scheduler=cluster.scheduler_address)  # workers load it once
            began = time.perf_counter()
            sweep(m, quantities, axes, chunk=20_000, scheduler=cluster.scheduler_address)
            timings["2-worker cluster"] = time.perf_counter() - began
            one = timings["one process"]
            rows.append(
                f"{name:12s} {count:9d} "
                + " ".join(f"{count / t / 1e3:14.1f}" for t in timings.values())
                + f" {one / timings['local threads']:9.2f} {one / timings['2-worker cluster']:9.2f}"
            )
    return rows


def main() -> None:
    warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
    os.environ["PARAKIN_THREADS"] = "1"  # every row single-threaded unless it says otherwise
    rows: list[tuple] = []

    def record(name: str, operation: str, backend: str, batch: int, seconds: float, baseline: float | None) -> None:
        per_pose = seconds / batch
        ratio = baseline / per_pose if baseline is not None and np.isfinite(baseline) else float("nan")
        rows.append((name, operation, backend, batch, seconds * 1e6, per_pose * 1e6, (baseline or np.nan) * 1e6, ratio))

    notes = [note for name in parakin.available() if (note := mechanism_rows(name, record))]
    print(
        "benchmark: every mechanism x backend on configurations sampled near home; baseline per pose:\n"
        f"sympy.lambdify of the same loop closure + scipy.optimize.root from the same guess ({BASELINE_POSES} poses)\n"
    )
    header = (
        f"{'mechanism':12s} {'operation':30s} {'backend':9s} {'batch':>6s} {'us/call':>11s} {'us/pose':>9s} "
        f"{'baseline us/pose':>17s} {'ratio':>8s}"
    )
    print(header)
    print("-" * len(header))
    for name, operation, backend, batch, call, per_pose, base, ratio in rows:
        print(
            f"{name:12s} {operation:30s} {backend:9s} {batch:6d} {call:11.1f} {per_pose:9.3f} {base:17.1f} {ratio:8.1f}"
        )
    for note in notes:
        print(f"note: {note}")
    print(
        f"\nforward_pose_all, every assembly mode (batch {MODES_BATCH} sampled near home; compiled = the generated C "
        "pipeline; python = the same algorithm orchestrated over the NumPy kernels; tracker = one batched Newton step "
        f"of 1 mm / 0.1 deg; multi-start = scipy.optimize.root from {MULTISTART_STARTS} random starts)\n"
    )
    header = (
        f"{'mechanism':12s} {'deg':>4s} {'us/input':>10s} {'single us':>10s} {'python us/in':>12s} {'ratio':>7s} "
        f"{'tracker us':>9s} {'fpa/trk':>8s} {'multi-st us':>12s} {'ratio':>9s}   modes found (first inputs)"
    )
    print(header)
    print("-" * len(header))
    for name in parakin.available():
        line = modes_rows(name)
        if line:
            print(line)
    print(
        f"\nforward_pose_all on the papers' named inputs: {EXAMPLE_REPEATS} single-threaded calls each (us); worst = "
        f"smallest conditioning (type II distance sigma_min/sigma_max of the closure Jacobian) of a mode; multi-start = scipy.optimize.root from "
        f"{EXAMPLE_STARTS} random starts on the same input\n"
    )
    header = (
        f"{'mechanism':10s} {'example':16s} {'modes':>5s} {'median us':>10s} {'p10 us':>9s} {'p90 us':>9s} "
        f"{'worst':>10s} {'multi-st us':>12s} {'ratio':>7s} {'found':>6s}"
    )
    print(header)
    print("-" * len(header))
    for line in example_rows():
        print(line)
    print(
        f"\nsolver statistics (ikfast-style): forward_pose_all on up to {STATISTICS_INPUTS} inputs made by inverse "
        f"pose from sampled configurations (fewer where {STATISTICS_BUDGET:.0f} s of solving runs out: the inputs "
        f"column); missing = modes a {MULTISTART_STARTS}-start scipy search finds on the first "
        f"{STATISTICS_ORACLE} inputs that we do not; time per input over chunks of up to 1000\n"
    )
    header = (
        f"{'mechanism':12s} {'inputs':>7s} {'success':>9s} {'wrong':>6s} {'missing':>9s} {'modes':>6s} "
        f"{'median us':>9s} {'min us':>7s} {'max us':>7s}"
    )
    print(header)
    print("-" * len(header))
    for name in parakin.available():
        line = solver_statistics_row(name)
        if line:
            print(line)
    print(
        "\nforward_pose_all by method (* the default): elimination = a closed form written with the mechanism, "
        "homotopy = its own polynomial system, automatic = the polynomial form derived from the loop closure "
        "(root count proven at generation: total-degree homotopies or the trace test); us/input single-threaded on "
        "the same inputs, x default = time / the default's time, certified = inputs whose distinct certified roots "
        f"number the root count, threads x = one thread / {os.cpu_count()} threads on the same batch (default method)\n"
    )
    header = (
        f"{'mechanism':12s} {'method':13s} {'paths':>6s} {'us/input':>12s} {'x default':>9s} {'certified':>10s} "
        f"{'witnesses':>10s} {'threads x':>9s}"
    )
    print(header)
    print("-" * len(header))
    for name in parakin.available():
        for line in method_rows(name):
            print(line)
    bench.floor.main()
    print(
        "\nparakin.sweep: reachable + type II distance over a pose grid (chunks of 20,000); thousands of poses "
        "per second, scaling = one process / local threads and / 2-worker cluster (2 cores on this machine)\n"
    )
    header = (
        f"{'mechanism':12s} {'poses':>9s} {'1 process k/s':>14s} {'threads k/s':>14s} {'cluster k/s':>14s} "
        f"{'threads x':>9s} {'cluster x':>9s}"
    )
    print(header)
    print("-" * len(header))
    for line in sweep_rows():
        print(line)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as scratch:
        generate(None, Path(scratch) / "generated")
    print(
        f"\nmake generate, all {len(discover())} mechanisms in parallel (scratch directory): {time.perf_counter() - start:.1f} s"
    )


if __name__ == "__main__":
    main()
