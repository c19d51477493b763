"""Command line: ``parakin list | inspect | demo | ik | fk | plot | sweep | view | generate | export |
calibrate | mjcf``.

Values are SI (metres, radians) unless a flag ends in ``-deg``: those convert revolute
variables (and Euler angles) from degrees and leave prismatic ones in metres. Exit status: 0 on
success (also when the reader of the output leaves early, as ``| head`` does), 1 when there is
no solution (no valid branch, no assembly mode, an example that does not reproduce), 2 on an
error (bad input, unknown mechanism, unsupported operation, a file that cannot be written), 3 on
an internal error (an exception parakin did not expect: a bug, please report it), 130 when
interrupted (Ctrl-C: ``parakin: interrupted``).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
from typing import Any, NoReturn

import numpy as np

import parakin
from parakin.errors import BadInputError, ParakinError, SelfMotionError
from parakin.log import logger
from parakin.packages.manifest import Manifest, Variable, unknown_name
from parakin.pose import POSE_KINDS, transform_from_pose
from parakin.results import RANGE_FAILURES, Configuration, certificate_verdict, certified_complete
from parakin.solvers.continuation import SelfMotion
from parakin.tables import pose_headers, pose_values, text_table


def _pose_arguments(coordinates: tuple[str, ...]) -> tuple[str, int]:
    """How a pose kind's values are given on the command line, and how many."""
    lengths = [c for c in coordinates if c in ("x", "y", "z")]
    angles = [c for c in coordinates if c not in lengths]
    words = [" ".join(lengths) + " (m)"] if lengths else []
    if angles:
        words.append(" ".join(angles) + (" (about z)" if angles == ["phi"] else " (Z-Y-X Euler)"))
    return " ".join(words), len(coordinates)


POSE_ARGUMENTS = {kind: _pose_arguments(info.coordinates) for kind, info in POSE_KINDS.items()}

#: exit status of an exception parakin did not expect (a bug): distinct from 1 (no solution)
#: and 2 (an error in the input or the environment)
INTERNAL_ERROR = 3


def _parameters(values: list[str]) -> dict[str, Any]:
    result: dict[str, Any] = {}
    for item in values:
        name, sep, text = item.partition("=")
        if not sep:
            raise BadInputError(f"--param takes NAME=VALUE, got {item!r}")
        try:
            result[name.strip()] = json.loads(text)
        except ValueError as error:
            raise BadInputError(f"--param {name}: {text!r} is not a number or a JSON list") from error
    return result


def _load(args: argparse.Namespace) -> parakin.Mechanism:
    """The mechanism with ``--param`` overrides: mechanism parameters only (a name such as
    ``limits`` or ``backend`` is no parameter, though ``load`` has a keyword of that name)."""
    parameters = _parameters(args.param)
    valid = parakin.metadata(args.name).parameter_names
    for key in parameters:
        if key not in valid:
            raise unknown_name("parameter", key, valid, str(args.name))
    return parakin.load(args.name, backend=args.backend, **parameters)


def _from_cli_units(variables: tuple[Variable, ...], values: list[float], degrees: bool) -> np.ndarray:
    array = np.array(values, dtype=float)
    if array.shape != (len(variables),):
        names = " ".join(f"{v.name}[{'deg' if degrees and v.revolute else v.unit}]" for v in variables)
        raise BadInputError(f"expected {len(variables)} values: {names}; got {len(values)}")
    if degrees:
        revolute = np.array([v.revolute for v in variables])
        array = np.where(revolute, np.deg2rad(array), array)
    else:
        # more than a full turn is legal but rarely meant: most often degrees given as radians
        turns = [
            f"{v.name} = {x:g}" for v, x in zip(variables, array, strict=True) if v.revolute and abs(x) > 2 * np.pi
        ]
        if turns:
            logger.warning(
                "%s rad: more than a full turn; values are radians (the flags ending in -deg take degrees)",
                ", ".join(turns),
            )
    return array


def _header(variable: Variable, degrees: bool) -> str:
    """A variable's column header: its name and unit (``deg`` for a revolute one with
    ``degrees``); a dimensionless variable (a quaternion component) has none."""
    unit = "deg" if degrees and variable.revolute else variable.unit
    return f"{variable.name} [{unit}]" if unit else variable.name


def _labelled(variables: tuple[Variable, ...], values: np.ndarray, degrees: bool) -> dict[str, float]:
    result = {}
    for v, x in zip(variables, np.asarray(values, dtype=float), strict=True):
        result[_header(v, degrees)] = float(np.rad2deg(x)) if degrees and v.revolute else float(x)
    return result


def _pose_from_cli(manifest: Manifest, values: list[float], degrees: bool) -> np.ndarray:
    kind = manifest.pose_kind
    described, count = POSE_ARGUMENTS[kind]
    array = np.array(values, dtype=float)
    if array.shape != (count,):
        raise BadInputError(f"{manifest.name} poses ({kind}) take {count} values: {described}; got {len(values)}")
    if not np.isfinite(array).all():  # before any conversion: the message names the value given
        first = int(np.flatnonzero(~np.isfinite(array))[0])
        raise BadInputError(
            f"pose value {first + 1} of {count} ({described}) is {values[first]}: values must be finite"
        )
    if kind == "transform":
        angles = np.deg2rad(array[3:]) if degrees else array[3:]
        return parakin.pose_from_xyz_euler(np.concatenate([array[:3], angles]))
    if kind == "rotation":
        angles = np.deg2rad(array) if degrees else array
        return parakin.euler_zyx_to_rotation(*angles)
    if kind == "planar":
        return np.array([array[0], array[1], np.deg2rad(array[2]) if degrees else array[2]])
    if kind == "planar_translation":  # ^B_P T = [I, (x, y, 0)]
        pose = np.eye(4)
        pose[:2, 3] = array
        return pose
    return array


