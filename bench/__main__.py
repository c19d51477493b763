"""``make bench``: time per call and per pose of SAM's solvers on every backend, next to a
baseline measured in the same run (sympy.lambdify of the same equations + scipy.optimize.root),
and Newton's iteration counts and failure rate over 10^4 random reachable poses.

Ratios are baseline time / parakin time (higher is faster than the baseline).
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np
import scipy.optimize
import sympy as sp

import parakin
from bench import gough, sps
from bench.timing import best_time
from parakin.generator.build import generate

BATCHES = [1, 1000, 100_000]
BASELINE_POSES = 200  # the scipy baseline loops in Python: timed on this many, reported per pose


def random_reachable(rng: np.random.Generator, count: int) -> np.ndarray:
    values = np.column_stack(
        [
            rng.uniform(-0.15, 0.15, count),
            rng.uniform(-0.15, 0.15, count),
            rng.uniform(0.5, 0.9, count),
            *(rng.uniform(-0.45, 0.45, count) for _ in range(3)),
        ]
    )
    return parakin.pose_from_xyz_euler(values)


class Baseline:
    """sympy.lambdify of parakin's own symbolic equations, solved by scipy.optimize.root."""

    def __init__(self, name: str = "sam") -> None:
        objects = parakin.symbolic(name)
        info = parakin.metadata(name)
        symbols = {s.name: s for obj in objects.values() if isinstance(obj, sp.Basic) for s in obj.free_symbols}
        actuated = [symbols[n] for n in info["actuated"]]
        passive = [symbols[n] for n in info["passive"]]
        params = [symbols[n] for n in info["parameters"]]
        self.params = list(info["parameters"].values())
        self._passive_count = len(passive)
        self.residual = sp.lambdify([actuated, passive, params], list(objects["loop_closure"]), "numpy")
        jacobian = objects["loop_closure"].jacobian(passive)
        self.jacobian = sp.lambdify([actuated, passive, params], jacobian, "numpy")
        steps = objects["inverse_steps"]
        substituted: dict = {}
        for target, value in steps:
            substituted[target] = value.subs(substituted)
        pose_symbols = sp.symbols("r11 r12 r13 r21 r22 r23 r31 r32 r33 px py pz", real=True)
        branches = [symbols.get(b, sp.Symbol(b, real=True)) for b in info["inverse"]["branches"]]
        self.combinations = np.array(info["inverse"]["combinations"], dtype=float)
        outputs = [substituted[symbols[n]] for n in info["actuated"] + info["passive"]]
        self.inverse = sp.lambdify([pose_symbols, branches, params], outputs, "numpy")

    def forward_all(self, actuated: np.ndarray, starts: int, rng: np.random.Generator) -> None:
        """The baseline for every mode: scipy.optimize.root from ``starts`` random starts per input
        (what a user without the closed form would do; it does not guarantee every mode)."""
        for i in range(actuated.shape[0]):
            for _ in range(starts):
                guess = rng.uniform(-np.pi, np.pi, self._passive_count)
                scipy.optimize.root(
                    lambda q, a=actuated[i]: self.residual(a, q, self.params),
                    guess,
                    jac=lambda q, a=actuated[i]: self.jacobian(a, q, self.params),
                    tol=1e-12,
                )

    def forward(self, actuated: np.ndarray, guess: np.ndarray) -> np.ndarray:
        out = np.empty_like(guess)
        for i in range(actuated.shape[0]):
            solution = scipy.optimize.root(
                lambda q, a=actuated[i]: self.residual(a, q, self.params),
                guess[i],
                jac=lambda q, a=actuated[i]: self.jacobian(a, q, self.params),
                tol=1e-12,
            )
            out[i] = solution.x
        return out

    def inverse_all(self, poses: np.ndarray) -> list:
        flat = np.concatenate([poses[:, :3, :3].reshape(-1, 9), poses[:, :3, 3]], axis=1).T
        return [self.inverse(flat, signs, self.params) for signs in self.combinations]


def spm_rows() -> list:
    """3-RRR SPM: inverse pose (8 branches) and every assembly mode (degree-8 polynomial)."""
    rng = np.random.default_rng(2027)
    baseline = Baseline("spm")
    out: list = []
    m_any = parakin.load("spm", backend="numpy")
    rotations = parakin.pose_from_xyz_euler(
        np.column_stack([np.zeros((10_000, 3)), rng.uniform(-0.6, 0.6, (10_000, 3))])
    )
    branches = m_any.inverse_pose(rotations, strict=False)
    keep = branches.valid.any(-1)
    first = np.argmax(branches.valid, axis=-1)
    actuated = np.take_along_axis(branches.actuated, first[:, None, None], axis=1)[:, 0][keep]
    rotations = rotations[keep]
    n = 50
    base_inverse = best_time(lambda: baseline.inverse_all(rotations[:n])) / n
    base_all = best_time(lambda: baseline.forward_all(actuated[:5], 16, rng), budget=1.0) / 5
    for backend in ["numpy", "compiled"]:
        m = parakin.load("spm", backend=backend)
        for batch in [1, 1000, 10_000]:
            batch = min(batch, actuated.shape[0])
            p, a = (rotations[0], actuated[0]) if batch == 1 else (rotations[:batch], actuated[:batch])
            t = best_time(lambda m=m, p=p: m.inverse_pose(p, strict=False))
            out.append(
                (
                    "spm inverse_pose (8 branches)",
                    backend,
                    batch,
                    t * 1e6,
                    t / batch * 1e6,
                    base_inverse * 1e6,
                    base_inverse * batch / t,
                )
            )
            t = best_time(lambda m=m, a=a: m.forward_pose_all(a), budget=0.2)
            out.append(
                (
                    "spm forward_pose_all (deg 8)",
                    backend,
                    batch,
                    t * 1e6,
                    t / batch * 1e6,
                    base_all * 1e6,
                    base_all * batch / t,
                )
            )
    return out


