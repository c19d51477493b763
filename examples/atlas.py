"""Design-study atlases with ``parakin.sweep``: the figures of the sweep issue.

    python examples/atlas.py [OUTPUT_FOLDER]     (default: atlas/)

- SAM: a constant-orientation workspace slice (x, y at z = 0.68 m, level platform) coloured by the
  distance to a type II singularity, and its assembly-mode count over two actuated angles
  (theta1, theta4; the other inputs as in eq (15), the paper's symmetric nominal configuration,
  which is a type II singularity): on the diagonal the elimination degenerates
  (parallel U-joint axes), the count is missing there and ``modes_status`` says 'degenerate',
  drawn as a hatched region;
- SPM: the orientation workspace (alpha, beta at gamma = 0) with the type II distance, and the
  design space: workspace volume over the two link angles alpha1, alpha2;
- five-bar: the reachable region (the analytic workspace of the test) and its singularity map.
Each figure is computed on dask's local scheduler; pass --scheduler ADDRESS to use a cluster.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np

from parakin import sweep
from parakin.studies.atlas import plot_sweep


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output", nargs="?", default="atlas")
    parser.add_argument("--scheduler", default=None)
    args = parser.parse_args()
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    # name, mechanism, quantities, axes, options of sweep, the quantity drawn
    figures: list[tuple[str, str, list[str], dict[str, Any], dict[str, Any], str]] = [
        (
            "sam_workspace_type_ii",
            "sam",
            ["reachable", "type_ii_distance"],
            {"x": np.linspace(-0.9, 0.9, 121), "y": np.linspace(-0.9, 0.9, 121)},
            {"fixed": {"z": 0.68, "alpha": 0.0, "beta": 0.0, "gamma": 0.0}},
            "type_ii_distance",
        ),
        (
            "sam_mode_count",
            "sam",
            ["modes"],
            {"theta1": np.linspace(-0.6, 0.6, 61), "theta4": np.linspace(-0.6, 0.6, 61)},
            {"fixed": {"theta2": -np.pi / 12, "theta3": 0.0, "theta5": np.pi / 12, "theta6": 0.0}},  # eq (15)
            "modes",
        ),
        (
            "spm_orientation_workspace_type_ii",
            "spm",
            ["reachable", "type_ii_distance"],
            {"alpha": np.linspace(-np.pi, np.pi, 121), "beta": np.linspace(-1.5, 1.5, 91)},
            {"fixed": {"gamma": 0.0}},
            "type_ii_distance",
        ),
        (
            "spm_design_space_workspace_volume",
            "spm",
            ["workspace_volume"],
            {"alpha1": np.linspace(0.5, 1.6, 12), "alpha2": np.linspace(0.5, 1.6, 12)},
            {
                "workspace": {
                    "alpha": np.linspace(-np.pi, np.pi, 13),
                    "beta": np.linspace(-1.5, 1.5, 11),
                    "gamma": np.linspace(-np.pi, np.pi, 13),
                }
            },
            "workspace_volume",
        ),
        (
            "five_bar_singularity_map",
            "five_bar",
            ["reachable", "type_ii_distance", "type_i_distance"],
            {"x": np.linspace(-0.5, 0.5, 161), "y": np.linspace(-0.4, 0.6, 161)},
            {},
            "type_ii_distance",
        ),
    ]
    for name, mechanism, quantities, axes, options, shown in figures:
        began = time.perf_counter()
        result = sweep(mechanism, quantities, axes, scheduler=args.scheduler, **options)
        path = out / f"{name}.png"
        plot_sweep(result, shown, str(path))
        points = int(np.prod([len(v) for v in axes.values()]))
        summary = ", ".join(f"{q} {_mean(result[q].values)}" for q in result.data_vars)
        print(f"{path}: {points} points in {time.perf_counter() - began:.1f} s; means: {summary}")


def _mean(values: np.ndarray) -> str:
    """The mean over the defined (finite) values, and how many there are."""
    array = np.asarray(values, dtype=float)
    finite = array[np.isfinite(array)]
    return (
        f"{finite.mean():.3g} ({finite.size}/{array.size} defined)" if finite.size else f"none of {array.size} defined"
    )


if __name__ == "__main__":
    main()