def _describe_pose(manifest: Manifest, pose: np.ndarray, degrees: bool) -> dict[str, float]:
    """The coordinates of the pose kind (``parakin.tables.pose_headers``: the columns of every
    table of poses), labelled with their units."""
    values = pose_values(manifest.pose_kind, pose, degrees)
    return {k: float(v) for k, v in zip(pose_headers(manifest.pose_kind, degrees), values, strict=True)}


def _number(value: float) -> str:
    return f"{value + 0.0:.6g}"  # + 0.0: no "-0"


def _print(record: dict[str, Any], as_json: bool) -> None:
    if as_json:
        print(json.dumps(record))
    else:
        text = "  ".join(f"{k}={_number(v)}" if isinstance(v, float) else f"{k}={v}" for k, v in record.items())
        print(text)


def _values_text(labelled: dict[str, float]) -> str:
    """``{"x [m]": 0.02, "alpha [deg]": 5.0}`` as ``x = 0.02 m, alpha = 5 deg``."""
    parts = []
    for header, value in labelled.items():
        name, _, unit = header.partition(" ")
        parts.append(f"{name} = {_number(value)}" + (f" {unit.strip('[]')}" if unit else ""))
    return ", ".join(parts)


def _signs(signs: np.ndarray) -> str:
    return " ".join("+" if s > 0 else "-" for s in signs) or "(none)"


class _Busy:
    """``with _Busy("rus6: every assembly mode"):`` work that may take more than a second: after
    ``delay`` seconds a line on stderr says what is running and for how long (redrawn each second,
    ended with the time taken), where progress bars appear (``parakin.log``: a terminal, or
    ``PARAKIN_PROGRESS=on``); nothing for work that ends sooner."""

    def __init__(self, what: str, delay: float = 1.0) -> None:
        import threading

        from parakin.log import progress_setting

        self.what, self.delay = what, delay
        setting = progress_setting()
        terminal = hasattr(sys.stderr, "isatty") and sys.stderr.isatty()
        self.show = setting == "on" or (setting == "auto" and terminal)
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._tick, daemon=True)
        self.drawn = False

    def _tick(self) -> None:
        import time

        start = time.perf_counter()
        if self.done.wait(self.delay):
            return
        while True:
            print(
                f"\rparakin: {self.what} ... {time.perf_counter() - start:.0f} s", end="", file=sys.stderr, flush=True
            )
            self.drawn = True
            if self.done.wait(1.0):
                print(
                    f"\rparakin: {self.what}: done in {time.perf_counter() - start:.1f} s", file=sys.stderr, flush=True
                )
                return

    def __enter__(self) -> _Busy:
        if self.show:
            self.thread.start()
        return self

    def __exit__(self, *exception: object) -> None:
        self.done.set()
        if self.show:
            self.thread.join()


def _list(args: argparse.Namespace) -> int:
    from parakin.packages.package import shadowings, survey

    readable, broken = survey()
    for name, reason in broken.items():  # reported and skipped: the others are still listed
        print(f"parakin: skipped the package {name!r}: {reason}", file=sys.stderr)
    hidden = shadowings()
    for name in readable:
        if name in hidden:
            print(f"parakin: {hidden[name]}", file=sys.stderr)
    for name, manifest in readable.items():
        caps = manifest.capabilities
        flags = [
            flag
            for flag, present in (
                ("inverse", caps.inverse),
                # a serial chain (no passive joint) has its forward pose by evaluating the chain
                (
                    f"forward(deg {caps.forward.degree})" if caps.forward else "forward(chain)",
                    caps.forward or not manifest.passive,
                ),
                ("rates", caps.rates or caps.legs),
                ("drawing", caps.drawing),
                ("architecture", caps.architecture),
            )
            if present
        ]
        if args.json:
            print(
                json.dumps(
                    {"name": name, "title": manifest.title, "dof": len(manifest.actuated), "capabilities": flags}
                )
            )
        else:
            print(f"{name:16s} {len(manifest.actuated)} inputs  {manifest.title}  [{', '.join(flags)}]")
    return 0


#: the help of ik's and sweep's --onto-reachable (Mechanism.inverse_pose's onto_reachable)
ONTO_REACHABLE_HELP = (
    "a lower-mobility platform (e.g. a 3-RPS): the pose read onto its reachable set, the controlled "
    "coordinates (height and tilt) kept, the parasitic ones as the platform reaches them; the "
    "configurations of that pose answer (an error for a mechanism whose inverse reads no pose so)"
)


