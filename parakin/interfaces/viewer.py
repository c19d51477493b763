"""An interactive viewer of any generated mechanism, in the browser and in notebooks.

A small standard-library HTTP server (``http.server`` in a thread, bound to 127.0.0.1 unless told
otherwise) serves one self-contained page (``viewer.html``: inline JavaScript and a canvas, no
network) and a JSON API over a ``ViewerSession``:

- the viewer starts (and "Home" returns) at a closed configuration with room to move: the
  manifest's home, or where a paper's example input sits among folds (stewart's 40 modes) a
  configuration near it found by a seeded search for the most predicted room before a fold
  towards each slider's ends (``ViewerSession._roomy``), always a mode its input's list shows;
- a slider per actuated input (SI units in the API and on the wire; revolute inputs labelled in
  degrees) drives the runtime's tracker (``m.tracker``): the assembly mode is followed
  continuously, and a step the tracker refuses (a crossed type II singularity, a branch it
  cannot follow, no convergence, a value outside the actuator's range) is reported by the named
  error of ``parakin.errors`` and its message, the drawing staying at the last solved input:
  never a silent jump of assembly mode;
- a mode selector lists the assembly modes of the current input (``m.forward_pose_all``);
  choosing one restarts the tracker there. Mode numbers are the viewer's own and stay with a
  mode: the first list is numbered as ``AssemblyModes.mode(k)``, each later list carries the
  numbers over from the list before it by nearness of pose and drawing, and the followed mode
  keeps its number as long as the tracker follows it (the solver's own order changes from input
  to input as modes swap places, appear and vanish);
- a move the tracker refuses is explained in the user's terms: where the followed mode ends
  (a fold, where it meets another mode), or reaches a singularity it would have to cross, is
  located on the move by bisection and named by the input's value;
- the singularity measures (``m.singularities``: named serial and type II factors and the
  determinants, zero means singular) and the closure Jacobian's conditioning update live;
- the drawing is the generated drawing kernel's point sets (``m.drawing``: 3 x n in {B}, metres)
  joined by the manifest's polylines, in 3-D (drag to orbit, wheel to zoom, shift-drag to pan) or
  in the plane for a drawing that lies in one plane z = const.

Nothing here knows a mechanism: every slider, measure and polyline comes from the manifest.

The server answers only requests that name it (Host and Origin: its own address, localhost or
127.0.0.1 with its port, so a DNS-rebinding page or another site cannot drive or read it), POSTs
declared ``application/json`` (a cross-origin "simple" POST cannot be one), changes state by POST
only, replies to every malformed request with a JSON error (non-finite numbers, nesting deeper
than MAX_DEPTH, bodies over MAX_BODY, a bad Content-Length) and drops a connection idle for
REQUEST_TIMEOUT seconds.
``serve(m)`` starts a server (``Viewer``: ``url``, ``close()``, a context manager, an iframe in
notebooks), ``show(m)`` returns that iframe, ``python -m parakin.interfaces.viewer NAME`` serves one from the
shell (``main(argv)``).
"""

from __future__ import annotations

import argparse
import ipaddress
import json
import math
import re
import sys
import threading
import webbrowser
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from typing import TYPE_CHECKING, Any

import numpy as np

from parakin.errors import (
    AssemblyModeChangeError,
    BadInputError,
    ConvergenceError,
    NoSuchModeError,
    ParakinError,
    SingularConfigurationError,
)
from parakin.pose import xyz_euler_deg_from_pose
from parakin.results import AssemblyModes, Configuration
from parakin.singularity import inverse_condition
from parakin.tables import POSE_HEADERS
from parakin.validation import within_ranges

if TYPE_CHECKING:
    from parakin.mechanism import Mechanism
    from parakin.solvers.tracker import ForwardPoseTracker

#: slider positions per input range
SLIDER_STEPS = 2000
#: a move is tracked in pieces of at most 1/TRACK_PIECES of each slider's range (a click on the
#: slider's track is a jump the tracker would refuse as too coarse), at most MAX_PIECES of them
TRACK_PIECES, MAX_PIECES = 200, 2000
#: the pose components each pose kind moves, as indices into POSE_LABELS
POSE_COMPONENTS = {
    "transform": (0, 1, 2, 3, 4, 5),
    "rotation": (3, 4, 5),
    "translation": (0, 1, 2),
    "planar": (0, 1, 3),
    "planar_translation": (0, 1),
}
#: assembly-mode lists kept per session (by input), most recent first
MODES_CACHED = 16
#: the largest request body accepted (bytes): a request is a few numbers
MAX_BODY = 65536
#: a larger body is still read (and dropped) up to this many bytes, so that its sender sees the
#: 413 reply instead of a connection reset; beyond it the connection is closed unread
DRAIN_LIMIT = 1 << 20
#: the deepest nesting of brackets a request body may have (a request is flat; the standard
#: parser recurses once per level and fails with RecursionError near 1000 levels)
MAX_DEPTH = 16
#: seconds a connection may stay silent (before or within a request) before the server drops it
REQUEST_TIMEOUT = 10.0
#: calls a GET may make: they only read; every other call changes state and needs a POST
READ_ONLY_CALLS = ("scene", "state")
#: bisection steps that locate where a refused move stops being trackable
BISECTIONS = 40
#: closure conditioning (sigma_min / sigma_max of d closure / d passive), relative to the
#: home's where that is below 1, at or below which the place a move stops is a singularity. The
#: ratio depends on the units the closure mixes (gough's, stewart's and planar_3rpr's homes are
#: at 0.008-0.011, the others' at 0.14-0.69), so it is read against the home's; at a fold it
#: falls as the square root of the distance (~1e-6 of the home's after the bisection), while a
#: regular stop stays within a small factor of it
SINGULAR_CONDITIONING = 1e-3
#: a message quotes at most this many characters of what a request held
ECHO = 120
#: a configuration is mode k when its pose and drawing agree with mode k's to this, relative to
#: the drawing's size (the tracker and the mode polisher both converge to about 1e-12)
SAME_MODE = 1e-7
#: pose shown on the page: position of {P} in {B} and Z-Y-X Euler angles of ^B_P R
POSE_LABELS = tuple(POSE_HEADERS)
#: the viewer's home (``ViewerSession._roomy``): rounds and inputs per round of the random search
#: for a start with room to move, its seed (the same home every time), the first round's spread
#: (rad for a revolute input, a fraction of the input for a prismatic one), the finite-difference
#: step (a fraction of the slider's range), how far inside the sliders' ranges a start lies, the
#: margin a candidate must beat the manifest's home by, and the weight of the type II measure
HOME_ROUNDS, HOME_CANDIDATES, HOME_SEED, HOME_SPREAD = 4, 48, 0, 0.2
HOME_STEP, HOME_INSIDE, HOME_MARGIN, HOME_DETERMINANT = 1e-4, 0.01, 0.05, 0.1


