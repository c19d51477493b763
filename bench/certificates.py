"""``python -m bench.certificates [--inputs N] [NAME...]``: the per-input certificate of every
homotopy method (``forward_pose_all(..., method=...)``) on N random inputs per mechanism.

Inputs are the actuated values of closed configurations sampled around each home (so every one
has at least its generating mode). Per mechanism and method the table counts the inputs whose
answer is certified complete (distinct Krawczyk-certified roots == the proven root count), the
inputs tracked again in projective space (``retracked``; complete or not after it) and
those left uncertified, with the mean uncertified paths of those, the time per input and the
proof of the root count stored at generation.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import parakin
from parakin.studies.sampling import sample_configurations


def statistics(name: str, inputs: int, seed: int = 19, others: int | None = None) -> list[dict[str, object]]:
    """One record per homotopy method of ``name`` (an empty list where there is none); methods
    other than the default (orchestrated in NumPy, slower) on the first ``others`` inputs."""
    m = parakin.load(name, backend="compiled")
    rows: list[dict[str, object]] = []
    homotopies = {k: v for k, v in m.capabilities.forward_methods.items() if v.homotopy is not None}
    if not homotopies:
        return rows
    sample = sample_configurations(m, 2 * inputs, spread=0.08, seed=seed)
    for method, info in homotopies.items():
        assert info.homotopy is not None and info.homotopy.root_count is not None
        theta = sample.actuated[: inputs if info is m.capabilities.forward or others is None else others]
        began = time.perf_counter()
        modes = m.forward_pose_all(theta, strict=False, method=method)
        seconds = time.perf_counter() - began
        certificate = modes.certificate()
        complete = np.asarray(certificate["certified_roots"]) == info.homotopy.root_count.count
        retracked = np.asarray(certificate["retracked"], bool)
        rows.append(
            {
                "mechanism": name,
                "method": method,
                "inputs": int(theta.shape[0]),
                "root_count": info.homotopy.root_count.count,
                "proven": bool(info.homotopy.root_count.proven),
                "complete": int(complete.sum()),
                "first_run_complete": int((complete & ~retracked).sum()),
                "retracked": int(retracked.sum()),
                "uncertified": int((~complete).sum()),
                "uncertified_paths": float(np.asarray(certificate["uncertified_paths"])[~complete].mean())
                if (~complete).any()
                else 0.0,
                "us_per_input": seconds / max(theta.shape[0], 1) * 1e6,
            }
        )
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.certificates", description=__doc__)
    parser.add_argument("names", nargs="*", help="mechanisms (default: every available one)")
    parser.add_argument("--inputs", type=int, default=1000, help="random inputs per mechanism")
    parser.add_argument("--others", type=int, help="inputs for the methods other than the default (default: --inputs)")
    args = parser.parse_args(argv)
    header = (
        f"{'mechanism':12s} {'method':10s} {'roots':>6s} {'proven':>6s} {'inputs':>7s} {'complete':>9s} "
        f"{'1st run':>8s} {'retracked':>9s} {'uncert.':>8s} {'paths/unc':>9s} {'us/input':>10s}"
    )
    print(header)
    print("-" * len(header))
    for name in args.names or parakin.available():
        for row in statistics(name, args.inputs, others=args.others):
            print(
                f"{row['mechanism']:12s} {row['method']:10s} {row['root_count']:6d} {('yes' if row['proven'] else 'no'):>6s} "
                f"{row['inputs']:7d} {row['complete']:9d} {row['first_run_complete']:8d} {row['retracked']:9d} "
                f"{row['uncertified']:8d} {row['uncertified_paths']:9.2f} {row['us_per_input']:10.1f}",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