def _ik(args: argparse.Namespace) -> int:
    m = _load(args)
    degrees = args.pose_deg is not None
    pose = _pose_from_cli(m.manifest, args.pose_deg if degrees else args.pose, degrees)
    result = m.inverse_pose(pose, strict=False, onto_reachable=args.onto_reachable)
    count = result.actuated.shape[-2]
    # with --onto-reachable: the pose the configurations reach (a lower-mobility reading)
    # (none where no branch is valid: then no configuration reaches a pose to report)
    reading = args.onto_reachable and bool(result.valid.any())
    reached = _describe_pose(m.manifest, result.pose, degrees and not args.json) if reading else None
    records = []
    for k in range(count):
        record: dict[str, Any] = {
            "branch": k,
            "signs": [int(s) for s in result.branches[k]],
            "valid": bool(result.valid[k]),
        }
        if not result.valid[k]:
            record["failed"] = [name for name, mask in result.failures.items() if mask[k]]
        # JSON keys and values in SI units and radians however the pose was typed
        record.update(_labelled(m.manifest.actuated, result.actuated[k], degrees and not args.json))
        record.update(_labelled(m.manifest.passive, result.passive[k], degrees and not args.json))
        if reached is not None:
            record["reached_pose"] = reached
        records.append(record)
    if args.json:
        for record in records:
            _print(record, True)
    else:
        shown = _describe_pose(m.manifest, transform_from_pose(pose, m.manifest.pose_kind), degrees)
        pose_text = _values_text(shown)
        if reached is not None:
            pose_text += f" (read onto the reachable set: {_values_text(reached)})"
        _ik_tables(m, records, degrees, pose_text)
    if not result.valid.any():
        print(f"parakin: no valid inverse branch for this pose on {m.name}", file=sys.stderr)
        return 1
    return 0


def _conditions(names: list[str]) -> str:
    """Failed condition names, those of consecutive legs joined: leg1_reachable ...
    leg6_reachable as ``leg1-6_reachable``."""
    import re

    groups: dict[str, list[int]] = {}
    others = []
    for name in names:
        match = re.fullmatch(r"leg(\d+)_(\w+)", name)
        if match:
            groups.setdefault(match[2], []).append(int(match[1]))
        else:
            others.append(name)
    joined = []
    for what, legs in groups.items():
        consecutive = len(legs) > 2 and legs == list(range(legs[0], legs[-1] + 1))
        joined.append(f"leg{legs[0]}-{legs[-1]}_{what}" if consecutive else ", ".join(f"leg{k}_{what}" for k in legs))
    return ", ".join(joined + others)


def _ik_tables(m: parakin.Mechanism, records: list[dict[str, Any]], degrees: bool, pose_text: str) -> None:
    """Two aligned tables, one row per branch: its signs, whether it is valid (else which
    conditions failed) and the actuated values; then the passive values. A branch that is not
    reachable shows no values ("-": the solver's numbers there are no configuration); one that is
    only out of a range shows them."""
    valid = sum(r["valid"] for r in records)
    print(f"{m.name} at {pose_text}: {len(records)} inverse branch{'es' if len(records) != 1 else ''}, {valid} valid")

    def cells(record: dict[str, Any], variables: tuple[Variable, ...]) -> list[str]:
        shown = record["valid"] or all(f in RANGE_FAILURES for f in record.get("failed", []))
        return [_number(record[_header(v, degrees)]) if shown else "-" for v in variables]

    def status(record: dict[str, Any]) -> str:
        return "yes" if record["valid"] else "no, failed: " + _conditions(record["failed"])

    actuated = [
        [str(r["branch"]), _signs(np.array(r["signs"])), *cells(r, m.manifest.actuated), status(r)] for r in records
    ]
    headers = ["branch", "signs", *(_header(v, degrees) for v in m.manifest.actuated), "valid"]
    print(text_table(headers, actuated, indent="", rows_shown=len(records)))
    if m.manifest.passive:
        print("\npassive joints per branch:")
        passive = [[str(r["branch"]), *cells(r, m.manifest.passive)] for r in records]
        headers = ["branch", *(_header(v, degrees) for v in m.manifest.passive)]
        print(text_table(headers, passive, indent="", rows_shown=len(records)))