def _finite_or_none(value: float) -> float | None:
    """JSON has no NaN or infinity: such a value goes out as null."""
    value = float(value)
    return value if math.isfinite(value) else None


def _error(error: BaseException, message: str | None = None) -> dict[str, str]:
    """The error of a reply: its class's name and the message (``message`` rewords it)."""
    return {"type": type(error).__name__, "message": str(error) if message is None else message}


def _shown(value: Any) -> str:
    """``repr(value)`` cut to ECHO characters: a message never copies a whole request."""
    text = repr(value)
    return text if len(text) <= ECHO else text[: ECHO - 3] + "..."


def _echo(value: Any) -> Any:
    """``value`` as a reply may echo it: itself when strict JSON can encode it (no NaN or infinity,
    no nesting deeper than the encoder's recursion), else its ``_shown`` text."""
    try:
        json.dumps(value, allow_nan=False)
    except (ValueError, TypeError, RecursionError):
        return _shown(value)
    return value


def _numbers(labels: Sequence[int]) -> str:
    """Mode numbers for a sentence: "0 to 5", or "0, 2, 3" where some are not in use."""
    ordered = sorted(labels)
    if ordered and ordered == list(range(ordered[0], ordered[-1] + 1)) and len(ordered) > 2:
        return f"{ordered[0]} to {ordered[-1]}"
    return ", ".join(str(k) for k in ordered)


@dataclass
class _Table:
    """The assembly modes of one input with the viewer's numbers: ``labels[i]`` is the number of
    ``modes.mode(i)``; ``prints`` its fingerprints (one row per mode), compared across inputs."""

    modes: AssemblyModes
    prints: np.ndarray
    labels: list[int]


