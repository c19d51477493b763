"""Benchmark rows for the 6-SPS with linearly related planar platforms (``mechanisms/gough.py``):
inverse pose, Newton forward pose and the closed-form forward pose (every mode), against a
baseline in the same run: scipy.optimize.root on the six leg equations (NumPy), per pose, from the
same guess (Newton) or from 8 spread starts (every mode)."""

from __future__ import annotations

import time
from collections.abc import Callable
from functools import partial

import numpy as np
import scipy.optimize

import parakin
from bench.timing import best_time
from parakin import architecture

#: a usable geometry near section 5.4's (A4 moved off the conic), metres
GEOMETRY: dict[str, float] = {"yA4": 1.0}


def _poses(rng: np.random.Generator, count: int) -> np.ndarray:
    values = np.column_stack(
        [
            rng.uniform(-3, 3, count),
            rng.uniform(-3, 3, count),
            rng.uniform(25, 35, count),
            *(rng.uniform(-0.3, 0.3, count) for _ in range(3)),
        ]
    )
    return parakin.pose_from_xyz_euler(values)


def rows(record: Callable[[str, str, int, float, float], None]) -> None:
    """Add rows through ``record(operation, backend, batch, seconds, baseline_seconds_per_pose)``."""
    rng = np.random.default_rng(2028)
    poses = _poses(rng, 10_000)
    geometry = architecture.Geometry.from_parameters({**parakin.metadata("gough")["parameters"], **GEOMETRY})
    lengths = geometry.leg_lengths(poses)
    guesses = parakin.xyz_euler_from_pose(poses) + rng.normal(0, 0.01, (poses.shape[0], 6))

    def residual(q: np.ndarray, target: np.ndarray) -> np.ndarray:
        return geometry.leg_lengths(parakin.pose_from_xyz_euler(q)) - target

    n = 50
    start = time.perf_counter()
    for k in range(n):
        scipy.optimize.root(residual, guesses[k], args=(lengths[k],), tol=1e-12)
    base_forward = (time.perf_counter() - start) / n
    base_all = 8 * base_forward
    base_inverse = best_time(lambda: geometry.leg_lengths(poses[:1000])) / 1000

    for backend in ["numpy", "compiled"]:
        try:
            m = parakin.load("gough", backend, None, **GEOMETRY)
        except (parakin.ParakinError, OSError):  # e.g. no compiled library for it yet
            continue
        for batch in [1, 1000, 10_000]:
            p: np.ndarray = poses[:batch]
            a: np.ndarray = lengths[:batch]
            g: np.ndarray = guesses[:batch]
            if batch == 1:
                p, a, g = p[0], a[0], g[0]
            record("gough inverse_pose", backend, batch, best_time(partial(m.inverse_pose, p)), base_inverse)
            record(
                "gough forward_pose (Newton)",
                backend,
                batch,
                best_time(partial(m.forward_pose, a, g, strict=False)),
                base_forward,
            )
            if batch <= 1000:
                record(
                    "gough forward_pose_all (quartic)",
                    backend,
                    batch,
                    best_time(partial(m.forward_pose_all, a)),
                    base_all,
                )