def _fk(args: argparse.Namespace) -> int:
    """Every assembly mode: a table (text) or one JSON object per mode; each says the certificate's
    verdict (``certified_complete``: true, false, or null where the method has no certificate).
    With no mode: the verdict on stderr (text) or one object ``{"modes": 0, ...}`` (JSON), exit 1."""
    m = _load(args)
    typed_degrees = args.actuated_deg is not None
    actuated = _from_cli_units(
        m.manifest.actuated, args.actuated_deg if typed_degrees else args.actuated, typed_degrees
    )
    methods = list(m.manifest.capabilities.forward_methods)
    if args.method is not None and args.method not in methods:
        known = ", ".join(repr(name) for name in methods) or "none (a serial chain: its forward pose is evaluated)"
        raise BadInputError(f"--method {args.method!r}: {m.name}'s forward methods are {known}")
    with _Busy(f"{m.name}: every assembly mode"):
        modes = m.forward_pose_all(actuated, method=args.method)
    # JSON keys and values in SI units and radians however the inputs were typed; the text
    # follows --actuated-deg, its columns labelled [deg]
    degrees = typed_degrees and not args.json
    given = _labelled(m.manifest.actuated, actuated, degrees)  # the inputs as the user gave them
    count = int(modes.count)
    # the same keys for every mechanism and method (FK_SUMMARY_KEYS), on every line
    summary: dict[str, Any] = {
        "modes": count,
        "certified_complete": certified_complete(modes),
        "verdict": certificate_verdict(modes, api_hints=False),
    }
    # "mode" numbers as modes.mode(n) does (0 .. count - 1); "slot" is the raw slot of modes.slot(s)
    records = []
    for n, k in enumerate(np.nonzero(modes.valid)[0]):
        record: dict[str, Any] = {"mode": n, "slot": int(k), **_describe_pose(m.manifest, modes.poses[k], degrees)}
        record.update(_labelled(m.manifest.passive, modes.passive[k], degrees))
        record["residual"] = float(modes.residual[k])
        records.append(record | summary)
    if args.json:
        for record in records or [summary]:  # no mode: the summary alone, so the answer still parses
            _print(record, True)
    elif records:
        at = _values_text(given)
        print(f"{m.name} at {at}: {count} assembly mode{'s' if count != 1 else ''}; {summary['verdict']}")
        pose = pose_headers(m.manifest.pose_kind, degrees)
        headers = ["mode", "slot", *pose, "residual"]
        rows = [
            [str(r["mode"]), str(r["slot"]), *(_number(r[h]) for h in pose), f"{r['residual']:.1e}"] for r in records
        ]
        print(text_table(headers, rows, indent="", rows_shown=count))
        passive = [v for v in m.manifest.passive if _header(v, degrees) not in pose]
        if passive:
            print("\npassive joints per mode:")
            rows = [[str(r["mode"]), *(_number(r[_header(v, degrees)]) for v in passive)] for r in records]
            print(text_table(["mode", *(_header(v, degrees) for v in passive)], rows, indent="", rows_shown=count))
    if count == 0:
        verdict = "proven: none exists (certified complete)" if summary["certified_complete"] else summary["verdict"]
        print(f"parakin: no real assembly mode of {m.name} for these inputs; {verdict}", file=sys.stderr)
        return 1
    return 0


#: the keys of ``parakin fk --json`` on every line, with or without a mode (``_fk``)
FK_SUMMARY_KEYS = ("modes", "certified_complete", "verdict")

FK_JSON_HELP = (
    "one JSON object per assembly mode: mode, slot, the pose and passive values (keys with units), "
    "residual, and on every line modes (the count), certified_complete (true, false, or null where the "
    "method has no certificate, e.g. an elimination) and verdict (in words); with no mode one object "
    '{"modes": 0, "certified_complete": ..., "verdict": ...} and exit status 1'
)


def _demo(args: argparse.Namespace) -> int:
    from parakin.interfaces.demo import CACHED, demo_backend, format_results, run_examples

    names = [args.name] if args.name else parakin.available()
    failed = 0
    with_examples = [name for name in names if parakin.metadata(name).examples]
    backends = {name: demo_backend(name, args.backend) for name in with_examples}  # each library looked up once
    on_numpy = [name for name in with_examples if args.backend == CACHED and backends[name] == "numpy"]
    if on_numpy:
        print(
            f"parakin: the demo runs on NumPy where no C library is built yet ({len(on_numpy)} of "
            f"{len(with_examples)}); "
            "`parakin demo --backend compiled` builds them once (1-20 s each)",
            file=sys.stderr,
        )
    for name in names:
        with _Busy(f"{name}: reproducing its examples"):
            results = run_examples(name, backend=backends.get(name, args.backend))
        print(format_results(name, results), flush=True)
        failed += sum(not r.holds for r in results)
    if failed:
        print(f"parakin: {failed} example(s) did not reproduce", file=sys.stderr)
        return 1
    return 0


def _plot(args: argparse.Namespace) -> int:
    from parakin.interfaces.plot import plot

    m = _load(args)
    degrees = args.actuated_deg is not None
    given = args.actuated_deg if degrees else args.actuated
    actuated = m.home_actuated if given is None else _from_cli_units(m.manifest.actuated, given, degrees)
    if args.animate is None and (args.frames is not None or args.to is not None):
        raise BadInputError("--frames and --to shape an animation: add --animate OUT.gif")
    if args.animate is not None:
        return _plot_animation(args, m, actuated, degrees)
    if m.capabilities.forward is not None:
        try:
            with _Busy(f"{m.name}: every assembly mode to draw"):
                state: Any = m.forward_pose_all(actuated)
        except SelfMotionError as error:  # draw the self-motion instead: a few points along it
            motion = error.solution_set
            assert isinstance(motion, SelfMotion)
            pick = np.linspace(0, motion.count - 1, min(6, motion.count)).astype(int)
            state = Configuration(
                np.broadcast_to(actuated, (pick.size, actuated.size)), motion.passive[pick], motion.poses[pick]
            )
            print(f"{m.name}: the actuators leave a self-motion here; drawing {pick.size} points along it")
        if int(getattr(state, "count", 1)) == 0:
            print(f"parakin: no real assembly mode of {m.name} to draw", file=sys.stderr)
            return 1
    else:
        state = m.forward_pose(actuated)
    path = args.output or f"{m.name}.png"
    with _Busy(f"{m.name}: drawing {path}"):
        plot(m, state, path, mode=args.mode, all_modes=args.all_modes)
    print(f"wrote {path}")
    return 0


def _inputs(m: parakin.Mechanism, actuated: np.ndarray) -> str:
    """Inputs by name with units, revolute ones in degrees (as the pictures' titles)."""
    from parakin.interfaces.plot import inputs_text

    return inputs_text(m, actuated).replace("\u00a0", " ")