def main() -> None:
    rng = np.random.default_rng(2026)
    backends = {name: parakin.load("sam", backend=name) for name in ["numpy", "casadi", "compiled"]}
    poses = random_reachable(rng, max(BATCHES))
    reference = backends["compiled"].inverse_pose(poses)
    configs = reference.branch(2)
    guess = configs.passive + rng.normal(0, 0.01, configs.passive.shape)  # a tracking-quality guess
    actuated = configs.actuated

    start = time.perf_counter()
    baseline = Baseline()
    setup = time.perf_counter() - start
    n = BASELINE_POSES
    base_inverse = best_time(lambda: baseline.inverse_all(poses[:n])) / n
    base_forward = best_time(lambda: baseline.forward(actuated[:n], guess[:n]), budget=1.0) / n
    base_all = 4 * base_forward  # one root solve per possible assembly mode (4), from spread starts

    rows = []

    def record(operation: str, backend: str, batch: int, seconds: float, baseline_per_pose: float) -> None:
        per_pose = seconds / batch
        rows.append(
            (
                operation,
                backend,
                batch,
                seconds * 1e6,
                per_pose * 1e6,
                baseline_per_pose * 1e6,
                baseline_per_pose / per_pose,
            )
        )

    for backend, m in backends.items():
        for batch in BATCHES:
            if backend == "casadi" and batch == max(BATCHES):
                continue  # DM conversion of 10^5 poses is minutes, not a use case for this path
            p, a, g = poses[:batch], actuated[:batch], guess[:batch]
            if batch == 1:
                p, a, g = p[0], a[0], g[0]
            record(
                "inverse_pose (16 branches)",
                backend,
                batch,
                best_time(lambda m=m, p=p: m.inverse_pose(p)),
                base_inverse,
            )
            record(
                "forward_pose (Newton)",
                backend,
                batch,
                best_time(lambda m=m, a=a, g=g: m.forward_pose(a, g)),
                base_forward,
            )
            record("forward_pose_all", backend, batch, best_time(lambda m=m, a=a: m.forward_pose_all(a)), base_all)
    compiled = backends["compiled"]
    # a 1 kHz control loop: each solve starts from the previous one, the platform having moved
    # 0.1 mm and 0.01 deg per axis since; the tracker alternates between the two poses
    step = np.array([1e-4, 1e-4, 1e-4, *np.deg2rad([0.01, 0.01, 0.01])])
    moved = compiled.inverse_pose(parakin.pose_from_xyz_euler(parakin.xyz_euler_from_pose(poses) + step)).branch(2)
    for batch in [1, 1000, 100_000]:
        tracker = compiled.tracker(parakin.Configuration(actuated[:batch], configs.passive[:batch], poses[:batch]))
        targets = [moved.actuated[:batch], actuated[:batch]]
        flip = iter(range(10**9))

        def solve(tracker=tracker, targets=targets, flip=flip) -> None:
            tracker.solve(targets[next(flip) % 2])

        record("tracker.solve (1 kHz step)", "compiled", batch, best_time(solve), base_forward)

    rows += spm_rows()
    gough.rows(record)
    sps.rows(record)

    print(
        "benchmark (baseline: sympy.lambdify of the same equations + scipy.optimize.root; for all modes,\n"
        f"root from 16 random starts per input for SPM, 4 for SAM; SAM baseline set-up {setup:.1f} s, timed on {n} poses)\n"
    )
    header = f"{'operation':28s} {'backend':9s} {'batch':>7s} {'us/call':>11s} {'us/pose':>9s} {'baseline us/pose':>17s} {'ratio':>8s}"
    print(header)
    print("-" * len(header))
    for operation, backend, batch, call, per_pose, base, ratio in rows:
        print(f"{operation:28s} {backend:9s} {batch:7d} {call:11.1f} {per_pose:9.3f} {base:17.1f} {ratio:8.1f}")

    # Newton statistics over 10^4 random reachable poses
    count = 10_000
    stats_poses = random_reachable(np.random.default_rng(7), count)
    configs = compiled.inverse_pose(stats_poses).branch(2)
    away = np.abs(compiled.singularities(configs)["closed_loop_determinant"]) > 1e-3
    print(
        f"\nNewton over {count} random reachable poses ({int((~away).sum())} within 1e-3 of a type II singularity excluded):"
    )
    for label, start_guess in [
        (
            "tracking guess (passive + N(0, 0.01))",
            configs.passive + np.random.default_rng(8).normal(0, 0.01, configs.passive.shape),
        ),
        (
            "tracking guess (passive + N(0, 0.05))",
            configs.passive + np.random.default_rng(9).normal(0, 0.05, configs.passive.shape),
        ),
        ("no guess (closed-form mode nearest home)", None),
    ]:
        result = compiled.forward_pose(configs.actuated, start_guess, strict=False)
        correct = result.converged & (np.abs(result.pose - stats_poses).max(axis=(-2, -1)) < 1e-9)
        iterations = result.iterations[away & result.converged]
        print(
            f"  {label:42s} converged {result.converged[away].mean():7.2%}  to the commanded pose {correct[away].mean():7.2%}"
            f"  iterations mean {iterations.mean():.2f} max {iterations.max()}"
        )
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as scratch:
        generate(["sam"], Path(scratch) / "generated")
    print(f"\nmake generate for SAM (into a scratch directory): {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
