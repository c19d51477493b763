"""An interactive viewer of any generated mechanism, in the browser and in notebooks.

A small standard-library HTTP server (``http.server`` in a thread, bound to 127.0.0.1 unless told
otherwise) serves one self-contained page (``viewer.html``: inline JavaScript and a canvas, no
network) and a JSON API over a ``ViewerSession``:

- a slider per actuated input (SI units in the API and on the wire; revolute inputs labelled in
  degrees) drives the runtime's tracker (``m.tracker``): the assembly mode is followed
  continuously, and a step the tracker refuses (a crossed type II singularity, a branch it
  cannot follow, no convergence, a value outside the actuator's range) is reported by the named
  error of ``parakin.errors`` and its message, the drawing staying at the last solved input:
  never a silent jump of assembly mode;
- a mode selector lists the assembly modes of the current input (``m.forward_pose_all``,
  numbered 0 .. count - 1 as ``AssemblyModes.mode(k)``); choosing one restarts the tracker there;
- the singularity measures (``m.singularities``: named serial and type II factors and the
  determinants, zero means singular) and the closure Jacobian's conditioning update live;
- the drawing is the generated drawing kernel's point sets (``m.drawing``: 3 x n in {B}, metres)
  joined by the manifest's polylines, in 3-D (drag to orbit, wheel to zoom, shift-drag to pan) or
  in the plane for a drawing that lies in one plane z = const.

Nothing here knows a mechanism: every slider, measure and polyline comes from the manifest.
``serve(m)`` starts a server (``Viewer``: ``url``, ``close()``, a context manager, an iframe in
notebooks), ``show(m)`` returns that iframe, ``python -m parakin.interfaces.viewer NAME`` serves one from the
shell (``main(argv)``).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import threading
import webbrowser
from collections import OrderedDict
from collections.abc import Sequence
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from typing import TYPE_CHECKING, Any

import numpy as np

from parakin.errors import BadInputError, ParakinError
from parakin.pose import xyz_euler_deg_from_pose
from parakin.results import MODE_HEADERS, AssemblyModes, Configuration
from parakin.solvers.linalg import pivoted_solve
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
#: a configuration is mode k when its pose and drawing agree with mode k's to this, relative to
#: the drawing's size (the tracker and the mode polisher both converge to about 1e-12)
SAME_MODE = 1e-7
#: pose shown on the page: position of {P} in {B} and Z-Y-X Euler angles of ^B_P R
POSE_LABELS = tuple(POSE_HEADERS)


def _finite_or_none(value: float) -> float | None:
    """JSON has no NaN or infinity: such a value goes out as null."""
    value = float(value)
    return value if math.isfinite(value) else None


def _error(error: BaseException) -> dict[str, str]:
    return {"type": type(error).__name__, "message": str(error)}


class ViewerSession:
    """The viewer's state and every request it answers, without HTTP (the server calls these; the
    tests too). One session follows one mechanism from its home configuration.

    Replies are JSON-ready dicts. A state reply (``state``, ``move``, ``select``, ``home``) holds
    ``ok``, ``error`` ({type, message} of the parakin error, or None), ``actuated`` (the input the
    drawing shows, SI), ``requested`` (what was asked), ``polylines`` (name -> 3 x k vertices in
    {B}, metres), ``measures`` ([name, value] of ``m.singularities``), ``conditioning`` (pivot ratio
    of the closure Jacobian: 1 well conditioned, 0 singular), ``residual`` (max-norm of the loop
    closure at the drawn configuration), ``pose`` (x, y, z in m, Z-Y-X Euler in deg) and ``mode``
    (its number among the modes of its input when those are known, else None).
    """

    def __init__(self, m: Mechanism, start: Configuration | None = None) -> None:
        self.m = m
        self._lock = threading.RLock()  # the tracker and the current configuration
        self._modes_lock = threading.Lock()  # one forward_pose_all at a time
        self._modes: OrderedDict[tuple[float, ...], AssemblyModes] = OrderedDict()
        self._tracker: ForwardPoseTracker | None = None
        self._config = self._restart(start if start is not None else self._home())
        self._home_measures = dict(self._measures(self._config))
        self._home_conditioning = self._conditioning(self._config)
        self._scale = self._drawing_scale(self._config)
        self._sliders = self.sliders()
        self._span = np.array([s["high"] - s["low"] for s in self._sliders], dtype=float)

    # ------------------------------------------------------------------ configurations
    def _home(self) -> Configuration:
        """The home configuration, closed by Newton from the manifest's home values (every
        package's home closes: the contract tests check it)."""
        return self.m.forward_pose(self.m.home_actuated, guess=self.m.home_passive)

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
        """Pivot ratio of the closure Jacobian d closure / d passive (1 well conditioned, 0 at a
        type II singularity; the tracker's and the mode finder's measure)."""
        if not self.m.passive_names:
            return None
        try:
            jacobian = self.m.loop_closure(config.actuated, config.passive)["jacobian"]
        except ParakinError:
            return None
        if jacobian.shape[-1] != jacobian.shape[-2]:
            return None
        return _finite_or_none(float(pivoted_solve(jacobian, np.zeros(jacobian.shape[-1]))[1]))

    def _report(self, error: BaseException | None = None, requested: Any = None) -> dict[str, Any]:
        config = self._config
        return {
            "ok": error is None,
            "error": None if error is None else _error(error),
            "requested": requested,
            "actuated": [float(v) for v in config.actuated],
            "passive": [_finite_or_none(v) for v in config.passive],
            "pose": [_finite_or_none(v) for v in xyz_euler_deg_from_pose(config.pose)],
            "polylines": self._polylines(config),
            "measures": self._measures(config),
            "conditioning": self._conditioning(config),
            "residual": self._residual(config),
            "mode": self._mode_number(config),
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

    def _mode_number(self, config: Configuration) -> int | None:
        """Which mode of its input ``config`` is (0 .. count - 1), when that input's modes are
        known; None when they are not, or none matches (the drawing and the pose decide: a
        quaternion and its negative are one mode)."""
        modes = self._modes.get(self._key(config.actuated))
        if modes is None:
            return None
        tolerance = SAME_MODE * max(1.0, self._scale)
        here = self._fingerprint(config)
        for number, mode in enumerate(modes):
            if np.abs(self._fingerprint(mode) - here).max(initial=0.0) <= tolerance:
                return number
        return None

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
            raise BadInputError(f"actuated must be a list of {len(names)} numbers ({', '.join(names)}), got {values!r}")
        if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in values):
            raise BadInputError(f"actuated must hold numbers only, got {values!r}")
        return np.array(values, dtype=float)

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
            "centre": self._centre(home),
            "radius": self._radius(home),
            "pose_components": list(POSE_COMPONENTS.get(m.manifest.pose_kind, range(6))),
            "pose_labels": list(POSE_LABELS),
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
        mode) ends the move at the last piece solved, reported with the error (named, with its
        message)."""
        with self._lock:
            try:
                target = self._actuated(actuated)
                low, high = self.m.actuated_bounds
                within_ranges(target, self.m.actuated_names, low, high, "actuated")
                start = self._config.actuated
                pieces = np.abs(target - start) / np.where(self._span > 0, self._span / TRACK_PIECES, np.inf)
                count = int(min(MAX_PIECES, max(1, math.ceil(float(np.nan_to_num(pieces.max(initial=0.0)))))))
                for fraction in np.arange(1, count + 1) / count:
                    self._config = self._solve(target if fraction == 1 else start + fraction * (target - start))
            except ParakinError as error:
                return self._report(error, requested=actuated)
            return self._report(requested=actuated)

    def home(self) -> dict[str, Any]:
        """Back to the home configuration, the tracker restarted there."""
        with self._lock:
            try:
                self._config = self._restart(self._home())
            except ParakinError as error:
                return self._report(error)
            return self._report()

    def modes(self, actuated: Any = None) -> dict[str, Any]:
        """The assembly modes of an input (default: the current one): ``count``, ``rows`` (mode,
        pose x y z [m], Z-Y-X Euler [deg], conditioning), ``current`` (the mode the drawing shows,
        when the input is the drawn one), or ``error``."""
        with self._lock:
            current = self._config
        try:
            theta = current.actuated if actuated is None else self._actuated(actuated)
            modes = self._assembly_modes(theta)
        except ParakinError as error:
            return {"ok": False, "error": _error(error), "actuated": actuated, "count": 0, "rows": []}
        from parakin.results import modes_rows, modes_summary

        with self._lock:
            drawn = self._config
            number = self._mode_number(drawn) if np.array_equal(drawn.actuated, theta) else None
        return {
            "ok": True,
            "error": None,
            "actuated": [float(v) for v in theta],
            "count": len(modes),
            "summary": modes_summary(modes),
            "headers": list(MODE_HEADERS),
            "rows": modes_rows(modes),
            "current": number,
        }

    def select(self, mode: Any, actuated: Any = None) -> dict[str, Any]:
        """Restart the tracker from mode ``mode`` (0 .. count - 1) of an input (default: the
        current one); NoSuchModeError (reported) for a number the input does not have."""
        with self._lock:
            try:
                theta = self._config.actuated if actuated is None else self._actuated(actuated)
                if isinstance(mode, bool) or not isinstance(mode, int):
                    raise BadInputError(f"mode must be an integer, got {mode!r}")
                chosen = self._assembly_modes(theta).mode(mode)
                self._config = self._restart(chosen)
            except ParakinError as error:
                return self._report(error, requested=actuated)
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


class _Handler(BaseHTTPRequestHandler):
    """GET / serves the page, POST /api/<call> a JSON reply; nothing else."""

    server: _Server

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 (the base class's name)
        pass  # quiet: a slider drag is dozens of requests a second

    def _send(self, status: int, content_type: str, data: bytes) -> None:
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(data)

    def _json(self, status: int, reply: Any) -> None:
        self._send(status, "application/json", json.dumps(reply, allow_nan=False).encode())

    def do_GET(self) -> None:
        if self.path.split("?")[0] in ("/", "/index.html"):
            self._send(HTTPStatus.OK, "text/html; charset=utf-8", self.server.page)
        elif self.path.startswith("/api/"):
            self._answer({})
        else:
            self._send(HTTPStatus.NOT_FOUND, "text/plain", b"not found")

    def do_POST(self) -> None:
        length = int(self.headers.get("Content-Length") or 0)
        if not 0 <= length <= MAX_BODY:
            self._json(HTTPStatus.REQUEST_ENTITY_TOO_LARGE, {"ok": False, "error": {"type": "BadInputError",
                       "message": f"request body of {length} bytes: at most {MAX_BODY}"}})  # fmt: skip
            return
        try:
            body = json.loads(self.rfile.read(length) or b"{}")
            if not isinstance(body, dict):
                raise ValueError("the body must be a JSON object")
        except ValueError as error:
            self._json(HTTPStatus.BAD_REQUEST, {"ok": False, "error": {"type": "BadInputError", "message": str(error)}})
            return
        self._answer(body)

    def _answer(self, body: dict[str, Any]) -> None:
        try:
            reply = self.server.session.request(self.path, body)
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


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m parakin.interfaces.viewer NAME [--port P]``: serve a viewer of NAME, print its URL, run
    until interrupted. Exit status 0, or 2 for an unknown mechanism or bad arguments."""
    import parakin

    parser = argparse.ArgumentParser(prog="python -m parakin.interfaces.viewer", description=main.__doc__)
    parser.add_argument("name", help="a mechanism name (parakin list) or package folder")
    parser.add_argument("--port", type=int, default=0, help="port to listen on (default: any free port)")
    parser.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1: this machine only)")
    parser.add_argument("--backend", default="auto", help="auto, compiled, numpy or casadi")
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
        print(f"parakin viewer: {error}", file=sys.stderr)
        return 2
    print(viewer.url, flush=True)
    try:
        threading.Event().wait()
    except KeyboardInterrupt:
        pass
    finally:
        viewer.close()
    return 0


__all__ = ["Viewer", "ViewerSession", "main", "page", "serve", "show"]

if __name__ == "__main__":
    sys.exit(main())