def _plot_animation(args: argparse.Namespace, m: parakin.Mechanism, actuated: np.ndarray, degrees: bool) -> int:
    """``parakin plot NAME --animate OUT.gif``: a straight line to ``--to``, or else a loop through
    the start (``actuated_loop``), shrunk up to three times while it crosses a singularity or
    leaves the workspace; the start is ``--mode K`` or the mode nearest the home."""
    from parakin.interfaces.plot import actuated_line, actuated_loop, animate

    frames = 24 if args.frames is None else args.frames
    with _Busy(f"{m.name}: every assembly mode"):
        start = None if args.mode is None else m.forward_pose_all(actuated).mode(args.mode)
    if args.to is not None:
        end = _from_cli_units(m.manifest.actuated, args.to, degrees)
        with _Busy(f"{m.name}: {frames} frames to {args.animate}"):
            animate(m, actuated_line(m, actuated, end, frames), args.animate, start=start)
        print(f"wrote {args.animate}: {frames} frames from {_inputs(m, actuated)} to {_inputs(m, end)}")
        return 0
    scales = (1.0, 0.5, 0.25, 0.125)
    for scale in scales:
        try:
            with _Busy(f"{m.name}: {frames} frames to {args.animate}"):
                animate(m, actuated_loop(m, actuated, frames, scale), args.animate, start=start)
        except ParakinError as error:
            if scale == scales[-1]:
                raise
            print(f"{m.name}: the loop at scale {scale:g} fails ({type(error).__name__}); trying {scale / 2:g}")
            continue
        print(f"wrote {args.animate}: {frames} frames, a loop through {_inputs(m, actuated)} (scale {scale:g})")
        return 0
    raise AssertionError("unreachable")


def _export(args: argparse.Namespace) -> int:
    from parakin.packages.package import GeneratedPackage, export_name

    package = GeneratedPackage.find(args.name)
    written = package.export_c(args.out, force=args.force)
    print(f"wrote {len(written)} files to {args.out}: {', '.join(p.name for p in written)}")
    name = package.manifest.name
    sources = " ".join(export_name(name, source) for source in ("example_main.c", "driver.c", "kernels.c"))
    print(f"see {args.out}/{export_name(name, 'README_C.md')}; try: cc -std=c99 -O2 -I. {sources} -lm")
    return 0


def _generate(args: argparse.Namespace) -> int:
    try:
        from parakin.generator.build import GenerationError, Terminated, generate_file
    except ImportError as error:
        raise ParakinError(
            f"generating needs the generator extra: pip install 'parakin[generator]' ({error})"
        ) from error
    import signal

    def terminated(signum: int, frame: object) -> None:
        raise Terminated(128 + signum)

    # a terminated build unwinds like an interrupted one: its staging folder is removed. Its own
    # exit (Terminated), not SystemExit: a mechanism file's SystemExit is an error (exit 2)
    signal.signal(signal.SIGTERM, terminated)
    try:
        report = generate_file(args.file, args.out, force=args.force)
    except GenerationError as error:
        raise BadInputError(str(error)) from error
    print(f"generated {args.out} in {report['seconds']:.1f} s; load it with parakin.load({str(args.out)!r})")
    return 0


def _inspect(args: argparse.Namespace) -> int:
    from parakin.interfaces.inspect import inspect

    with _Busy(f"{args.name}: reading and printing its symbolic model"):
        text = inspect(args.name, args.format, args.width, args.lines)
    print(text)
    return 0


def _axis(text: str) -> tuple[str, np.ndarray]:
    """NAME=START:STOP:COUNT (a linspace) or NAME=V1,V2,... (values)."""
    name, _, spec = text.partition("=")
    try:
        if ":" in spec:
            start, stop, count = spec.split(":")
            return name, np.linspace(float(start), float(stop), int(count))
        return name, np.array([float(v) for v in spec.split(",")])
    except ValueError as error:
        raise BadInputError(f"axis {text!r}: write NAME=START:STOP:COUNT or NAME=V1,V2,...") from error


def _fixed(text: str) -> tuple[str, float]:
    """NAME=VALUE: one number (a fixed coordinate is not an axis)."""
    name, sep, value = text.partition("=")
    try:
        if not sep or not name.strip():
            raise ValueError(text)
        return name.strip(), float(value)
    except ValueError as error:
        raise BadInputError(f"--fixed {text!r}: write NAME=VALUE with one number (SI)") from error


def _sweep(args: argparse.Namespace) -> int:
    from parakin.studies.sweep import sweep

    m = _load(args)
    axes = dict(_axis(a) for a in args.axis)
    fixed = dict(map(_fixed, args.fixed))
    workspace = dict(_axis(a) for a in args.workspace) or None
    result = sweep(
        m, args.quantities, axes, fixed=fixed, workspace=workspace, branch=args.branch, chunk=args.chunk,
        scheduler=args.scheduler, store=args.store, progress=args.progress, onto_reachable=args.onto_reachable,
    )  # fmt: skip
    if args.netcdf:
        result.to_netcdf(args.netcdf)
    for name, values in result.data_vars.items():
        array = np.asarray(values.values, dtype=float)
        finite = array[np.isfinite(array)]
        summary = (
            f"min {finite.min():.6g}  mean {finite.mean():.6g}  max {finite.max():.6g}" if finite.size else "all NaN"
        )
        print(f"{name:24s} {dict(values.sizes)}  {summary}  ({finite.size}/{array.size} defined)")
    if args.plot:
        from parakin.studies.atlas import plot_sweep

        quantity = args.plot_quantity or str(next(iter(result.data_vars)))
        plot_sweep(result, quantity, args.plot)
        print(f"wrote {args.plot}")
    return 0


