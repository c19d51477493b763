"""``python -m bench.calibration [--campaigns N] [--backend B ...]``: the figures of issue 35.

A symmetric 6-6 hexapod (``stewart`` package, joints in pairs on 0.5 m and 0.3 m circles) built
with every joint coordinate and leg offset off by N(0, 1 mm), measured at 40 random poses about
(0, 0, 0.7) m by a tracker with 20 um / 0.002 deg noise; readings from the true robot's
closed-form inverse. Per backend: the time per fit (best of repeated runs) with known and with
unknown tracker and tool frames, the rank and null-space dimension; then over N campaigns the
coverage of the 95 % intervals, the z-scores' standard deviation, the rms after over its
noise-predicted value, and held-out accuracy. The delta (its own 4 parameters and 3 encoder
offsets) with xyz positions and with z-only probing and an unknown bed height: null dimensions.
"""

from __future__ import annotations

import argparse
import time
from functools import partial
from typing import Any

import numpy as np

import parakin
from bench.timing import best_time
from parakin.calibration import CalibrationData, calibrate, prediction_covariance
from parakin.calibration.rotation_vectors import rotation

SIGMA = (20e-6, np.deg2rad(0.002))


def hexapod() -> dict[str, Any]:
    base, platform = [], []
    for k in range(3):
        for s in (-1, 1):
            a, b = np.deg2rad(120 * k + 12 * s), np.deg2rad(120 * k + 60 - 48 * s)
            base.append([0.5 * np.cos(a), 0.5 * np.sin(a), 0.0])
            platform.append([0.3 * np.cos(b), 0.3 * np.sin(b), 0.0])
    return {"base": np.array(base), "platform": np.array(platform)}


def poses(rng: np.random.Generator, n: int) -> np.ndarray:
    out = np.zeros((n, 4, 4))
    out[:, 3, 3] = 1.0
    out[:, :3, 3] = [0.0, 0.0, 0.7] + rng.uniform(-0.1, 0.1, (n, 3))
    for k in range(n):
        out[k, :3, :3] = rotation(rng.uniform(-0.15, 0.15, 3))
    return out


def campaign(m: parakin.Mechanism, rng: np.random.Generator, n: int = 40, frames: bool = False):
    names = [p.name for p in m.manifest.parameters]
    true = dict(zip(names, m.params + rng.normal(0.0, 1e-3, m.params.size), strict=True))
    offsets = rng.normal(0.0, 1e-3, 6)
    truth = parakin.load(m.package.path, backend=m.backend.name, **true)
    at = poses(rng, n)
    readings = truth.inverse_pose(at).actuated[:, 0] - offsets
    tracker, tool = np.eye(4), np.eye(4)
    if frames:
        tracker[:3, :3], tracker[:3, 3] = rotation(np.array([0.02, -0.01, 0.3])), [1.5, -0.4, 0.2]
        tool[:3, :3], tool[:3, 3] = rotation(np.array([0.01, 0.02, -0.02])), [0.01, 0.02, 0.05]
    seen = np.linalg.inv(tracker) @ at @ tool
    seen[:, :3, 3] += rng.normal(0.0, SIGMA[0], (n, 3))
    for k in range(n):
        seen[k, :3, :3] = seen[k, :3, :3] @ rotation(rng.normal(0.0, SIGMA[1], 3))
    unknown = ("tracker", "tool") if frames else ()
    truth_values = true | {f"l{k + 1}_offset": o for k, o in enumerate(offsets)}
    return CalibrationData(readings, seen, sigma=SIGMA, unknown=unknown), truth_values, truth, offsets


