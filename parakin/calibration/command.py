"""``parakin calibrate NAME DATA.csv``: calibrate a mechanism from a CSV of measurements.

The CSV has a header row naming its columns (``#`` starts a comment line): every actuated
variable (``parakin inspect NAME`` lists them; the encoder readings, m or rad), then the
measurement's columns for ``--kind``:

* ``pose``: ``x y z alpha beta gamma`` (m; Z-Y-X Euler angles in rad, ``parakin.pose_from_xyz_euler``);
* ``position``: ``x y z`` (m);
* ``z``: ``z`` (m);
* ``distance``: ``distance`` (m).

``--deg`` reads revolute actuated columns and the pose's angles in degrees. The output is a table
(or with ``--json`` one JSON object) of the free parameters with their standard errors, the
unidentifiable combinations, the rms before and after and O1..O5; ``--output FILE`` writes the
calibrated values as JSON (``{"parameters": {...}, "offsets": {...}, ...}``; the parameters go
back into ``--param NAME=VALUE`` or ``parakin.load(NAME, **parameters)``).

Errors (a malformed CSV, an unknown column or parameter) raise ``parakin.errors`` exceptions, which
the command line reports with exit status 2.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path
from typing import Any

import numpy as np

from parakin.calibration.data import KINDS, CalibrationData
from parakin.calibration.fit import CalibrationResult, calibrate
from parakin.calibration.rotation_vectors import rotation
from parakin.errors import CalibrationDataError
from parakin.mechanism import Mechanism
from parakin.pose import pose_from_xyz_euler

#: the measurement columns of each kind
COLUMNS = {
    "pose": ("x", "y", "z", "alpha", "beta", "gamma"),
    "position": ("x", "y", "z"),
    "z": ("z",),
    "distance": ("distance",),
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``parakin calibrate`` (module docstring)."""
    parser.add_argument("name", help="mechanism name (parakin list) or generated package folder")
    parser.add_argument(
        "data", nargs="?", default=None, help="CSV of measurements: actuated columns, then the kind's columns"
    )
    parser.add_argument(
        "--simulate",
        type=int,
        metavar="N",
        help="instead of a CSV: N simulated measurements of a robot whose length parameters differ from the "
        "nominal by N(0, --perturb), read with noise --sigma (what a campaign would identify)",
    )
    parser.add_argument("--perturb", type=float, default=1e-3, help="--simulate: the build errors, m (default 1e-3)")
    parser.add_argument("--seed", type=int, default=0, help="--simulate: the random seed (default 0)")
    parser.add_argument("--kind", choices=KINDS, default="pose", help="what was measured (default pose)")
    parser.add_argument("--sigma", type=float, required=True, help="measurement noise, one standard deviation (m)")
    parser.add_argument(
        "--sigma-angle", type=float, default=None, help="rotation noise of poses (rad; needed for --kind pose)"
    )
    parser.add_argument("--deg", action="store_true", help="revolute actuated columns and pose angles in degrees")
    parser.add_argument(
        "--unknown", action="append", choices=("tracker", "tool"), default=[], help="a frame to estimate (repeat)"
    )
    parser.add_argument("--free", default=None, help="comma-separated parameters to estimate (default: all)")
    parser.add_argument("--fix", action="append", default=[], metavar="NAME", help="hold a parameter (repeat)")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE", help="nominal parameter (SI)")
    parser.add_argument("--backend", default="auto", choices=["auto", "compiled", "numpy", "casadi"])
    parser.add_argument("--json", action="store_true", help="the result as one JSON object")
    parser.add_argument("--output", default=None, help="write the calibrated values to this JSON file")