class _Parser(argparse.ArgumentParser):
    """argparse with a suggestion for a mistyped command or option (``did you mean 'plot'?``), and
    negative numbers in any float notation taken as values (``--pose -1e-3 0 0.4``: argparse's own
    pattern takes only ``-1`` and ``-0.5`` as numbers, so ``-3.5e-17``, as ``fk`` prints it, would
    read as an option)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        self.exit(2, f"{self.prog}: error: {message}{_suggestion(self, message)}\n")


def _suggestion(parser: argparse.ArgumentParser, message: str) -> str:
    """``; did you mean ...?`` for an invalid choice or an unrecognized option, or nothing."""
    import difflib
    import re

    choice = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)", message)
    known = sorted(_option_strings(parser))
    if choice:
        known, given = re.findall(r"'([^']*)'", choice[2]), [choice[1]]
    elif "unrecognized arguments: " in message:
        given = [word for word in message.split("unrecognized arguments: ")[1].split() if word.startswith("--")]
    elif "required" in message:  # a mistyped required option is reported as missing: name it
        given = [word.split("=")[0] for word in _GIVEN if word.startswith("--") and word.split("=")[0] not in known]
    else:
        return ""
    hints = []
    formats = _format_choices(parser)
    for word in given:
        close = difflib.get_close_matches(word, known, n=1, cutoff=0.6)
        if word[2:] in formats:  # --json where the command writes formats: --format json
            close = [f"--format {word[2:]}"]
        if close:
            hints.append(
                f"did you mean {close[0]!r} for {word!r}?" if len(given) > 1 else f"did you mean {close[0]!r}?"
            )
    return "; " + " ".join(hints) if hints else ""


def _format_choices(parser: argparse.ArgumentParser) -> list[str]:
    """The choices of the parser's ``--format`` option (none where it has none)."""
    for action in parser._actions:
        if "--format" in action.option_strings and action.choices is not None:
            return [str(choice) for choice in action.choices]
    return []


#: a negative number as a value: -1, -0.5, -.5, -1e-3, -2.5E+4, -inf
_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-inf$")

#: the command line being parsed (``_main``): what a "required" error's suggestion looks through
_GIVEN: list[str] = []