class ViewerSession:
    """The viewer's state and every request it answers, without HTTP (the server calls these; the
    tests too). One session follows one mechanism from its home configuration.

    Replies are JSON-ready dicts. A state reply (``state``, ``move``, ``select``, ``home``) holds
    ``ok``, ``error`` ({type, message} of the parakin error, or None), ``actuated`` (the input the
    drawing shows, SI), ``requested`` (what was asked), ``polylines`` (name -> 3 x k vertices in
    {B}, metres), ``measures`` ([name, value] of ``m.singularities``), ``conditioning`` (sigma_min /
    sigma_max of the closure Jacobian: 1 far from, 0 at a singularity), ``residual`` (max-norm of the loop
    closure at the drawn configuration), ``pose`` (x, y, z in m, Z-Y-X Euler in deg) and ``mode``
    (the viewer's number of the followed mode, None until it is known). A refused move's error
    keeps the class name of the solver's error and says in the user's terms what happened.
    """

    def __init__(self, m: Mechanism, start: Configuration | None = None) -> None:
        self.m = m
        self._lock = threading.RLock()  # the tracker and the current configuration
        self._modes_lock = threading.Lock()  # one forward_pose_all at a time
        self._modes: OrderedDict[tuple[float, ...], AssemblyModes] = OrderedDict()
        # the viewer's mode numbers (under _lock): the tables of the latest inputs, the table the
        # next one continues from, and the number of the mode the tracker follows
        self._tables: OrderedDict[tuple[float, ...], _Table] = OrderedDict()
        self._reference: _Table | None = None
        self._followed: int | None = None
        self._tracker: ForwardPoseTracker | None = None
        manifest_home = start if start is not None else self._manifest_home()
        self._config = self._restart(manifest_home)
        self._scale = self._drawing_scale(self._config)
        self._sphere = self._sphere_of(self._config)
        self._sliders = self.sliders()
        self._span = np.array([s["high"] - s["low"] for s in self._sliders], dtype=float)
        # the viewer's home: the manifest's, or a closed configuration near it with more room to
        # move before a fold (a paper's example input may sit among folds: stewart's 40 modes)
        self._start = self._config if start is not None else self._roomy(self._config)
        self._config = self._restart(self._start)
        for slider, value in zip(self._sliders, self._start.actuated, strict=True):
            slider["home"] = float(value)
        self._home_measures = dict(self._measures(self._config))
        self._home_conditioning = self._conditioning(self._config)
        #: what ``SINGULAR_CONDITIONING`` is relative to: the home's conditioning, at most 1
        self._conditioning_scale = min(1.0, self._home_conditioning or 1.0)

    # ------------------------------------------------------------------ configurations
    def _manifest_home(self) -> Configuration:
        """The manifest's home configuration, closed by Newton from its home values (every
        package's home closes: the contract tests check it)."""
        return self.m.forward_pose(self.m.home_actuated, guess=self.m.home_passive)

    def _home(self) -> Configuration:
        """The viewer's home: where the session started (``_roomy``)."""
        return self._start

    # ------------------------------------------------------------------ a home with room to move
    def _room(self, candidates: Configuration) -> np.ndarray:
        """Each candidate's predicted room to move (n,): over the 2 n_a slider directions, the
        mean of min(1, distance to a fold / distance to the slider's end), the distance to a fold
        the linear extrapolation of the type II measure (``closure_singularity``: 0 at a fold)
        from central differences of the followed mode; plus ``HOME_DETERMINANT`` x |measure| to
        prefer the better conditioned of candidates that both reach every end."""
        from parakin.studies.sampling import closure_singularity

        m = self.m
        count, inputs = candidates.actuated.shape
        low = np.array([s["low"] for s in self._sliders])
        high = np.array([s["high"] for s in self._sliders])
        measure = closure_singularity(m, candidates)
        total = np.zeros(count)
        for k in range(inputs):
            h = HOME_STEP * self._span[k]
            ends = []
            for sign in (1.0, -1.0):
                moved = np.array(candidates.actuated, dtype=float)
                moved[:, k] += sign * h
                solved = m.forward_pose(moved, candidates.passive, strict=False)
                value = closure_singularity(m, Configuration(moved, solved.passive, solved.pose))
                ends.append(np.where(np.asarray(solved.converged), value, np.nan))
            with np.errstate(all="ignore"):
                crossing = -measure / ((ends[0] - ends[1]) / (2 * h))  # where the measure reaches 0
                for end, sign in ((high[k], 1.0), (low[k], -1.0)):
                    to_end = np.abs(end - candidates.actuated[:, k])
                    fold = np.where(np.sign(crossing) == sign, np.abs(crossing), np.inf)
                    share = np.where(to_end > 0, np.minimum(1.0, fold / np.maximum(to_end, 1e-300)), 1.0)
                    total += np.nan_to_num(share, nan=0.0)
        return total / (2 * inputs) + HOME_DETERMINANT * np.abs(np.nan_to_num(measure, nan=0.0))

    def _roomy(self, home: Configuration) -> Configuration:
        """A start with room to move: a seeded random search over closed configurations around
        ``home`` (HOME_ROUNDS rounds of HOME_CANDIDATES inputs, each round around the best so far
        with half the spread) for the most ``_room``; ``home`` itself unless a candidate has
        HOME_MARGIN more of it. A serial chain, or a search the solver refuses, keeps ``home``."""
        m = self.m
        if not m.passive_names or not self._sliders:
            return home
        rng = np.random.default_rng(HOME_SEED)
        low = np.array([s["low"] for s in self._sliders]) + HOME_INSIDE * self._span
        high = np.array([s["high"] for s in self._sliders]) - HOME_INSIDE * self._span
        revolute = np.array([s["revolute"] for s in self._sliders])
        try:
            one = Configuration(home.actuated[None], home.passive[None], home.pose[None])
            inside = bool(((home.actuated >= low) & (home.actuated <= high)).all())
            best, score = home, float(self._room(one)[0]) + HOME_MARGIN if inside else -np.inf
            spread = HOME_SPREAD
            for _ in range(HOME_ROUNDS):
                scale = np.where(revolute, 1.0, np.maximum(np.abs(best.actuated), self._scale * 1e-3))
                inputs = best.actuated + spread * scale * rng.standard_normal((HOME_CANDIDATES, best.actuated.size))
                inputs = inputs[((inputs >= low) & (inputs <= high)).all(-1)]
                spread /= 2
                if not inputs.size:
                    continue
                guess = np.broadcast_to(best.passive, (inputs.shape[0], best.passive.size))
                solved = m.forward_pose(inputs, guess, strict=False)
                # closed, and a mode the page can list (forward_pose_all keeps the joint limits)
                closed = np.asarray(solved.converged & solved.within_limits) & np.isfinite(solved.pose).all((-2, -1))
                if not closed.any():
                    continue
                found = Configuration(inputs[closed], solved.passive[closed], solved.pose[closed])
                room = self._room(found)
                k = int(np.argmax(room))
                if room[k] > score:
                    score = float(room[k])
                    best = Configuration(found.actuated[k].copy(), found.passive[k].copy(), found.pose[k].copy())
        except ParakinError:
            return home
        return best

    def _restart(self, start: Configuration) -> Configuration:
        """A new tracker from ``start`` (strict: a change of mode raises); a serial chain has no
        passive joints to track and is solved in closed form by ``forward_pose`` instead."""
        config = Configuration(
            np.array(start.actuated, dtype=float).reshape(-1),
            np.array(start.passive, dtype=float).reshape(-1),
            np.array(start.pose, dtype=float).reshape(4, 4),
        )
        self._tracker = self.m.tracker(config) if self.m.passive_names else None
        return config

    def _solve(self, actuated: np.ndarray) -> Configuration:
        """The tracker's next solution (raises its error and keeps the previous one on failure)."""
        if self._tracker is None:
            solved = self.m.forward_pose(actuated)
            return Configuration(np.array(solved.actuated), np.array(solved.passive), np.array(solved.pose))
        passive, pose = self._tracker.solve(actuated)
        return Configuration(self._tracker.actuated[0].copy(), passive.copy(), pose.copy())

    # ------------------------------------------------------------------ what a configuration shows
    def _polylines(self, config: Configuration) -> dict[str, list[list[float | None]]]:
        drawing = self.m.capabilities.drawing
        if drawing is None:
            return {}
        points = self.m.drawing(config)
        return {
            name: [[_finite_or_none(points[s][axis, i]) for s, i in vertices] for axis in range(3)]
            for name, vertices in drawing.polylines.items()
        }

    def _measures(self, config: Configuration) -> list[tuple[str, float | None]]:
        try:
            values = self.m.singularities(config)
        except ParakinError:  # a measure not finite here: none shown rather than a wrong one
            return []
        return [(name, _finite_or_none(float(value))) for name, value in values.items()]

    def _sphere_of(self, config: Configuration) -> dict[str, Any] | None:
        """A spherical mechanism's sphere (centre in {B}, radius), as ``parakin.interfaces.plot``
        finds it: the page then draws it and great-circle arcs between the polylines' vertices."""
        if self.m.capabilities.drawing is None:
            return None
        from parakin.interfaces.plot import sphere_of

        sphere = sphere_of(self.m, [config], self._points(config))
        if sphere is None:
            return None
        return {"centre": [float(v) for v in sphere.centre], "radius": float(sphere.radius)}

    def _drawing_scale(self, config: Configuration) -> float:
        """The drawing's size (m): the largest extent of its points or of the platform position."""
        extent = float(np.ptp(self._points(config), axis=-1).max())
        return max(extent, float(np.abs(config.pose[:3, 3]).max()), 1e-9)

    def _residual(self, config: Configuration) -> float | None:
        if not self.m.passive_names:
            return 0.0  # a serial chain closes by construction
        try:
            closure = self.m.loop_closure(config.actuated, config.passive)["residual"]
        except ParakinError:
            return None
        return _finite_or_none(np.abs(closure).max(initial=0.0))

    def _conditioning(self, config: Configuration) -> float | None:
        """Distance to a type II singularity: sigma_min / sigma_max of the closure Jacobian
        d closure / d passive (``parakin.singularity.inverse_condition``: 1 well conditioned, 0
        singular; the measure ``forward_pose_all`` reports per mode and the tracker's)."""
        if not self.m.passive_names:
            return None
        try:
            jacobian = self.m.loop_closure(config.actuated, config.passive)["jacobian"]
        except ParakinError:
            return None
        return _finite_or_none(float(inverse_condition(jacobian)))

    def _report(self, error: dict[str, str] | None = None, requested: Any = None) -> dict[str, Any]:
        config = self._config
        return {
            "ok": error is None,
            "error": error,
            "requested": _echo(requested),
            "actuated": [float(v) for v in config.actuated],
            "passive": [_finite_or_none(v) for v in config.passive],
            "pose": [_finite_or_none(v) for v in xyz_euler_deg_from_pose(config.pose)],
            "polylines": self._polylines(config),
            "measures": self._measures(config),
            "conditioning": self._conditioning(config),
            "residual": self._residual(config),
            "mode": self._mode_number(),
        }

    # ------------------------------------------------------------------ assembly modes
    def _key(self, actuated: np.ndarray) -> tuple[float, ...]:
        return tuple(float(v) for v in actuated)

    def _assembly_modes(self, actuated: np.ndarray) -> AssemblyModes:
        """Every assembly mode of one input, computed once (the latest MODES_CACHED inputs kept)."""
        key = self._key(actuated)
        with self._modes_lock:
            if key not in self._modes:
                self._modes[key] = self.m.forward_pose_all(actuated)
                while len(self._modes) > MODES_CACHED:
                    self._modes.popitem(last=False)
            self._modes.move_to_end(key)
            return self._modes[key]

    def _table(self, actuated: np.ndarray, modes: AssemblyModes) -> _Table:
        """The numbered modes of one input (under ``_lock``): numbered once, by continuity from
        the table shown before (``_continued``), the followed mode holding its number at the drawn
        input; this table becomes the one the next continues from."""
        key = self._key(actuated)
        table = self._tables.get(key)
        if table is None or table.modes is not modes:
            count = len(modes)
            prints = np.array([self._fingerprint(modes.mode(k)) for k in range(count)], dtype=float)
            prints = prints.reshape(count, -1) if count else np.zeros((0, 0))  # an input without a mode
            table = _Table(modes, prints, self._continued(prints))
            self._tables[key] = table
            while len(self._tables) > MODES_CACHED:
                self._tables.popitem(last=False)
        self._tables.move_to_end(key)
        self._reference = table
        return table

    def _continued(self, prints: np.ndarray) -> list[int]:
        """Numbers for the modes with fingerprints ``prints``: the first table's own order; later,
        each mode takes the number of the nearest mode of the previous table (closest pairs first,
        each number once), and a mode with no partner there the smallest number not in use."""
        reference = self._reference
        if reference is None or not len(reference.labels) or prints.shape[1] != reference.prints.shape[1]:
            return list(range(len(prints)))
        distance = np.abs(prints[:, None, :] - reference.prints[None, :, :]).max(-1, initial=0.0)
        labels: list[int | None] = [None] * len(prints)
        used: set[int] = set()
        for flat in np.argsort(distance, axis=None, kind="stable"):
            i, j = divmod(int(flat), distance.shape[1])
            if labels[i] is None and reference.labels[j] not in used:
                labels[i] = reference.labels[j]
                used.add(reference.labels[j])
        out = []
        for label in labels:
            if label is None:
                label = self._unused(used)
                used.add(label)
            out.append(label)
        return out

    @staticmethod
    def _unused(used: set[int] | list[int]) -> int:
        return next(k for k in range(len(used) + 1) if k not in used)

    def _drawn_row(self, table: _Table) -> int | None:
        """Which row of ``table`` (a table of the drawn input) the drawing is, making the followed
        mode's number that row's (swapping with the row that had it), or taking the followed
        number from that row when none is known yet; None when no row matches (the drawing and
        the pose decide: a quaternion and its negative are one mode)."""
        if not len(table.labels):
            row = None
        else:
            distance = np.abs(table.prints - self._fingerprint(self._config)).max(-1, initial=0.0)
            nearest = int(np.argmin(distance))
            row = nearest if distance[nearest] <= SAME_MODE * max(1.0, self._scale) else None
        followed = self._followed
        if followed is None:
            if row is not None:
                self._followed = table.labels[row]
            return row
        holder = table.labels.index(followed) if followed in table.labels else None
        if row is None:  # the drawing is not listed (outside a joint limit): no row wears its number
            if holder is not None:
                table.labels[holder] = self._unused(table.labels)
        elif holder != row:
            if holder is not None:
                table.labels[holder] = table.labels[row]
            table.labels[row] = followed
        return row

    def _mode_number(self) -> int | None:
        """The number of the mode the tracker follows: kept while it is followed, taken from its
        input's table when that is known and no number is yet (at the start, after home)."""
        table = self._tables.get(self._key(self._config.actuated))
        if table is not None:
            self._drawn_row(table)
        return self._followed

    def _fingerprint(self, config: Configuration) -> np.ndarray:
        """Pose entries and every drawn point: equal for one mode, different across modes."""
        parts = [np.asarray(config.pose, dtype=float).reshape(-1)]
        if self.m.capabilities.drawing is not None:
            parts += [v.reshape(-1) for v in self.m.drawing(config).values()]
        return np.concatenate(parts)

    # ------------------------------------------------------------------ requests
    def _actuated(self, values: Any) -> np.ndarray:
        """Request values as (n_a,) floats (range checks are the solvers'): BadInputError else."""
        names = self.m.actuated_names
        if not isinstance(values, list) or len(values) != len(names):
            raise BadInputError(
                f"actuated must be a list of {len(names)} numbers ({', '.join(names)}), got {_shown(values)}"
            )
        if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in values):
            raise BadInputError(f"actuated must hold numbers only, got {_shown(values)}")
        try:
            array = np.array(values, dtype=float)
        except OverflowError:
            array = np.full(len(values), np.inf)
        if not np.isfinite(array).all():
            raise BadInputError(f"actuated must hold finite numbers, got {_shown(values)}")
        return array

    def scene(self) -> dict[str, Any]:
        """What the page is built from: title, sliders, polyline names and parts, view kind and size."""
        m = self.m
        home = self._config
        planar = self._planar()
        return {
            "name": m.name,
            "title": m.manifest.title,
            "backend": m.backend.name,
            "sliders": self._sliders,
            "polylines": list(m.capabilities.drawing.polylines) if m.capabilities.drawing else [],
            "parts": dict(m.capabilities.drawing.parts) if m.capabilities.drawing else {},
            "planar": planar,
            "scale": self._scale,
            "sphere": self._sphere,
            "centre": self._centre(home) if self._sphere is None else self._sphere["centre"],
            "radius": self._radius(home) if self._sphere is None else 1.05 * self._sphere["radius"],
            "pose_components": list(POSE_COMPONENTS.get(m.manifest.pose_kind, range(6))),
            # the planar turn is phi (alpha of the Z-Y-X angles), as in the modes table
            "pose_labels": [
                "phi [deg]" if label == "alpha [deg]" and m.manifest.pose_kind == "planar" else label
                for label in POSE_LABELS
            ],
            "home_measures": self._home_measures,
            "home_conditioning": self._home_conditioning,
            "tracks": bool(m.passive_names),
        }

    def _points(self, config: Configuration) -> np.ndarray:
        """Every finite drawn point (3, k) in {B}, or the platform origin without a drawing."""
        cloud = [np.asarray(line, dtype=float) for line in self._polylines(config).values()]
        points = np.concatenate(cloud, axis=-1) if cloud else config.pose[:3, 3:]
        points = points[:, np.isfinite(points).all(0)]
        return points if points.size else np.zeros((3, 1))

    def _centre(self, config: Configuration) -> list[float]:
        """The centre of the drawing's bounding box (m, {B}): the view turns about it."""
        points = self._points(config)
        return [float(v) for v in (points.min(-1) + points.max(-1)) / 2]

    def _radius(self, config: Configuration) -> float:
        """Half the bounding box's diagonal (m): the drawing fits a circle of it in every view."""
        points = self._points(config)
        return max(float(np.linalg.norm(np.ptp(points, axis=-1))) / 2, 1e-9)

    def _planar(self) -> bool:
        """The drawing lies in one plane z = const (drawn in 2-D): the mechanism's pose kind says
        so, or the home drawing is flat."""
        if self.m.manifest.pose_kind in ("planar", "planar_translation"):
            return True
        lines = [np.asarray(line, dtype=float) for line in self._polylines(self._config).values()]
        if not lines:
            return False
        z = np.concatenate([line[2] for line in lines])
        return bool(np.ptp(z) <= 1e-9 * self._scale)

    def sliders(self) -> list[dict[str, Any]]:
        """One slider per actuated input: name, unit, revolute, low, high, step, home (SI).

        The range is the actuator's declared range (``m.actuated_ranges``) where it is finite;
        an open side is a span around the home input: +-180 deg for a revolute input, +-50 % of
        its home value (or of the drawing's size at 0) for a prismatic one, clipped to the range.
        """
        m = self.m
        out = []
        for k, variable in enumerate(m.manifest.actuated):
            low, high = m.actuated_ranges[variable.name]
            home = float(m.home_actuated[k])
            if not (math.isfinite(low) and math.isfinite(high)):
                half = math.pi if variable.revolute else 0.5 * (abs(home) or self._scale)
                low, high = max(low, home - half), min(high, home + half)
            out.append(
                {
                    "name": variable.name,
                    "unit": "deg" if variable.revolute else (variable.unit or ""),
                    "revolute": bool(variable.revolute),
                    "low": float(low),
                    "high": float(high),
                    "step": float(high - low) / SLIDER_STEPS,
                    "home": home,
                }
            )
        return out

    def state(self) -> dict[str, Any]:
        """The current configuration."""
        with self._lock:
            return self._report()

    def move(self, actuated: Any) -> dict[str, Any]:
        """Track to new actuated values (SI, one per input), in pieces of at most 1/TRACK_PIECES
        of each slider's range. A value outside an actuator's range is refused before any step;
        a piece the tracker refuses (no convergence, a singular Jacobian, a change of assembly
        mode) ends the move at the last piece solved, reported with the solver's error class and
        a message that says where and why the followed mode cannot go on (``_refusal``)."""
        with self._lock:
            try:
                target = self._actuated(actuated)
                low, high = self.m.actuated_bounds
                within_ranges(target, self.m.actuated_names, low, high, "actuated")
            except ParakinError as error:
                return self._report(_error(error), requested=actuated)
            start = self._config.actuated
            pieces = np.abs(target - start) / np.where(self._span > 0, self._span / TRACK_PIECES, np.inf)
            count = int(min(MAX_PIECES, max(1, math.ceil(float(np.nan_to_num(pieces.max(initial=0.0)))))))
            for fraction in np.arange(1, count + 1) / count:
                piece = target if fraction == 1 else start + fraction * (target - start)
                try:
                    self._config = self._solve(piece)
                except ParakinError as error:
                    return self._report(self._refusal(error, piece, target - start), requested=actuated)
            return self._report(requested=actuated)

    # ------------------------------------------------------------------ a refused move, in the user's terms
    def _refusal(self, error: ParakinError, piece: np.ndarray, direction: np.ndarray) -> dict[str, str]:
        """The reply's error for a piece of a move the solver refused: where on the piece the
        followed mode stops being trackable (bisection on a scratch tracker from the drawn
        configuration, which stays as it is) and what is there. A singular configuration there is
        a fold when nothing of the mode lies just beyond (it meets another mode and both cease to
        exist), a crossing when the solution goes on through the singularity into another mode;
        elsewhere the solver's cause is named in plain words."""
        if self._tracker is None:  # a serial chain: the closed form's own message
            return _error(error)
        try:
            reached = self._last_trackable(piece)
        except ParakinError:
            reached = self._config
        if self._followed is None:  # no list of modes asked for yet: number the drawn one now
            try:
                here = self._config.actuated
                self._drawn_row(self._table(here, self._assembly_modes(here)))
            except ParakinError:
                pass
        mode = "the followed assembly mode" if self._followed is None else f"mode {self._followed}"
        where = self._inputs_text(reached.actuated, direction)
        conditioning = self._conditioning(reached)
        if conditioning is not None and conditioning <= SINGULAR_CONDITIONING * self._conditioning_scale:
            if self._continues_through(reached, direction):
                message = (
                    f"{mode} reaches a type II singularity near {where} (closure conditioning "
                    f"{conditioning:.1g}): past it the mechanism would go on in another assembly mode, so the "
                    "viewer stops before it; choose another mode or step back"
                )
            else:
                message = (
                    f"{mode} ends near {where}, a fold: there it meets another assembly mode and both cease "
                    f"to exist (a type II singularity, closure conditioning {conditioning:.1g}); choose another "
                    "mode or step back"
                )
        else:
            cause = {
                ConvergenceError: "no configuration of this mode was found there",
                SingularConfigurationError: "the closure Jacobian became singular on the way",
                AssemblyModeChangeError: "the solution there belongs to another assembly mode",
                BadInputError: "the model has no value there",
            }
            because = next((text for kind, text in cause.items() if isinstance(error, kind)), str(error))
            shown = "" if conditioning is None else f", closure conditioning {conditioning:.2g}"
            message = (
                f"{mode} could not be followed past {where}: {because} (the configuration reached is not "
                f"singular{shown}); step back, try a smaller step or choose another mode"
            )
        return _error(error, message)

    def _last_trackable(self, piece: np.ndarray) -> Configuration:
        """Bisection on the segment from the drawn input to ``piece`` (which the tracker refused):
        the last configuration a scratch tracker reaches on it."""
        reached = self._config
        tracker = self.m.tracker(reached)
        low, high = np.array(reached.actuated, dtype=float), np.array(piece, dtype=float)
        for _ in range(BISECTIONS):
            if not (np.abs(high - low) > 1e-12 * self._span).any():
                break
            middle = low + 0.5 * (high - low)
            try:
                passive, pose = tracker.solve(middle)
            except ParakinError:  # the strict tracker keeps its previous solution
                high = middle
                continue
            low = np.array(tracker.actuated[0], dtype=float)
            reached = Configuration(low.copy(), np.array(passive, dtype=float), np.array(pose, dtype=float))
        return reached

    def _continues_through(self, reached: Configuration, direction: np.ndarray) -> bool:
        """Whether the solution at ``reached`` (a singular configuration) goes on past it: Newton
        from it, allowed to change mode, at an input 1e-6 of the sliders' ranges further along
        ``direction`` converges next to it. Past a fold nothing real lies near (the nearest
        solutions are complex): Newton fails or lands on a distant mode."""
        scaled = np.abs(direction) / np.where(self._span > 0, self._span, np.inf)
        if not scaled.max(initial=0.0) > 0:
            return False
        beyond = reached.actuated + direction * (1e-6 / float(scaled.max()))
        try:
            passive, pose = self.m.tracker(reached, strict=False).solve(beyond)
        except ParakinError:
            return False
        moved = Configuration(beyond, np.array(passive, dtype=float), np.array(pose, dtype=float))
        distance = float(np.abs(self._fingerprint(moved) - self._fingerprint(reached)).max(initial=0.0))
        return distance <= 1e-2 * self._scale

    def _inputs_text(self, actuated: np.ndarray, direction: np.ndarray) -> str:
        """The inputs a move changes, as the sliders show them: "rho1 = 19.042 m", angles in
        degrees; every input when the move changes none."""
        moved = [k for k in range(len(actuated)) if direction[k] != 0] or list(range(len(actuated)))
        parts = []
        for k in moved:
            slider = self._sliders[k]
            if slider["revolute"]:
                parts.append(f"{slider['name']} = {math.degrees(float(actuated[k])):.3f}°")
            else:
                unit = f" {slider['unit']}" if slider["unit"] else ""
                parts.append(f"{slider['name']} = {float(actuated[k]):.6g}{unit}")
        return ", ".join(parts)

    def home(self) -> dict[str, Any]:
        """Back to the home configuration, the tracker restarted there (its mode number: the one
        its row has in the home input's table, once that is known)."""
        with self._lock:
            try:
                self._config = self._restart(self._home())
            except ParakinError as error:
                return self._report(_error(error))
            self._followed = None
            return self._report()

    def modes(self, actuated: Any = None) -> dict[str, Any]:
        """The assembly modes of an input (default: the current one): ``count``, ``rows`` (mode
        number, pose x y z [m], Z-Y-X Euler [deg], conditioning; by number), ``current`` (the
        number of the mode the drawing shows, when the input is the drawn one and the drawing is
        among them), or ``error``. Numbers are the viewer's (see the module docstring)."""
        with self._lock:
            current = self._config
        try:
            theta = current.actuated if actuated is None else self._actuated(actuated)
            modes = self._assembly_modes(theta)
        except ParakinError as error:
            return {"ok": False, "error": _error(error), "actuated": _echo(actuated), "count": 0, "rows": []}
        from parakin.results import mode_headers, modes_rows, modes_summary

        with self._lock:
            table = self._table(theta, modes)
            drawn = np.array_equal(self._config.actuated, theta)
            row = self._drawn_row(table) if drawn else None
            kind = self.m.manifest.pose_kind
            labelled = zip(table.labels, modes_rows(modes, pose_kind=kind), strict=True)
            rows = [[str(label), *cells[1:]] for label, cells in labelled]
            number = None if row is None else table.labels[row]
        return {
            "ok": True,
            "error": None,
            "actuated": [float(v) for v in theta],
            "count": len(modes),
            "summary": modes_summary(modes),
            "headers": mode_headers(self.m.manifest.pose_kind),
            "rows": sorted(rows, key=lambda cells: int(cells[0])),
            "current": number,
        }

    def select(self, mode: Any, actuated: Any = None) -> dict[str, Any]:
        """Restart the tracker from mode number ``mode`` (as ``modes`` numbers them) of an input
        (default: the current one); NoSuchModeError (reported, with the numbers there are) for a
        number the input does not have. The chosen mode keeps its number while it is followed."""
        with self._lock:
            try:
                theta = self._config.actuated if actuated is None else self._actuated(actuated)
                if isinstance(mode, bool) or not isinstance(mode, int):
                    raise BadInputError(f"mode must be an integer, got {_shown(mode)}")
                table = self._table(theta, self._assembly_modes(theta))
                if mode not in table.labels:
                    numbers = f", numbered {_numbers(table.labels)}" if table.labels else ""
                    raise NoSuchModeError(f"no mode {mode} at this input: there are {len(table.labels)} modes{numbers}")
                self._config = self._restart(table.modes.mode(table.labels.index(mode)))
                self._followed = mode
            except ParakinError as error:
                return self._report(_error(error), requested=actuated)
            return self._report(requested=actuated)

    def request(self, path: str, body: dict[str, Any]) -> dict[str, Any]:
        """Dispatch one API call (``/api/<name>``) with its JSON body; BadInputError for an
        unknown one."""
        name = path.removeprefix("/api/")
        if name == "scene":
            return self.scene()
        if name == "state":
            return self.state()
        if name == "move":
            return self.move(body.get("actuated"))
        if name == "home":
            return self.home()
        if name == "modes":
            return self.modes(body.get("actuated"))
        if name == "select":
            return self.select(body.get("mode"), body.get("actuated"))
        raise BadInputError(f"no API call {path!r}: scene, state, move, home, modes, select")