def read_csv(path: str | Path, m: Mechanism, kind: str, degrees: bool) -> tuple[np.ndarray, np.ndarray]:
    """Encoder readings (N, n_a) and measurements (kind's shape) from a CSV (module docstring).

    Raises
    ------
    CalibrationDataError
        A missing file or column, an unknown column, a value that is not a number.
    """
    try:
        with open(path, newline="") as handle:
            lines = [line for line in handle if line.strip() and not line.lstrip().startswith("#")]
    except OSError as error:
        raise CalibrationDataError(f"cannot read the measurements {str(path)!r}: {error.strerror}") from error
    rows = list(csv.reader(lines))
    if len(rows) < 2:
        raise CalibrationDataError(f"{path}: a header row and at least one measurement are needed")
    header = [cell.strip() for cell in rows[0]]
    needed = [*m.actuated_names, *COLUMNS[kind]]
    for name in header:
        if name not in needed:
            raise CalibrationDataError(f"{path}: unknown column {name!r}; kind {kind!r} of {m.name} reads {needed}")
    for name in needed:
        if name not in header:
            raise CalibrationDataError(f"{path}: no column {name!r} (kind {kind!r} of {m.name} reads {needed})")
    values = np.zeros((len(rows) - 1, len(needed)))
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise CalibrationDataError(f"{path} line {line}: {len(row)} values for {len(header)} columns")
        for k, name in enumerate(needed):
            text = row[header.index(name)].strip()
            try:
                values[line - 2, k] = float(text)
            except ValueError as error:
                raise CalibrationDataError(f"{path} line {line}, column {name!r}: {text!r} is not a number") from error
    n_a = len(m.actuated_names)
    readings, measured = values[:, :n_a], values[:, n_a:]
    if degrees:
        revolute = np.array([v.revolute for v in m.manifest.actuated])
        readings[:, revolute] = np.deg2rad(readings[:, revolute])
        if kind == "pose":
            measured[:, 3:] = np.deg2rad(measured[:, 3:])
    if kind == "pose":
        return readings, pose_from_xyz_euler(measured)
    return readings, measured if kind == "position" else measured[:, 0]


def record(result: CalibrationResult) -> dict[str, Any]:
    """The result as a JSON-ready dict."""
    return {
        "mechanism": result.mechanism.name,
        "free": list(result.names),
        "values": {name: result.values[name] for name in result.names},
        "standard_errors": {k: (v if np.isfinite(v) else None) for k, v in result.standard_errors.items()},
        "rank": result.rank,
        "identifiable": list(result.identifiable),
        "unidentifiable": [str(c) for c in result.unidentifiable],
        "rms_before": result.rms_before,
        "rms_after": result.rms_after,
        "observability": result.observability,
        "iterations": result.iterations,
        "seconds": result.seconds,
        "parameters": dict(result.mechanism.parameters),
        "offsets": result.offsets,
        "scales": {k: v for k, v in result.values.items() if k.endswith("_scale")},
        "tracker": {k: v for k, v in result.values.items() if k.startswith("tracker_")},
        "tool": {k: v for k, v in result.values.items() if k.startswith("tool_")},
    }


def run(args: argparse.Namespace) -> int:
    """Run ``parakin calibrate``: 0 after a fit (its output printed), errors raised as
    ``parakin.errors`` exceptions (exit status 2 on the command line)."""
    from parakin.loading import load

    parameters: dict[str, Any] = {}
    for item in args.param:
        name, sep, text = item.partition("=")
        if not sep:
            raise CalibrationDataError(f"--param takes NAME=VALUE, got {item!r}")
        try:
            parameters[name.strip()] = json.loads(text)
        except ValueError as error:
            raise CalibrationDataError(f"--param {name}: {text!r} is not a number or a JSON list") from error
    m = load(args.name, backend=args.backend, **parameters)
    truth: dict[str, float] | None = None
    planned: np.ndarray | None = None
    if (args.data is None) == (args.simulate is None):
        raise CalibrationDataError("give the measurements DATA.csv, or --simulate N for a simulated campaign")
    if args.simulate is not None:
        readings, measured, truth, planned = simulate(m, args.kind, args.simulate, args.sigma, args.sigma_angle, args)
    else:
        readings, measured = read_csv(args.data, m, args.kind, args.deg)
    sigma: float | tuple[float, float] = args.sigma
    if args.kind == "pose":
        if args.sigma_angle is None:
            raise CalibrationDataError("--kind pose needs --sigma-angle (the rotation noise, rad)")
        sigma = (args.sigma, args.sigma_angle)
    elif args.sigma_angle is not None:
        raise CalibrationDataError(f"--sigma-angle is for --kind pose, not {args.kind!r}")
    data = CalibrationData(
        readings, measured, kind=args.kind, sigma=sigma, unknown=tuple(args.unknown), passive=planned
    )
    free = None if args.free is None else [name.strip() for name in args.free.split(",") if name.strip()]
    result = calibrate(m, data, free=free, fixed=args.fix)
    output = record(result)
    if args.output is not None:
        try:
            Path(args.output).write_text(json.dumps(output, indent=2) + "\n")
        except OSError as error:
            raise CalibrationDataError(f"cannot write {args.output!r}: {error.strerror}") from error
    if truth is not None:
        errors = {
            name: (abs(m.parameters[name] - value), abs(result.values.get(name, m.parameters[name]) - value))
            for name, value in truth.items()
        }
        output["simulated"] = {"truth": truth, "error_before": {k: v[0] for k, v in errors.items()},
                               "error_after": {k: v[1] for k, v in errors.items()}}  # fmt: skip
    print(json.dumps(output) if args.json else result.summary())
    if truth is not None and not args.json:
        identified = [name for name in errors if name in result.identifiable] or list(errors)
        worst_before = max(errors[name][0] for name in identified)
        worst_after = max(errors[name][1] for name in identified)
        print(
            f"simulated: {len(readings)} measurements of a robot built {args.perturb:g} m (1 sigma) off its "
            f"drawing: largest error of an identifiable length parameter {worst_before:.3g} m before, "
            f"{worst_after:.3g} m after"
        )
    return 0