def _option_strings(parser: argparse.ArgumentParser) -> set[str]:
    """Every option string of ``parser`` and of its commands' parsers."""
    options = {o for action in parser._actions for o in action.option_strings}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for command in action.choices.values():
                options |= _option_strings(command)
    return options


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="parakin",
        description=(__doc__ or "").replace("``", ""),  # plain text: no reST markup in a terminal
        epilog="parakin COMMAND --help shows a command's options.",
        formatter_class=argparse.RawTextHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"parakin {_version()}")
    commands = parser.add_subparsers(dest="command", required=True)
    # each flag only on the commands that use it (the README's command table says which)
    backend = _Parser(add_help=False)
    backend.add_argument("--backend", default="auto", choices=["auto", "compiled", "numpy", "casadi"])
    as_json = _Parser(add_help=False)
    as_json.add_argument("--json", action="store_true", help="one JSON object per line")
    mechanism = _Parser(add_help=False, parents=[backend])
    mechanism.add_argument("name", help="mechanism name (parakin list) or generated package folder")
    mechanism.add_argument(
        "--param", action="append", default=[], metavar="NAME=VALUE", help="override a parameter (SI; JSON lists too)"
    )

    commands.add_parser("list", parents=[as_json], help="available mechanisms with titles")
    inspect = commands.add_parser("inspect", help="symbolic closure, Jacobians, factored singularity conditions")
    inspect.add_argument("name", help="mechanism name (parakin list) or generated package folder")
    inspect.add_argument("--format", choices=["text", "latex", "json"], default="text")
    inspect.add_argument("--width", type=_positive, default=100, help="line width of text expressions")
    inspect.add_argument("--lines", type=_positive, default=12, help="lines shown per expression (text)")
    demo = commands.add_parser("demo", help="reproduce the named examples of the papers")
    demo.add_argument("name", nargs="?", help="one mechanism (default: every one, in parakin list's order)")
    demo.add_argument(
        "--backend",
        default="cached",
        choices=["cached", "auto", "compiled", "numpy", "casadi"],
        help="default cached: the C library where it is already built, else NumPy (the demo never waits "
        "for the compiler); auto or compiled build each mechanism's C library on first use (1-20 s each)",
    )

    ik = commands.add_parser("ik", parents=[mechanism, as_json], help="every inverse branch of a pose")
    group = ik.add_mutually_exclusive_group(required=True)
    group.add_argument("--pose", nargs="+", type=float, metavar="V", help="pose values, SI and radians (see list)")
    group.add_argument("--pose-deg", nargs="+", type=float, metavar="V", help="the same with angles in degrees")
    ik.add_argument("--onto-reachable", action="store_true", help=ONTO_REACHABLE_HELP)
    ik.epilog = "pose values per pose kind: " + "; ".join(f"{k}: {v[0]}" for k, v in POSE_ARGUMENTS.items())

    fk = commands.add_parser(
        "fk",
        parents=[mechanism],
        help="every assembly mode for actuated values",
        description="Every real assembly mode for the actuated values, with the certificate's verdict: 'certified "
        "complete' (no mode can be missing) or why not (a homotopy whose certificate failed, or a method without one, "
        "such as an elimination). Exit status 0 with at least one mode, 1 with none (the verdict on stderr), 2 on "
        "bad input.",
    )
    fk.add_argument("--json", action="store_true", help=FK_JSON_HELP)
    fk.add_argument(
        "--method",
        default=None,
        help="a forward method of the mechanism (parakin inspect NAME lists them, e.g. 'automatic': a "
        "homotopy whose certificate proves no mode missing); default: the mechanism's fastest complete one",
    )
    group = fk.add_mutually_exclusive_group(required=True)
    group.add_argument("--actuated", nargs="+", type=float, metavar="V", help="actuated values (m, rad)")
    group.add_argument(
        "--actuated-deg", nargs="+", type=float, metavar="V", help="revolute inputs in degrees, prismatic in metres"
    )

    plot = commands.add_parser(
        "plot",
        parents=[mechanism],
        help="draw the assembly modes (PNG: a grid of the first 12, all with --all-modes, or one) or animate one (GIF)",
        description="Draw the mechanism at the actuated inputs (default: home). Default: a grid of the first 12 "
        "assembly modes (all of them where there are at most 12), each panel titled 'mode k' (k = 0 .. count-1) "
        "with its distance to singularity, in red where near a type II singularity; the title names the modes "
        "left out. --all-modes draws every mode; --mode K draws mode K alone. --animate OUT.gif tracks one mode "
        "(--mode K, default the mode nearest the home) along a loop through the inputs, or a straight line --to "
        "other inputs, instead.",
    )
    plot.add_argument("--output", "--out", default=None, help="image path, its format by the suffix (default NAME.png)")
    group = plot.add_mutually_exclusive_group()
    group.add_argument("--actuated", nargs="+", type=float, metavar="V", help="actuated values (default: home)")
    group.add_argument("--actuated-deg", nargs="+", type=float, metavar="V", help="revolute in degrees, prismatic in m")
    which = plot.add_mutually_exclusive_group()
    which.add_argument("--mode", type=int, default=None, metavar="K", help="draw (or animate from) mode K only")
    which.add_argument(
        "--all-modes",
        action="store_true",
        help="draw every mode in the grid (default: the first 12, the others named in the title)",
    )
    plot.add_argument("--animate", default=None, metavar="OUT.gif", help="write a GIF along an actuated path")
    plot.add_argument("--frames", type=int, default=None, metavar="N", help="frames of the animation (default 24)")
    plot.add_argument(
        "--to", nargs="+", type=float, default=None, metavar="V",
        help="animate along the line to these inputs (units as --actuated / --actuated-deg; default: a loop)",
    )  # fmt: skip

    generate = commands.add_parser("generate", help="turn a mechanism file into a generated package folder")
    generate.add_argument("file", help="a mechanism file (defines build() -> parakin.generator.Mechanism)")
    generate.add_argument("--out", required=True, help="the package folder to write (load it with parakin.load(DIR))")
    generate.add_argument(
        "--force", action="store_true", help="write into a non-empty --out folder that is not a parakin package"
    )
    sweeping = commands.add_parser(
        "sweep", parents=[mechanism], help="quantities over grids of poses, inputs or parameters (dask)"
    )
    sweeping.add_argument("quantities", nargs="+", help="reachable, branches, type_i_distance, type_ii_distance, ...")
    sweeping.add_argument(
        "--axis", action="append", default=[], required=True, metavar="NAME=START:STOP:COUNT", help="a swept axis (SI)"
    )
    sweeping.add_argument(
        "--fixed",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a fixed coordinate: pose, actuated input or parameter",
    )
    sweeping.add_argument("--workspace", action="append", default=[], metavar="NAME=START:STOP:COUNT")
    sweeping.add_argument(
        "--branch",
        type=int,
        default=None,
        help="the inverse branch singularity distances are measured in (default: the home's branch)",
    )
    sweeping.add_argument("--onto-reachable", action="store_true", help=ONTO_REACHABLE_HELP)
    sweeping.add_argument("--chunk", type=int, default=65536, help="points per chunk (memory bound)")
    sweeping.add_argument("--scheduler", default=None, help="dask.distributed scheduler address (default: local)")
    sweeping.add_argument("--store", default=None, help="zarr folder: written chunk by chunk, resumable")
    sweeping.add_argument("--netcdf", default=None, help="also write the result as netCDF")
    sweeping.add_argument("--plot", default=None, help="PNG of one quantity")
    sweeping.add_argument("--plot-quantity", default=None, help="the quantity to plot (default: the first)")
    sweeping.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="a progress bar on stderr: always, or never (--no-progress); default: for a large sweep on a terminal",
    )
    export = commands.add_parser("export", help="write the mechanism's C library (sources, header, example)")
    export.add_argument("name", help="mechanism name (parakin list) or generated package folder")
    export.add_argument(
        "--out",
        required=True,
        help="folder to write the C files into (NAME_driver.c, NAME.h, ...): new, empty, or one parakin exported to",
    )
    export.add_argument(
        "--force",
        action="store_true",
        help="also write into a folder that is not an export, and over files of the same names; other files are kept",
    )
    view = commands.add_parser(
        "view",
        help="interactive viewer in the browser: a slider per actuated input, modes, singularity measures",
        add_help=False,
    )
    view.add_argument("arguments", nargs=argparse.REMAINDER, help="NAME [--port P] [--open] (parakin view --help)")
    from parakin.calibration import command as calibration_cli

    calibrate = commands.add_parser(
        "calibrate",
        help="identify the geometric parameters from measured poses, positions or probe heights (a CSV)",
        description=calibration_cli.__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    calibration_cli.add_arguments(calibrate)
    from parakin import mjcf

    mjcf_parser = commands.add_parser(
        "mjcf", help="a MuJoCo model (MJCF) of the mechanism: bodies, closed loops, a keyframe per assembly mode"
    )
    mjcf.add_arguments(mjcf_parser)
    return parser


def _calibrate(args: argparse.Namespace) -> int:
    from parakin.calibration.command import run

    return run(args)


def _mjcf(args: argparse.Namespace) -> int:
    from parakin.loading import load
    from parakin.mjcf import run

    m = load(args.name)
    if args.actuated_deg is not None:
        args.actuated = list(_from_cli_units(m.manifest.actuated, args.actuated_deg, True))
    return run(args, m)


def _positive(text: str) -> int:
    """A whole number >= 1, for argparse (its usage message, exit 2, on anything else)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} must be at least 1")
    return value


def _view(args: argparse.Namespace) -> int:
    from parakin.interfaces.viewer import main as viewer

    return viewer(args.arguments)


COMMANDS = {
    "list": _list,
    "inspect": _inspect,
    "demo": _demo,
    "ik": _ik,
    "fk": _fk,
    "plot": _plot,
    "generate": _generate,
    "export": _export,
    "sweep": _sweep,
    "view": _view,
    "calibrate": _calibrate,
    "mjcf": _mjcf,
}


def _version() -> str:
    """The installed distribution's version (the checkout's pyproject.toml when run from it)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("parakin")
    except PackageNotFoundError:
        return "unknown (not installed)"