def page() -> str:
    """The viewer's HTML page (self-contained: no script or style from the network)."""
    return resources.files("parakin.interfaces").joinpath("viewer.html").read_text(encoding="utf-8")


def _host_and_port(value: str) -> tuple[str, int | None] | None:
    """A Host header's (or an origin's) host, lower case and without IPv6 brackets, and its port
    (None when absent); None when it is not of that form."""
    found = re.fullmatch(r"(\[[0-9a-f:.]+\]|[^:\[\]/@\s]+)(?::(\d{1,5}))?", value.strip().lower())
    if found is None:
        return None
    return found.group(1).strip("[]"), None if found.group(2) is None else int(found.group(2))


def _parsed_body(data: bytes) -> dict[str, Any]:
    """A request body as a JSON object: strict UTF-8, nesting at most MAX_DEPTH, finite numbers
    only (no NaN, Infinity or number beyond the float range: a reply could not carry them back).
    ValueError naming what is wrong, never quoting more than a few characters of it."""
    text = data.decode("utf-8") if data.strip() else "{}"
    depth, inside, escaped = 0, False, False
    for character in text:  # before the parser, whose recursion fails near 1000 levels
        if inside:
            escaped, inside = (False, True) if escaped else (character == "\\", character != '"')
        elif character == '"':
            inside = True
        elif character in "[{":
            depth += 1
            if depth > MAX_DEPTH:
                raise ValueError(f"the body nests deeper than {MAX_DEPTH} levels")
        elif character in "]}":
            depth -= 1

    def constant(name: str) -> None:
        raise ValueError(f"{name} is not a number JSON allows: numbers must be finite")

    def real(token: str) -> float:
        value = float(token)
        if not math.isfinite(value):
            raise ValueError(f"the number {token[:24]} is beyond the range of a double: numbers must be finite")
        return value

    def integer(token: str) -> int:
        value = int(token)
        try:
            float(value)
        except OverflowError:
            raise ValueError(f"the number {token[:24]}... is beyond the range of a double") from None
        return value

    body = json.loads(text, parse_constant=constant, parse_float=real, parse_int=integer)
    if not isinstance(body, dict):
        raise ValueError(f"the body must be a JSON object, got {type(body).__name__}")
    return body