def stewart_rows(backend: str, campaigns: int) -> None:
    m = parakin.load("stewart", backend=backend, **hexapod())
    rng = np.random.default_rng(35)
    for frames in (False, True):
        data, _, _, _ = campaign(m, rng, frames=frames)
        result = calibrate(m, data)
        seconds = best_time(partial(calibrate, m, data), budget=2.0)
        ratio = result.singular_values[result.rank - 1] / result.singular_values[0]
        print(
            f"stewart {backend:9} frames {'unknown' if frames else 'known  '}: {len(result.names)} parameters, rank "
            f"{result.rank}, null {len(result.unidentifiable)}, s_min/s_max {ratio:.3g}, {result.iterations} "
            f"iterations, {seconds * 1e3:.1f} ms per fit"
        )
    scores, ratios, held = [], [], []
    started = time.perf_counter()
    for _ in range(campaigns):
        data, truth_values, truth, offsets = campaign(m, rng)
        result = calibrate(m, data)
        scores.append([(result.values[n] - truth_values[n]) / result.standard_errors[n] for n in result.names])
        rows = 6 * len(data)
        ratios.append(result.rms_after["position"] / (SIGMA[0] * np.sqrt(3 * (rows - result.rank) / rows)))
        at = poses(rng, 20)
        readings = truth.inverse_pose(at).actuated[:, 0] - offsets
        nominal = m.forward_pose(readings, guess=at).pose
        predicted, covariance = prediction_covariance(result, readings, guess=at)
        error = [np.sqrt(np.mean(np.sum((p[:, :3, 3] - at[:, :3, 3]) ** 2, axis=1))) for p in (nominal, predicted)]
        held.append([*error, np.sqrt(np.mean(np.trace(covariance, axis1=1, axis2=2)))])
    z = np.ravel(scores)
    h = np.array(held)
    print(
        f"stewart {backend:9} {campaigns} campaigns x 40 poses: coverage {np.mean(np.abs(z) < 1.959964):.3f}, z std "
        f"{z.std():.3f}, rms after / predicted max {max(ratios):.3f} (mean {np.mean(ratios):.3f}); held-out rms "
        f"{h[:, 0].mean() * 1e3:.2f} mm -> {h[:, 1].mean() * 1e3:.4f} mm (predicted {h[:, 2].mean() * 1e3:.4f} mm); "
        f"{(time.perf_counter() - started) / campaigns:.2f} s per campaign"
    )


def delta_rows(backend: str) -> None:
    m = parakin.load("delta", backend=backend)
    rng = np.random.default_rng(7)
    truth = parakin.load("delta", backend=backend, R=0.2007, r=0.0496, L=0.3512, l=1.2985)
    at = np.column_stack([rng.uniform(-0.25, 0.25, (40, 2)), rng.uniform(-1.35, -1.05, 40)])
    readings = truth.inverse_pose(at).actuated[:, 0] - np.array([0.004, -0.003, 0.002])
    xyz = CalibrationData(readings, at + rng.normal(0, 1e-5, at.shape), kind="position", sigma=1e-5)
    heights = CalibrationData(readings, at[:, 2] - 0.007 + rng.normal(0, 1e-5, 40), kind="z", sigma=1e-5)
    free = ["R", "r", "L", "l", "theta1_offset", "theta2_offset", "theta3_offset", "tracker_z"]
    for label, data, chosen in (("xyz", xyz, None), ("z + bed", heights, free)):
        result = calibrate(m, data, free=chosen)
        seconds = best_time(partial(calibrate, m, data, free=chosen), budget=1.0)
        print(
            f"delta   {backend:9} {label:8}: {len(result.names)} parameters, rank {result.rank}, null "
            f"{[str(c) for c in result.unidentifiable]}, smallest kept s/s_max "
            f"{result.singular_values[result.rank - 1] / result.singular_values[0]:.3g}, {seconds * 1e3:.1f} ms per fit"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--campaigns", type=int, default=40)
    parser.add_argument("--backend", action="append", default=None, choices=["compiled", "numpy", "casadi"])
    args = parser.parse_args()
    for backend in args.backend or ["compiled", "numpy"]:
        stewart_rows(backend, args.campaigns)
        delta_rows(backend)


if __name__ == "__main__":
    main()