def _show_warning(
    message: Warning | str, category: type[Warning], filename: str, lineno: int, file: Any = None, line: Any = None
) -> None:
    """A warning as one line, ``parakin: warning: ...`` (parakin's own without their class name;
    no source path or code line: they are for parakin's developers, not its users)."""
    text = " ".join(str(message).split())
    own = category.__module__.startswith("parakin")
    print(f"parakin: warning: {text}" if own else f"parakin: warning: {category.__name__}: {text}", file=sys.stderr)


#: the exit status of an interrupted command (128 + SIGINT, as shells report it)
INTERRUPTED = 130


def main(argv: list[str] | None = None) -> int:
    """Run one command; the exit status (see the module docstring) is returned, never raised.

    Ctrl-C prints ``parakin: interrupted`` and gives 130; as the ``parakin`` program
    (``argv`` None) the process then ends at once, without waiting for worker threads (a
    sweep's) to finish their chunks."""
    import warnings

    with warnings.catch_warnings():
        warnings.showwarning = _show_warning
        try:
            return _main(argv)
        except KeyboardInterrupt:
            print("\nparakin: interrupted", file=sys.stderr)
            if argv is None:  # the program: worker threads would hold its exit for seconds
                try:
                    sys.stdout.flush()
                except OSError:
                    pass
                sys.stderr.flush()
                os._exit(INTERRUPTED)
            return INTERRUPTED


def _main(argv: list[str] | None) -> int:
    given = sys.argv[1:] if argv is None else list(argv)
    if given[:1] == ["view"]:  # its own options, --help included (argparse would take those)
        return _view(argparse.Namespace(arguments=given[1:]))
    _GIVEN[:] = given
    parser = _parser()
    args, extra = parser.parse_known_args(given)
    if extra:  # reported by the command's own parser: its usage, and suggestions from its options
        commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        commands.choices[args.command].error(f"unrecognized arguments: {' '.join(extra)}")
    np.set_printoptions(precision=6, suppress=True, linewidth=120)
    try:
        status = COMMANDS[args.command](args)
        sys.stdout.flush()  # inside the try: a reader that left makes this flush fail
        return status
    except BrokenPipeError:  # `parakin ... | head`: the reader left; first, as it is an OSError
        # the interpreter flushes stdout once more at exit: point it at /dev/null so that this
        # flush cannot fail again and print "Exception ignored"
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except ParakinError as error:
        print(f"parakin: {type(error).__name__}: {error}", file=sys.stderr)
        return 2
    except OSError as error:  # an output path that cannot be written, a missing folder
        where = f" {error.filename}" if error.filename else ""
        print(f"parakin: cannot use{where}: {error.strerror or error}", file=sys.stderr)
        return 2
    except Exception as error:  # a bug: one line, not a traceback, and not 1 ("no solution")
        message = " ".join(str(error).split())
        print(
            f"parakin: internal error: {type(error).__name__}: {message}; please report it with the command line",
            file=sys.stderr,
        )
        return INTERNAL_ERROR


if __name__ == "__main__":
    sys.exit(main())