class _Refused(Exception):
    """A request answered with an HTTP error (status and a message for the page)."""

    def __init__(self, status: int, message: str, allow: str | None = None) -> None:
        super().__init__(message)
        self.status, self.allow = status, allow


class _Handler(BaseHTTPRequestHandler):
    """GET / serves the page, GET /api/<read-only call> and POST /api/<call> a JSON reply; every
    refusal and every malformed request a JSON error."""

    server: _Server

    def setup(self) -> None:
        super().setup()
        self.connection.settimeout(self.server.request_timeout)  # a silent peer is dropped

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 (the base class's name)
        pass  # quiet: a slider drag is dozens of requests a second

    def _send(self, status: int, content_type: str, data: bytes, allow: str | None = None) -> None:
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        if allow is not None:
            self.send_header("Allow", allow)
        if self.close_connection:
            self.send_header("Connection", "close")
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(data)

    def _json(self, status: int, reply: Any, allow: str | None = None) -> None:
        try:
            data = json.dumps(reply, allow_nan=False).encode()
        except (ValueError, TypeError, RecursionError) as error:  # a bug: still a JSON reply
            status = HTTPStatus.INTERNAL_SERVER_ERROR
            data = json.dumps(
                {"ok": False, "error": {"type": "InternalError", "message": f"the reply cannot be encoded: {error}"}}
            ).encode()
        self._send(status, "application/json", data, allow)

    def _refuse(self, refusal: _Refused) -> None:
        error = {"type": "BadRequestError", "message": str(refusal)}
        self._json(refusal.status, {"ok": False, "error": error}, refusal.allow)

    def send_error(self, code: int, message: str | None = None, explain: str | None = None) -> None:
        """The base class's replies to requests it cannot parse (bad request line, headers too
        long or too many, a method with no handler), as JSON errors."""
        self.close_connection = True
        short, long = self.responses.get(code, ("error", ""))
        text = message or short
        if explain or long:
            text = f"{text}: {explain or long}"
        self._refuse(_Refused(code, text))

    def _check_addresses(self) -> None:
        """Host must name this server (a DNS-rebinding page names its own host); an Origin, when
        sent, must be this server's own http origin (a page elsewhere sends its own)."""
        hosts = self.headers.get_all("Host") or []
        if len(hosts) != 1:
            raise _Refused(HTTPStatus.BAD_REQUEST, "the request needs one Host header naming the viewer's address")
        if not self.server.names_me(hosts[0]):
            raise _Refused(
                HTTPStatus.FORBIDDEN,
                f"Host {_shown(hosts[0])} is not this viewer's address: open {self.server.url} (localhost or "
                "127.0.0.1 with its port)",
            )
        origin = self.headers.get("Origin")
        if origin is not None:
            scheme, _, rest = origin.strip().partition("://")
            if scheme.lower() != "http" or not self.server.names_me(rest):
                raise _Refused(
                    HTTPStatus.FORBIDDEN,
                    f"requests from origin {_shown(origin)} are refused: the viewer "
                    f"answers its own page only ({self.server.url})",
                )

    def do_GET(self) -> None:
        try:
            self._check_addresses()
            path = self.path.split("?")[0]
            if path in ("/", "/index.html"):
                self._send(HTTPStatus.OK, "text/html; charset=utf-8", self.server.page)
                return
            call = path.removeprefix("/api/")
            if not path.startswith("/api/"):
                raise _Refused(HTTPStatus.NOT_FOUND, f"no page {_shown(path)}: the viewer is at /")
            if call not in READ_ONLY_CALLS:
                raise _Refused(
                    HTTPStatus.METHOD_NOT_ALLOWED,
                    f"/api/{call[:40]} needs a POST (with a JSON body): a "
                    f"GET only reads ({', '.join(READ_ONLY_CALLS)})",
                    allow="POST",
                )
        except _Refused as refusal:
            self._refuse(refusal)
            return
        self._answer(path, {})

    def do_HEAD(self) -> None:
        self.do_GET()

    def do_POST(self) -> None:
        try:
            self._check_addresses()
            body = self._body()
        except _Refused as refusal:
            self._refuse(refusal)
            return
        self._answer(self.path.split("?")[0], body)

    def _body(self) -> dict[str, Any]:
        """The request's JSON object, read within MAX_BODY bytes; _Refused for anything else."""
        declared = self.headers.get("Content-Type", "").split(";")[0].strip().lower()
        if declared != "application/json":
            raise _Refused(
                HTTPStatus.UNSUPPORTED_MEDIA_TYPE,
                f"a POST must be Content-Type application/json, got {_shown(declared) if declared else 'none'}",
            )
        if self.headers.get("Transfer-Encoding") is not None:
            self.close_connection = True
            raise _Refused(HTTPStatus.LENGTH_REQUIRED, "a POST needs a Content-Length (no Transfer-Encoding)")
        lengths = self.headers.get_all("Content-Length") or ["0"]
        if len(lengths) != 1 or not re.fullmatch(r"\d{1,18}", lengths[0].strip()):
            self.close_connection = True  # where the body ends is unknown
            raise _Refused(
                HTTPStatus.BAD_REQUEST,
                f"Content-Length must be one whole number of bytes, got {_shown(', '.join(lengths))}",
            )
        length = int(lengths[0])
        try:
            if length > MAX_BODY:
                self.close_connection = True
                if length <= DRAIN_LIMIT:  # read and dropped: the sender then reads the reply
                    self.rfile.read(length)
                raise _Refused(
                    HTTPStatus.REQUEST_ENTITY_TOO_LARGE, f"a request body of {length} bytes: at most {MAX_BODY}"
                )
            data = self.rfile.read(length)
        except TimeoutError:
            self.close_connection = True
            raise _Refused(
                HTTPStatus.REQUEST_TIMEOUT, f"the body did not arrive within {self.server.request_timeout:g} s"
            ) from None
        if len(data) < length:
            self.close_connection = True
            raise _Refused(HTTPStatus.BAD_REQUEST, f"the body ended after {len(data)} of {length} bytes")
        try:
            return _parsed_body(data)
        except (ValueError, RecursionError) as error:  # UnicodeDecodeError and JSONDecodeError are ValueErrors
            message = (
                f"the body is not UTF-8 text ({error.reason})" if isinstance(error, UnicodeDecodeError) else str(error)
            )
            raise _Refused(
                HTTPStatus.BAD_REQUEST, f"the request is not a JSON object the viewer reads: {message}"
            ) from None

    def _answer(self, path: str, body: dict[str, Any]) -> None:
        try:
            reply = self.server.session.request(path, body)
        except ParakinError as error:
            self._json(HTTPStatus.BAD_REQUEST, {"ok": False, "error": _error(error)})
        except Exception as error:  # a bug: say so on the page rather than drop the connection
            self._json(
                HTTPStatus.INTERNAL_SERVER_ERROR,
                {"ok": False, "error": {"type": "InternalError", "message": f"{type(error).__name__}: {error}"}},
            )
        else:
            self._json(HTTPStatus.OK, reply)


class _Server(ThreadingHTTPServer):
    daemon_threads = True

    def __init__(self, address: tuple[str, int], session: ViewerSession) -> None:
        super().__init__(address, _Handler)
        self.session = session
        self.page = page().encode("utf-8")
        self.request_timeout = REQUEST_TIMEOUT
        self.port = int(self.server_address[1])
        bound = address[0].strip("[]").lower()
        #: a wildcard bind is reachable at any of the machine's addresses: any IP literal may be
        #: named then (DNS rebinding needs a host name, never a literal address)
        self.any_address = bound in ("", "0.0.0.0", "::")
        self.names = {"localhost", "127.0.0.1", "::1"} | ({bound} if not self.any_address else set())
        shown = "127.0.0.1" if self.any_address else address[0]
        self.url = f"http://{shown}:{self.port}/"

    def names_me(self, value: str) -> bool:
        """Whether ``value`` (host[:port]) names this server: one of its names with its port."""
        parsed = _host_and_port(value)
        if parsed is None:
            return False
        host, port = parsed
        if (port if port is not None else 80) != self.port:
            return False
        if host in self.names:
            return True
        if self.any_address:
            try:
                ipaddress.ip_address(host)
            except ValueError:
                return False
            return True
        return False


class Viewer:
    """A running viewer: ``url``, ``session`` (its state), ``close()``; a context manager, and an
    iframe of the page in a notebook (``_repr_html_``)."""

    def __init__(self, m: Mechanism, host: str = "127.0.0.1", port: int = 0) -> None:
        self.session = ViewerSession(m)
        self._server = _Server((host, port), self.session)
        self.host, self.port = host, int(self._server.server_address[1])
        self._thread = threading.Thread(target=self._server.serve_forever, name=f"parakin-viewer-{m.name}", daemon=True)
        self._thread.start()

    @property
    def url(self) -> str:
        """The page's address."""
        return f"http://{self.host}:{self.port}/"

    def close(self) -> None:
        """Stop the server (idempotent)."""
        if self._thread.is_alive():
            self._server.shutdown()
            self._thread.join()
        self._server.server_close()

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<parakin viewer of {self.session.m.name} at {self.url}>"

    def _repr_html_(self) -> str:
        return (
            f'<iframe src="{self.url}" width="100%" height="640" style="border:1px solid #ccc" '
            f'title="parakin viewer: {self.session.m.name}"></iframe>'
        )


def serve(m: Mechanism, port: int = 0, open_browser: bool = False, host: str = "127.0.0.1") -> Viewer:
    """Start a viewer of ``m`` on ``host:port`` (port 0: any free one) in a background thread;
    open it in the default browser when asked. The server runs until ``close()``."""
    viewer = Viewer(m, host, port)
    if open_browser:
        webbrowser.open(viewer.url)
    return viewer


def show(m: Mechanism, port: int = 0, width: str = "100%", height: int = 640) -> Any:
    """A viewer of ``m`` for a notebook: an IPython IFrame of its page (the Viewer itself, which
    renders as the same iframe, where IPython is missing). The server runs until the kernel ends
    or ``.viewer.close()`` / ``Viewer.close()``."""
    viewer = serve(m, port)
    try:
        from IPython.display import IFrame
    except ImportError:
        return viewer
    frame = IFrame(viewer.url, width=width, height=height)
    frame.viewer = viewer  # type: ignore[attr-defined]  # keep the server reachable
    return frame


def _port(text: str) -> int:
    """A TCP port number, 0 (any free port) to 65535, for argparse (its message on anything else)."""
    try:
        port = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a port number (0 to 65535)") from None
    if not 0 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"{port} is not a port number (0 to 65535; 0: any free port)")
    return port