def simulate(
    m: Mechanism, kind: str, count: int, sigma: float, sigma_angle: float | None, args: argparse.Namespace
) -> tuple[np.ndarray, np.ndarray, dict[str, float], np.ndarray]:
    """A simulated campaign: encoder readings (N, n_a), the kind's measurements with noise, the
    true length parameters (the nominal ones plus N(0, ``args.perturb``)). The readings are
    the drawing's inverse at poses ``design_poses`` chooses near the home; the measurements come
    from the true robot's own forward kinematics there, not from the residual the fit uses; and
    the planned passive values (N, n_p): the modes the campaign commanded, the fit's start."""
    from parakin.calibration.design import design_poses
    from parakin.errors import BadInputError
    from parakin.log import logger
    from parakin.mechanism import Mechanism as Model
    from parakin.studies.sampling import sample_configurations

    if kind not in ("pose", "position", "z"):
        raise CalibrationDataError(f"--simulate makes pose, position or z measurements, not {kind!r}")
    if count < 1 or not np.isfinite(args.perturb) or args.perturb < 0:
        raise CalibrationDataError(f"--simulate N >= 1 and --perturb >= 0 needed, got {count}, {args.perturb}")
    for flag, value in (("--sigma", sigma), ("--sigma-angle", sigma_angle)):
        if value is not None and not (np.isfinite(value) and value > 0):
            raise CalibrationDataError(
                f"{flag} must be a positive number (the noise's standard deviation), got {value}"
            )
    rng = np.random.default_rng(args.seed)
    truth = {
        p.name: float(m.parameters[p.name] + rng.normal(0.0, args.perturb))
        for p in m.manifest.parameters
        if p.unit == "m"
    }
    robot = Model(m.package, m.backend, {**m.parameters, **truth}, m.limits, m.actuated_ranges)
    # the campaign as one would plan it: poses chosen by design_poses (O1) among configurations
    # near the home of the drawing, away from singularities (its margin), commanded through the
    # drawing's inverse; the robot as built goes where its own forward kinematics take it
    candidates = sample_configurations(m, max(8 * count, 200), spread=0.1, seed=args.seed)
    plan_sigma = sigma if kind != "pose" else (sigma, sigma_angle or sigma)
    try:
        try:
            design = design_poses(m, candidates.pose, count, kind=kind, sigma=plan_sigma)
        except CalibrationDataError:  # fewer candidates away from singularities than asked for: all of them
            probe = design_poses(m, candidates.pose, 1, kind=kind, sigma=plan_sigma, exchange=False)
            design = design_poses(m, candidates.pose, probe.eligible, kind=kind, sigma=plan_sigma)
    except (CalibrationDataError, BadInputError) as error:
        raise CalibrationDataError(f"no campaign of {m.name} near its home could be planned: {error}") from error
    eligible = design.eligible
    state = robot.forward_pose(design.actuated, guess=design.poses, strict=False)
    built = np.asarray(state.converged)
    if not built.any():
        raise CalibrationDataError(f"no planned configuration of {m.name} closed for the simulated robot")
    if built.sum() < count:
        logger.warning(
            "the simulated campaign has %d of the %d measurements asked for: %s",
            int(built.sum()), count,
            f"{eligible} configurations near the home are away from singularities"
            if eligible < count else f"{int((~built).sum())} did not close on the robot as built",
        )  # fmt: skip
    readings = np.asarray(design.actuated, dtype=float)[built]
    # the planned configurations (the drawing's): the modes the robot was commanded in
    planned = np.asarray(candidates.passive, dtype=float)[design.indices][built]
    pose = np.array(state.pose, dtype=float)[built]
    position = pose[:, :3, 3] + rng.normal(0.0, sigma, (len(pose), 3))
    if kind == "pose":
        turn = rng.normal(0.0, sigma_angle or 0.0, (len(pose), 3))
        noisy = pose.copy()
        noisy[:, :3, :3] = pose[:, :3, :3] @ np.stack([rotation(t) for t in turn])
        noisy[:, :3, 3] = position
        return readings, noisy, truth, planned
    return readings, position if kind == "position" else position[:, 2], truth, planned


__all__ = ["COLUMNS", "add_arguments", "read_csv", "record", "run", "simulate"]
