"""Benchmark rows for the 3(SPS)-S spherical platform (Knapczyk & Tora), for ``make bench``.

``rows(record)`` times inverse_pose, forward_pose (Newton) and forward_pose_all on every backend, on
leg lengths around section 5's machine configuration, next to a same-run baseline: per pose,
scipy.optimize.root on eq (7) in the Euler angles of eq (9) written directly in NumPy (the
forward baseline; forward_pose_all's is 8 such solves, the degree of the polynomial), and a Python
loop of |a_i - R b_ip| (the inverse baseline). ``record(operation, backend, batch, seconds,
baseline_seconds_per_pose)`` is bench/__main__.py's.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

import numpy as np
import scipy.optimize

import parakin
from bench.timing import best_time
from parakin import demos_sps as s5

BATCHES = [1, 1000, 10_000]  # forward_pose_all tries 16 candidates per input
BASELINE_POSES = 200


def _euler(angles: np.ndarray) -> np.ndarray:
    """Eq (9): Rx(alpha) Ry(beta) Rx(gamma)."""
    ca, sa, cb, sb, cg, sg = (f(a) for a in angles for f in (np.cos, np.sin))
    return np.array(
        [
            [cb, sb * sg, sb * cg],
            [sa * sb, -sa * cb * sg + ca * cg, -sa * cb * cg - ca * sg],
            [-ca * sb, ca * cb * sg + sa * cg, ca * cb * cg - sa * sg],
        ]
    )


def _inputs(m: parakin.Mechanism, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rotations within 0.3 rad of the machine's configuration, inside the strokes: (rotations,
    lengths, Euler angles); ``count`` of them (repeated if needed)."""
    rng = np.random.default_rng(2026)
    count *= 2
    machine = s5.configurations(m, s5.LENGTHS)[s5.MACHINE_ROOT][3]
    axes = rng.normal(size=(count, 3))
    axes *= rng.uniform(0, 0.3, (count, 1)) / np.linalg.norm(axes, axis=1, keepdims=True)
    k = np.zeros((count, 3, 3))
    k[:, 0, 1], k[:, 0, 2], k[:, 1, 2] = -axes[:, 2], axes[:, 1], -axes[:, 0]
    k -= np.swapaxes(k, 1, 2)
    angle = np.linalg.norm(axes, axis=1)[:, None, None]
    unit = k / np.maximum(angle, 1e-300)
    rotations = (np.eye(3) + np.sin(angle) * unit + (1 - np.cos(angle)) * unit @ unit) @ machine.rotation
    branches = m.inverse_pose(rotations, strict=False)
    keep = np.resize(np.nonzero(branches.valid[:, 0])[0], count // 2)
    return rotations[keep], branches.actuated[keep, 0], branches.passive[keep, 0]


def rows(record: Callable[[str, str, int, float, float], None]) -> None:
    reference = parakin.load("sps", backend="numpy")
    rotations, lengths, euler = _inputs(reference, max(BATCHES))
    guess = euler + np.random.default_rng(7).normal(0, 0.01, euler.shape)
    base, platform = s5.geometry(reference)
    n = BASELINE_POSES

    def baseline_inverse() -> None:
        for rotation in rotations[:n]:
            np.linalg.norm(base - (rotation @ platform.T).T, axis=1)

    def residual(angles: np.ndarray, target: np.ndarray) -> np.ndarray:
        return np.linalg.norm(base - (_euler(angles) @ platform.T).T, axis=1) - target

    def baseline_forward() -> None:
        for i in range(n):
            scipy.optimize.root(residual, guess[i], args=(lengths[i],), tol=1e-12)

    base_inverse = best_time(baseline_inverse) / n
    base_forward = best_time(baseline_forward, budget=1.0) / n
    for backend in ["numpy", "casadi", "compiled"]:
        m = parakin.load("sps", backend=backend)
        for batch in BATCHES:
            if backend == "casadi" and batch == max(BATCHES):
                continue  # DM conversion of large batches: not a use case for this path
            r, d, g = rotations[:batch], lengths[:batch], guess[:batch]
            if batch == 1:
                r, d, g = r[0], d[0], g[0]
            label = "sps "
            record(
                label + "inverse_pose (2 branches)",
                backend,
                batch,
                best_time(partial(m.inverse_pose, r)),
                base_inverse,
            )
            record(
                label + "forward_pose (Newton)",
                backend,
                batch,
                best_time(partial(m.forward_pose, d, g)),
                base_forward,
            )
            record(
                label + "forward_pose_all",
                backend,
                batch,
                best_time(partial(m.forward_pose_all, d)),
                8 * base_forward,
            )