def main(argv: Sequence[str] | None = None) -> int:
    """``parakin view NAME [--port P] [--open]``: serve a viewer of NAME, print its URL, run until
    interrupted (Ctrl-C: ``parakin: interrupted``, exit status 130). Exit status 2 for an
    unknown mechanism or bad arguments."""
    import parakin

    parser = argparse.ArgumentParser(
        prog="parakin view",
        description="Serve an interactive viewer of the mechanism NAME in the browser (a slider per actuated "
        "input, its assembly modes, singularity measures), print its address and run until Ctrl-C.",
    )
    parser.add_argument("name", help="a mechanism name (parakin list) or package folder")
    parser.add_argument("--port", type=_port, default=0, help="port to listen on (default: any free port)")
    parser.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to bind (default 127.0.0.1: this machine only); the page answers to that address, "
        "localhost and 127.0.0.1 with the port, and after 0.0.0.0 to any IP address, never to a host name",
    )
    parser.add_argument("--backend", default="auto", choices=["auto", "compiled", "numpy", "casadi"])
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE", help="a mechanism parameter")
    parser.add_argument("--open", action="store_true", help="open the page in the default browser")
    args = parser.parse_args(argv)
    try:
        parameters: dict[str, Any] = {}
        for item in args.param:
            key, sep, value = item.partition("=")
            if not sep:
                raise BadInputError(f"--param needs NAME=VALUE, got {item!r}")
            parameters[key] = float(value)
        m = parakin.load(args.name, backend=args.backend, **parameters)
        viewer = serve(m, args.port, args.open, args.host)
    except (ParakinError, ValueError, OSError) as error:
        print(f"parakin: {type(error).__name__}: {error}", file=sys.stderr)
        return 2
    print(viewer.url, flush=True)
    try:
        threading.Event().wait()
    except KeyboardInterrupt:  # the way to stop it: as every command, "interrupted" and 130
        print("\nparakin: interrupted", file=sys.stderr)
        return 130
    finally:
        viewer.close()
    return 0


__all__ = ["Viewer", "ViewerSession", "main", "page", "serve", "show"]

if __name__ == "__main__":
    sys.exit(main())
