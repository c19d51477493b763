"""Pictures of any mechanism from its generated drawing kernel (matplotlib, optional extra 'plot').

The kernel returns named point sets (3 x n, in {B}, metres) for a configuration; the manifest
lists the polylines through them. ``plot`` draws one configuration, a chosen assembly mode, every
mode overlaid on given axes, or the modes as a grid of small multiples (common limits, each panel
titled "mode k"; by default the first ``MAX_PANELS``, the others named in the title, and every
one with ``all_modes``); ``animate`` draws a GIF along an actuated trajectory, tracking one mode.
How a drawing is drawn comes from the package alone (``compose_scene``):

- a drawing in one plane z = const is drawn on 2-D axes (the x-y plane);
- a spherical one (pose kind ``rotation``, every point at one distance from the fixed centre) on
  its translucent sphere, with great-circle arcs between consecutive points instead of chords;
- polylines are parts (base, legs, platform) as the manifest says (``Drawing.parts``), each with
  its own colour and width; joints of the manifest's fixed point sets are squares, moving joints
  circles, each no wider than a share of the segments it ends (``marker_sizes``: a small
  platform is not hidden under its joints); in 3-D the parts are drawn in that order, not by
  depth; a legend names the parts;
- every panel shows the distance to singularity (``parakin.singularity``): ``type II`` (1/cond of
  the loop-closure Jacobian) and ``type I`` (1/cond of the rate model's B, or of the worst leg
  Jacobian), 1 far, 0 singular; a grid's panel below ``NEAR_SINGULAR`` in type II is titled in
  red, "near-singular" (the MJCF export warns of such keyframes with the same measure and level,
  and ``parakin sweep`` maps it).
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from parakin.errors import (
    AssemblyModeChangeError,
    BadInputError,
    ConvergenceError,
    NoSuchModeError,
    ParakinError,
    SelfMotionError,
    UnreachablePoseError,
    UnsupportedOperationError,
)
from parakin.packages.manifest import DRAWING_PARTS
from parakin.results import Array, AssemblyModes, Configuration
from parakin.singularity import NEAR_SINGULAR, is_near_singular, singularity_distance

if TYPE_CHECKING:
    from parakin.solvers.loaded import LoadedMechanism


# ---------------------------------------------------------- the scene: what a picture shows
#: the parts a polyline can belong to, in drawing order (later parts are drawn on top)
PARTS = DRAWING_PARTS
#: relative tolerance of the planarity and sphere tests (the kernel's points are exact to rounding)
SHAPE_TOLERANCE = 1e-9
#: points per great-circle arc between two consecutive vertices of a spherical polyline
ARC_POINTS = 33


@dataclass(frozen=True)
class Sphere:
    """The sphere every point of a spherical drawing lies on: centre (3,) in {B}, radius (m)."""

    centre: Array
    radius: float


@dataclass(frozen=True)
class Drawn:
    """One configuration ready to draw: ``lines`` maps each polyline name to its vertices (3 x k,
    {B}, metres; arcs densified on a sphere), ``joints`` the polyline vertices (3 x n) split into
    ``fixed`` and ``moving`` ones, ``distance`` the distance to singularity (``singularity_distance``)."""

    lines: dict[str, Array]
    joints: dict[str, Array]
    distance: dict[str, float]
    #: per joint kind, each joint's shortest polyline segment to another joint (n,), m (inf: none)
    gaps: dict[str, Array] = field(default_factory=dict)


@dataclass(frozen=True)
class Scene:
    """Every configuration of one picture with what they share: ``parts`` (polyline name -> part),
    ``planar`` (all points in one plane z = const), ``sphere`` (or None), and the common axis
    box ``low``, ``high`` (3,) (a cube in 3-D, a square in the x-y plane for a planar scene)."""

    drawn: list[Drawn]
    parts: dict[str, str]
    planar: bool
    sphere: Sphere | None
    low: Array
    high: Array


def distance_text(distance: dict[str, float]) -> str:
    """'type II 0.012 · type I 0.31' (1/cond: 0 at a singularity), or '' without measures."""
    return " · ".join(f"{name} {value:.2g}" for name, value in distance.items())


def numbers_text(numbers: Sequence[int]) -> str:
    """Integers as runs: [0, 1, 2, 5, 7, 8] -> '0-2, 5, 7-8'."""
    runs: list[list[int]] = []
    for n in sorted(numbers):
        if runs and n == runs[-1][-1] + 1:
            runs[-1].append(n)
        else:
            runs.append([n])
    return ", ".join(f"{run[0]}-{run[-1]}" if len(run) > 1 else f"{run[0]}" for run in runs)


def labels_text(labels: Sequence[str]) -> str:
    """Panel labels as runs: ['mode 0', 'mode 1', 'mode 2', 'mode 5'] -> 'modes 0-2, 5' (entries
    '#k' of a batch: 'entries ...')."""
    if not labels:
        return ""
    many = len(labels) > 1
    kind = ("modes" if many else "mode") if labels[0].startswith("mode") else ("entries" if many else "entry")
    return f"{kind} {numbers_text([int(label.split()[-1].lstrip('#')) for label in labels])}"


def rest_text(m: LoadedMechanism, rest: list[Configuration], labels: list[str], distances: bool = True) -> str:
    """The line of a grid that names the modes it leaves out (``labels``: 'mode 12', ...), those
    of them near a type II singularity, and how to draw them."""
    text = f"not drawn: {labels_text(labels)}"
    if distances:
        near = [label for label, c in zip(labels, rest, strict=True) if is_near_singular(singularity_distance(m, c))]
        if near:
            text += f" (near-singular: {labels_text(near).split(' ', 1)[1]})"
    every = len(rest) + MAX_PANELS
    return f"{text}; all_modes=True (parakin plot --all-modes) draws all {every}, mode=k (--mode K) one"


def inputs_text(m: LoadedMechanism, actuated: ArrayLike, digits: int = 4) -> str:
    """The actuated inputs (n_a,) by name with their units, revolute ones in degrees:
    ``theta1 = -74.46°, theta2 = ...`` or ``rho1 = 14.99 m, ...`` (``digits`` significant digits of a
    length, ``digits - 2`` decimals of an angle)."""
    values = np.asarray(actuated, dtype=float).reshape(-1)
    parts = []
    for variable, value in zip(m.manifest.actuated, values, strict=True):
        if variable.revolute:
            parts.append(f"{variable.name}\u00a0=\u00a0{math.degrees(value) + 0.0:.{max(digits - 2, 1)}f}°")
        else:
            unit = f"\u00a0{variable.unit}" if variable.unit else ""
            parts.append(f"{variable.name}\u00a0=\u00a0{value + 0.0:.{digits}g}{unit}")
    return ", ".join(parts)  # no line break inside "name = value unit" (non-breaking spaces)


def axes_note(scene: Scene) -> str:
    """What the axes measure: metres, or the unit sphere of a spherical drawing of radius 1."""
    names = "x, y" if scene.planar else "x, y, z"
    if scene.sphere is not None and abs(scene.sphere.radius - 1.0) < 1e-9:
        return f"axes {names} on the unit sphere (radius 1)"
    return f"axes {names} in m"


def great_circle(a: Array, b: Array, sphere: Sphere, count: int = ARC_POINTS) -> Array:
    """The shorter great-circle arc from a to b (3,) on ``sphere``: 3 x count points; the chord
    when a and b are (nearly) antipodal or equal, where the arc is not unique or not needed."""
    u, v = (a - sphere.centre) / sphere.radius, (b - sphere.centre) / sphere.radius
    angle = float(np.arccos(np.clip(u @ v, -1.0, 1.0)))
    t = np.linspace(0.0, 1.0, count)
    if angle < 1e-9 or angle > np.pi - 1e-6:
        return a[:, None] + (b - a)[:, None] * t
    arc = (np.sin((1 - t) * angle)[:, None] * u + np.sin(t * angle)[:, None] * v) / np.sin(angle)
    arc /= np.linalg.norm(arc, axis=-1, keepdims=True)  # on the sphere to rounding
    return (sphere.centre + sphere.radius * arc).T


def sphere_of(m: LoadedMechanism, configurations: list[Configuration], cloud: Array) -> Sphere | None:
    """The sphere a spherical drawing lies on (pose kind ``rotation``, every point of ``cloud``
    (3, k) at one distance from the platform's fixed centre), or None: drawn with great-circle
    arcs on it (here and in the viewer)."""
    if m.manifest.pose_kind != "rotation" or cloud.shape[1] < 3:
        return None
    centre = np.asarray(configurations[0].pose)[:3, 3]
    if any(not np.allclose(np.asarray(c.pose)[:3, 3], centre, atol=1e-12) for c in configurations):
        return None
    radii = np.linalg.norm(cloud - centre[:, None], axis=0)
    radius = float(radii.mean())
    if radius <= 0 or np.ptp(radii) > SHAPE_TOLERANCE * max(radius, 1.0):
        return None
    return Sphere(centre, radius)


def compose_scene(m: LoadedMechanism, configurations: list[Configuration], distances: bool = True) -> Scene:
    """Evaluate the drawing kernel at every configuration and decide how to draw them together."""
    drawing = m.capabilities.drawing
    assert drawing is not None
    points = [m.drawing(c) for c in configurations]
    fixed, parts = set(drawing.fixed), drawing.parts
    used = {(s, i) for vertices in drawing.polylines.values() for s, i in vertices}
    cloud = np.concatenate([np.stack([p[s][:, i] for s, i in sorted(used)], -1) for p in points], -1)
    scale = max(1.0, float(np.abs(cloud).max(initial=0.0)))
    planar = bool(np.ptp(cloud[2]) <= SHAPE_TOLERANCE * scale) if cloud.size else False
    sphere = None if planar else sphere_of(m, configurations, cloud)
    drawn = []
    for config, p in zip(configurations, points, strict=True):
        lines = {}
        gap = dict.fromkeys(used, math.inf)  # each joint's shortest segment to another joint
        for name, vertices in drawing.polylines.items():
            xyz = np.stack([p[s][:, i] for s, i in vertices], axis=-1)
            steps = np.linalg.norm(np.diff(xyz, axis=-1), axis=0)
            for k, step in enumerate(steps.tolist()):
                if step > SHAPE_TOLERANCE * scale:  # a segment, not a repeated point
                    for vertex in vertices[k : k + 2]:
                        gap[vertex] = min(gap[vertex], step)
            if sphere is not None and xyz.shape[1] > 1:
                arcs = [great_circle(xyz[:, k], xyz[:, k + 1], sphere) for k in range(xyz.shape[1] - 1)]
                xyz = np.concatenate([arcs[0]] + [arc[:, 1:] for arc in arcs[1:]], axis=-1)
            lines[name] = xyz
        joints = {
            kind: np.stack([p[s][:, i] for s, i in sorted(used) if (s in fixed) == (kind == "fixed")], -1)
            if any((s in fixed) == (kind == "fixed") for s, _ in used)
            else np.zeros((3, 0))
            for kind in ("fixed", "moving")
        }
        gaps = {
            kind: np.array([gap[v] for v in sorted(used) if (v[0] in fixed) == (kind == "fixed")]) for kind in joints
        }
        drawn.append(Drawn(lines, joints, singularity_distance(m, config) if distances else {}, gaps))
    if sphere is not None:
        low, high = sphere.centre - 1.05 * sphere.radius, sphere.centre + 1.05 * sphere.radius
    elif cloud.size:
        centre = (cloud.max(-1) + cloud.min(-1)) / 2
        half = max(float(np.ptp(cloud[:2] if planar else cloud, axis=-1).max()) / 2 * 1.08, 1e-9)
        low, high = centre - half, centre + half
    else:
        low, high = -np.ones(3), np.ones(3)
    return Scene(drawn, parts, planar, sphere, low, high)


# ---------------------------------------------------------- drawing a scene (matplotlib)
#: line style of each part: colour, line width, drawing order
PART_STYLE: dict[str, dict[str, Any]] = {
    "base": {"color": "#3b3b3b", "linewidth": 3.2, "zorder": 2},
    "leg": {"color": "#e66101", "linewidth": 1.8, "zorder": 3},
    "platform": {"color": "#1f5fa8", "linewidth": 2.6, "zorder": 4},
}
#: what each part is called in a legend
PART_LABEL = {"base": "base", "leg": "legs", "platform": "platform"}
#: joint markers: fixed (on the base) and moving; ``s`` (points^2) is the largest size, shrunk
#: where joints lie close on screen (``marker_size``)
JOINT_STYLE: dict[str, dict[str, Any]] = {
    "fixed": {"marker": "s", "s": 26, "c": "#111111", "edgecolors": "#111111"},
    "moving": {"marker": "o", "s": 20, "c": "white", "edgecolors": "#222222"},
}
JOINT_LABEL = {"fixed": "fixed joints", "moving": "moving joints"}
#: a joint marker's width is at most this share of the shortest segment between two joints on
#: screen, so that a small body (a delta's platform) is not hidden under its joints' markers
MARKER_SHARE = 0.35
#: the smallest marker width (points): joints closer on screen get none
MIN_MARKER = 1.5
#: the share of a 3-D panel's width that one side of its cube of limits spans on screen (at the
#: view and zoom ``decorate`` sets; measured on rendered panels)
CUBE_ON_SCREEN = 0.5


def _pyplot() -> Any:
    """matplotlib.pyplot on a non-interactive backend (Agg) unless inline in a notebook."""
    try:
        import matplotlib
    except ImportError as error:
        raise UnsupportedOperationError("plotting needs matplotlib: pip install 'parakin[plot]'") from error
    if matplotlib.get_backend().lower() not in ("agg", "module://matplotlib_inline.backend_inline"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def is_3d(ax: Any) -> bool:
    """Whether ``ax`` is matplotlib's 3-D Axes (2-D Axes have no z limits)."""
    return hasattr(ax, "set_zlim")


def check_axes(ax: Any, scene: Scene, name: str) -> None:
    """2-D axes draw only a planar scene: BadInputError naming the z extent otherwise."""
    if is_3d(ax) or scene.planar:
        return
    z = np.concatenate([xyz[2] for d in scene.drawn for xyz in d.lines.values()])
    raise BadInputError(
        f"the drawing of {name} spans {float(np.ptp(z)):.3g} m in z: it needs 3-D axes "
        "(figure.add_subplot(projection='3d'), or ax=None); 2-D axes draw planar drawings only"
    )


def _fill(ax: Any, xyz: np.ndarray, colour: Any) -> None:
    closed = xyz.shape[1] >= 4 and np.allclose(xyz[:, 0], xyz[:, -1])
    if not closed:
        return
    if is_3d(ax):
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        ax.add_collection3d(Poly3DCollection([xyz.T], facecolors=[colour], alpha=0.18, edgecolors="none"))
    else:
        ax.fill(xyz[0], xyz[1], color=colour, alpha=0.18, linewidth=0, zorder=1)


def draw_configuration(
    ax: Any, scene: Scene, index: int, colour: Any = None, label: str | None = None, base: bool = True
) -> None:
    """Configuration ``index`` of ``scene`` on ``ax`` (2-D: the x-y plane), one Line per polyline
    in manifest order; ``colour`` overrides the colour of the moving parts (modes overlaid),
    ``label`` goes on its first moving line (the legend by mode), ``base=False`` skips the base."""
    drawn = scene.drawn[index]
    three = is_3d(ax)
    labelled = False
    for name, xyz in drawn.lines.items():
        part = scene.parts[name]
        if part == "base" and not base:
            continue
        style = dict(PART_STYLE[part])
        if colour is not None and part != "base":
            style["color"] = colour
        if part == "leg" and colour is not None:
            style["linewidth"] = 1.2
        legend = label if label and not labelled and part != "base" else None
        labelled = labelled or legend is not None
        ax.plot(*(xyz if three else xyz[:2]), label=legend, solid_capstyle="round", **style)
        if part == "platform" and scene.sphere is None:
            _fill(ax, xyz, style["color"])
    if three:  # the parts in their drawing order (base, legs, platform, joints), not by depth
        ax.computed_zorder = False
    for kind, xyz in drawn.joints.items():
        if not xyz.shape[1] or (kind == "fixed" and not base):
            continue
        options: dict[str, Any] = {"depthshade": False} if three else {}
        sizes = marker_sizes(ax, scene, drawn.gaps.get(kind, np.full(xyz.shape[1], np.inf)), JOINT_STYLE[kind]["s"])
        style = {**JOINT_STYLE[kind], "s": sizes}
        widths = np.minimum(0.8, 0.25 * np.sqrt(sizes))
        ax.scatter(*(xyz if three else xyz[:2]), zorder=5, linewidths=widths, **style, **options)


def points_per_metre(ax: Any, scene: Scene) -> float:
    """About how many points (1/72 in) one metre of the scene spans on ``ax`` (its limits the
    scene's box: a square in 2-D, a cube seen at ``decorate``'s view in 3-D)."""
    box = ax.get_position()
    inches = min(box.width * ax.figure.get_figwidth(), box.height * ax.figure.get_figheight())
    three = is_3d(ax)
    span = float(np.max((scene.high - scene.low)[: 3 if three else 2]))
    return inches * 72 * (CUBE_ON_SCREEN if three else 1.0) / max(span, 1e-300)


def marker_sizes(ax: Any, scene: Scene, gaps: Array, largest: float) -> Array:
    """Joint markers' areas (points^2) on ``ax``, one per joint: at most ``largest``, and no wider
    than ``MARKER_SHARE`` of the joint's shortest segment to another joint (``gaps``, m) at the
    panel's scale (``points_per_metre``; in 3-D before foreshortening), so that markers do not
    cover the bodies between close joints; 0 (no marker) where that is under ``MIN_MARKER``:
    joints too close to show apart (the body's lines show where they are)."""
    room = MARKER_SHARE * np.asarray(gaps, dtype=float) * points_per_metre(ax, scene)
    return np.where(room >= MIN_MARKER, np.minimum(largest, room**2), 0.0)


def _sphere_surface(ax: Any, scene: Scene) -> None:
    sphere = scene.sphere
    assert sphere is not None
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 49), np.linspace(0, np.pi, 25))
    x = sphere.centre[0] + sphere.radius * np.cos(u) * np.sin(v)
    y = sphere.centre[1] + sphere.radius * np.sin(u) * np.sin(v)
    z = sphere.centre[2] + sphere.radius * np.cos(v)
    ax.plot_surface(x, y, z, color="#9ecae1", alpha=0.10, linewidth=0, shade=False, zorder=0)
    ax.plot_wireframe(x, y, z, color="#6b8fb3", alpha=0.18, linewidth=0.4, rstride=4, cstride=4)
    ax.scatter(*sphere.centre, marker="+", s=30, c="#555555", depthshade=False)


def decorate(ax: Any, scene: Scene, small: bool = False) -> None:
    """Axis labels in metres, the scene's common limits, equal scales, and the sphere if any."""
    three = is_3d(ax)
    names = ("x", "y", "z") if three else ("x", "y")
    size = 6 if small else 9
    unit = "" if scene.sphere is not None and abs(scene.sphere.radius - 1.0) < 1e-9 else " [m]"
    for index, name in enumerate(names):
        # small multiples: a short name by each axis (the figure's title says the unit)
        label, pad = (name, -6 if three else 1) if small else (f"{name}{unit}", 4)
        getattr(ax, f"set_{name}label")(label, fontsize=size, labelpad=pad)
        getattr(ax, f"set_{name}lim")(scene.low[index], scene.high[index])
    ax.tick_params(labelsize=size - 1, pad=0 if small else 2)
    if small:
        from matplotlib.ticker import MaxNLocator

        for name in names:
            getattr(ax, f"{name}axis").set_major_locator(MaxNLocator(3))
    if three:
        ax.set_box_aspect((1, 1, 1), zoom=1.15 if small else 0.9)  # room for the z label
        ax.view_init(elev=22, azim=-58)
        if scene.sphere is not None:
            _sphere_surface(ax, scene)
    else:
        ax.set_aspect("equal")
        ax.grid(True, linewidth=0.3, alpha=0.5)


def part_handles(scene: Scene) -> list[Any]:
    """Legend entries for the parts and joint kinds this scene has."""
    from matplotlib.lines import Line2D

    present = set(scene.parts.values())
    handles: list[Any] = [
        Line2D([], [], color=PART_STYLE[p]["color"], linewidth=PART_STYLE[p]["linewidth"], label=PART_LABEL[p])
        for p in PARTS
        if p in present
    ]
    for kind in ("fixed", "moving"):
        if any(d.joints[kind].shape[1] for d in scene.drawn):
            style = JOINT_STYLE[kind]
            handles.append(
                Line2D(
                    [],
                    [],
                    linestyle="",
                    marker=style["marker"],
                    markersize=5,
                    markerfacecolor=style["c"],
                    markeredgecolor=style["edgecolors"],
                    label=JOINT_LABEL[kind],
                )  # fmt: skip
            )
    return handles


def wrap(text: str, inches: float, fontsize: float = 10) -> str:
    """``text`` broken into lines that fit ``inches`` of figure width at ``fontsize`` points."""
    width = max(20, int(inches * 140 / fontsize))
    return "\n".join(textwrap.fill(line, width) for line in text.split("\n"))


def new_axes(plt: Any, scene: Scene, size: float = 6.4) -> tuple[Any, Any]:
    """A figure with one axes: 2-D for a planar scene, 3-D otherwise."""
    figure = plt.figure(figsize=(size, size + 0.5), layout="constrained")
    ax = figure.add_subplot() if scene.planar else figure.add_subplot(projection="3d")
    return figure, ax


def grid(
    plt: Any, scene: Scene, titles: list[str], suptitle: str, many: bool = False, near: Sequence[bool] = ()
) -> tuple[Any, np.ndarray]:
    """Small multiples: one panel per configuration of ``scene``, titled ``titles[k]`` (in
    ``NEAR_COLOUR`` where ``near[k]``), common limits, one legend of parts for the figure; ``many``
    (a picture of more than ``MAX_PANELS`` modes) gets larger panels. Returns the figure and the
    panels (in order)."""
    count = len(scene.drawn)
    cols = math.ceil(math.sqrt(count))
    rows = math.ceil(count / cols)
    panel = MANY_PANEL if many else 2.7 if count > 4 else 3.6
    figure = plt.figure(figsize=(cols * panel, rows * panel + 1.1), layout="constrained")
    figure.get_layout_engine().set(
        h_pad=0.15, w_pad=0.05, hspace=0.02
    )  # room between a row's ticks and the titles below
    axes = []
    for k in range(rows * cols):
        ax = figure.add_subplot(rows, cols, k + 1, **({} if scene.planar else {"projection": "3d"}))
        if k >= count:
            ax.set_axis_off()
            continue
        draw_configuration(ax, scene, k)
        decorate(ax, scene, small=True)
        warn = k < len(near) and near[k]
        ax.set_title(titles[k], fontsize=8, pad=4, color=NEAR_COLOUR if warn else "black")
        axes.append(ax)
    figure.suptitle(wrap(suptitle, cols * panel), fontsize=10)
    handles = part_handles(scene)
    figure.legend(handles=handles, loc="outside lower center", ncol=len(handles), fontsize=8, frameon=False)
    return figure, np.array(axes, dtype=object)


# ---------------------------------------------------------- animation along an actuated path
#: amplitude of the default loop (``actuated_loop``): radians for a revolute input, a fraction of
#: the input's value for a prismatic one
LOOP_ANGLE, LOOP_FRACTION = 0.12, 0.04
#: most substeps a frame is split into where Newton does not converge in one step
MAX_SUBSTEPS = 16


@dataclass(frozen=True)
class Animation:
    """A tracked path: ``configurations`` (actuated (N, n_a), passive (N, n_p), pose (N, 4, 4)),
    ``distance`` (name -> (N,) distance to singularity, 1/cond as ``singularity_distance``) and the
    matplotlib ``animation`` (None when nothing was drawn)."""

    configurations: Configuration
    distance: dict[str, Array]
    animation: Any = None

    def __len__(self) -> int:
        return int(np.asarray(self.configurations.actuated).shape[0])


def actuated_path(m: LoadedMechanism, value: ArrayLike, name: str = "actuated_path") -> Array:
    """Validated inputs (N, n_a), N >= 2, finite, every one inside the actuators' ranges: a path
    that leaves them is refused naming the frame and the actuator (BadInputError)."""
    try:
        path = np.array(value, dtype=float)
    except (TypeError, ValueError) as error:
        raise BadInputError(f"{name} must be numbers (N, {len(m.actuated_names)}): {error}") from error
    if path.ndim != 2 or path.shape[1] != len(m.actuated_names) or path.shape[0] < 2:
        raise BadInputError(
            f"{name} must have shape (N >= 2, {len(m.actuated_names)}) (one row per frame: "
            f"{', '.join(m.actuated_names)}), got {path.shape}"
        )
    if not np.isfinite(path).all():
        raise BadInputError(f"{name} has a non-finite value at frame {int(np.argwhere(~np.isfinite(path))[0, 0])}")
    low, high = m.actuated_bounds
    outside = (path < low) | (path > high)
    if outside.any():
        frame, k = (int(i) for i in np.argwhere(outside)[0])
        raise BadInputError(
            f"{name} leaves the workspace at frame {frame}: {m.actuated_names[k]} = {path[frame, k]:.6g} is "
            f"outside its range [{low[k]:.6g}, {high[k]:.6g}]"
        )
    return path


def actuated_line(m: LoadedMechanism, start: ArrayLike, end: ArrayLike, frames: int) -> Array:
    """Inputs evenly spaced on the straight line between two inputs: a path for ``animate``.

    Parameters
    ----------
    m : Mechanism
        The mechanism (its actuators' ranges bound the path).
    start, end : array_like, shape (n_a,)
        The first and last input (metres for prismatic, radians for revolute actuators).
    frames : int
        The number of inputs, at least 2.

    Returns
    -------
    ndarray, shape (frames, n_a)
        The inputs, ``start`` first and ``end`` last.

    Raises
    ------
    BadInputError
        ``frames`` below 2, or an input outside its actuator's range (naming the frame).

    Examples
    --------
    >>> import parakin
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> actuated_line(m, [1.5, 1.6], [1.7, 1.4], 3).round(2).tolist()
    [[1.5, 1.6], [1.6, 1.5], [1.7, 1.4]]
    """
    if isinstance(frames, bool) or not isinstance(frames, int | np.integer) or frames < 2:
        raise BadInputError(f"frames must be an integer >= 2, got {frames!r}")
    t = np.linspace(0.0, 1.0, int(frames))[:, None]
    a, b = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    return actuated_path(m, a + t * (b - a))


def actuated_loop(m: LoadedMechanism, start: ArrayLike, frames: int, scale: float = 1.0) -> Array:
    """A closed loop of inputs through ``start``: the default path of ``parakin plot --animate``.

    Input i moves as a_i + scale * amplitude_i * (sin(2 pi t + phi_i) - sin(phi_i)), t in [0, 1],
    phi_i = 2 pi i / n_a: every input moves, out of phase, and the last frame is the first (a GIF
    that loops). The amplitude is ``LOOP_ANGLE`` (rad) for a revolute input and
    ``LOOP_FRACTION * |a_i|`` for a prismatic one.

    Parameters
    ----------
    m : Mechanism
        The mechanism (its actuators' ranges bound the loop).
    start : array_like, shape (n_a,)
        The input the loop starts and ends at (m, rad).
    frames : int
        The number of inputs, at least 2.
    scale : float
        A factor on the amplitudes (smaller loops stay clear of singularities).

    Returns
    -------
    ndarray, shape (frames, n_a)
        The inputs, first and last equal to ``start``.

    Raises
    ------
    BadInputError
        ``frames`` below 2, or an input outside its actuator's range (naming the frame).

    Examples
    --------
    >>> import numpy as np, parakin
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> loop = actuated_loop(m, m.home_actuated, 24)
    >>> loop.shape, bool(np.allclose(loop[0], loop[-1]))
    ((24, 2), True)
    """
    if isinstance(frames, bool) or not isinstance(frames, int | np.integer) or frames < 2:
        raise BadInputError(f"frames must be an integer >= 2, got {frames!r}")
    a = np.asarray(start, dtype=float)
    revolute = np.array([v.revolute for v in m.manifest.actuated])
    amplitude = scale * np.where(revolute, LOOP_ANGLE, LOOP_FRACTION * np.abs(a))
    t = np.linspace(0.0, 1.0, int(frames))[:, None]
    phase = 2 * np.pi * np.arange(a.size) / max(a.size, 1)
    return actuated_path(m, a + amplitude * (np.sin(2 * np.pi * t + phase) - np.sin(phase)))


def _at_frame(error: ParakinError, frame: int, frames: int, theta: Array) -> ParakinError:
    """The same kind of error, its message prefixed with the frame and its inputs."""
    values = np.array2string(theta, precision=6, separator=", ")
    message = f"animation frame {frame} of {frames} (actuated {values}): {error}"
    if isinstance(error, AssemblyModeChangeError):
        return AssemblyModeChangeError(message, frame, error.change)
    if isinstance(error, ConvergenceError):
        return ConvergenceError(message, error.residual)
    if isinstance(error, SelfMotionError):
        return SelfMotionError(message, error.solution_set)
    try:
        return type(error)(message)
    except TypeError:  # an error class with other constructor arguments: keep it as it is
        return error


def _step(tracker: Any, previous: Array, theta: Array) -> tuple[Array, Array]:
    """One frame of tracking: the tracker's solve, or, where Newton does not converge in one step,
    the same segment in 2, 4, ... ``MAX_SUBSTEPS`` substeps (each still checked for a mode change;
    a failed solve leaves the tracker at its previous solution)."""
    substeps = 1
    while True:
        try:
            for t in np.linspace(0.0, 1.0, substeps + 1)[1:]:
                q, pose = tracker.solve(previous + t * (theta - previous))
            return q, pose
        except ConvergenceError:
            if substeps >= MAX_SUBSTEPS:
                raise
            tracker.solve(previous)  # back to the frame's start (a solve at the inputs it came from)
            substeps *= 2


def track(m: LoadedMechanism, path: ArrayLike, start: Configuration | None = None) -> Configuration:
    """The configurations along a path of inputs, in one assembly mode.

    The runtime's tracker follows the mode from ``start``, so the assembly mode stays the start's
    (never a silent jump); a serial chain (no passive joints) is solved in closed form per frame.

    Parameters
    ----------
    m : Mechanism
        The mechanism.
    path : array_like, shape (N, n_a)
        The inputs, N >= 2 (m, rad), e.g. ``actuated_line`` or ``actuated_loop``.
    start : Configuration, optional
        A solved configuration at ``path[0]`` (e.g. ``modes.mode(k)``); default the forward pose
        nearest the home (``m.forward_pose``).

    Returns
    -------
    Configuration
        actuated (N, n_a), passive (N, n_p) and pose ^B_P T (N, 4, 4) in {B}, metres.

    Raises
    ------
    AssemblyModeChangeError
        Where the path crosses a type II singularity (or the branch ends); every error names
        the frame.
    ConvergenceError, SingularConfigurationError
        Where Newton fails.
    UnreachablePoseError
        Where passive joints leave their limits.
    BadInputError
        Where an input leaves its range.

    Examples
    --------
    >>> import parakin
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> tracked = track(m, actuated_loop(m, m.home_actuated, 12))
    >>> tracked.pose.shape
    (12, 4, 4)
    """
    theta = actuated_path(m, path)
    frames = theta.shape[0]
    if start is None:  # at the home inputs, the home's own mode (Newton from it: no all-modes solve)
        at_home = np.allclose(theta[0], m.home_actuated, rtol=0, atol=1e-12)
        start = m.forward_pose(theta[0], guess=m.home_passive) if at_home else m.forward_pose(theta[0])
    if not isinstance(start, Configuration) or np.asarray(start.actuated).shape != theta[0].shape:
        raise BadInputError("start must be one solved Configuration (e.g. modes.mode(k)) at the path's first input")
    if not np.allclose(start.actuated, theta[0], rtol=0, atol=1e-9):
        raise BadInputError(
            f"start is at actuated {np.asarray(start.actuated)}, the path begins at {theta[0]}: they must agree"
        )
    if not m.passive_names:
        forward = m.forward_pose(theta)
        return Configuration(theta, np.asarray(forward.passive), np.asarray(forward.pose))
    tracker = m.tracker(start, strict=True)
    passive = np.empty((frames, len(m.passive_names)))
    poses = np.empty((frames, 4, 4))
    passive[0], poses[0] = np.asarray(start.passive), np.asarray(start.pose)
    limited = bool(m.within_limits(passive[0]))
    for k in range(1, frames):
        try:
            q, pose = _step(tracker, theta[k - 1], theta[k])
        except ParakinError as error:
            raise _at_frame(error, k, frames, theta[k]) from error
        passive[k], poses[k] = q, pose
        if limited and not m.within_limits(passive[k]):
            raise UnreachablePoseError(
                f"animation frame {k} of {frames} (actuated {theta[k]}): the tracked configuration leaves "
                "the passive joint limits (the path leaves the workspace)"
            )
    return Configuration(theta, passive, poses)


# ---------------------------------------------------------- plot and animate
#: the default grid draws at most this many modes, the first ones, and names the others in its
#: title; ``all_modes=True`` (``parakin plot --all-modes``) draws every one
MAX_PANELS = 12
#: a panel's size (inches) in a grid of more than ``MAX_PANELS`` modes
MANY_PANEL = 3.4
#: the colour of a panel's title near a type II singularity (``is_near_singular``)
NEAR_COLOUR = "#b2182b"
#: the explanation of the distance measures under a figure
DISTANCE_NOTE = "type I / type II: 1/cond of the serial / closure Jacobian (1 far from, 0 at a singularity)"


def _states(state: Configuration | AssemblyModes) -> tuple[list[Configuration], list[str]]:
    if isinstance(state, AssemblyModes):
        if np.ndim(state.count):
            raise BadInputError(
                f"plot draws the modes of one input; these AssemblyModes hold a batch {np.shape(state.count)}"
            )
        # modes numbered as AssemblyModes.mode(k) numbers them: 0 .. count - 1, not by slot
        return list(state), [f"mode {n}" for n in range(len(state))]
    if not isinstance(state, Configuration):
        raise BadInputError(f"state must be a Configuration or AssemblyModes, got {type(state).__name__}")
    actuated = np.asarray(state.actuated)
    if actuated.ndim > 1:  # a batch: one drawing per entry
        passive, pose = np.asarray(state.passive), np.asarray(state.pose)
        count = actuated.shape[0]
        return [Configuration(actuated[k], passive[k], pose[k]) for k in range(count)], [f"#{k}" for k in range(count)]
    return [state], [""]


def _pick(configurations: list[Configuration], labels: list[str], mode: object) -> int:
    count = len(configurations)
    if isinstance(mode, bool | np.bool_) or not isinstance(mode, int | np.integer):
        raise NoSuchModeError(f"mode must be an integer in [0, {count}), got {type(mode).__name__} {mode!r}")
    if not 0 <= mode < count:
        valid = f"indexed 0 to {count - 1}" if count else "none to draw"
        raise NoSuchModeError(f"no mode {mode}: there are {count} modes ({valid})")
    return int(mode)


def plot(
    m: LoadedMechanism,
    state: Configuration | AssemblyModes,
    path: str | None = None,
    ax: Any = None,
    title: str | None = None,
    *,
    mode: int | None = None,
    all_modes: bool = False,
    distances: bool = True,
) -> Any:
    """Draw the mechanism (``m.plot``, ``parakin plot``) and write a PNG when asked.

    Without ``mode`` or ``all_modes``, given ``ax`` gets every configuration overlaid (coloured by
    mode, a legend by mode number), and ``ax=None`` gets one drawing for a single Configuration
    and the grid otherwise: the first ``MAX_PANELS`` (12) modes, larger panels where there are
    more, the others named in the figure's title (those near a type II singularity too);
    ``all_modes=True`` draws every one. A grid's panels share their limits and view; each is
    titled with its mode number and distances to singularity, in red and marked
    "near-singular" where type II is below ``parakin.singularity.NEAR_SINGULAR`` (0.02). Lengths
    are metres in {B}; a planar drawing is drawn in the x-y plane, a spherical one on its sphere
    with great-circle arcs.

    Parameters
    ----------
    m : Mechanism
        The mechanism (it needs a drawing kernel: ``m.capabilities.drawing``).
    state : Configuration or AssemblyModes
        One configuration, a batch (one drawing per entry, labelled #k), or the assembly modes of
        one input (numbered 0 .. count - 1 as ``modes.mode(k)``).
    path : str, optional
        Where to write a PNG.
    ax : matplotlib Axes, optional
        3-D axes, or 2-D axes for a planar drawing.
    title : str, optional
        The heading (default: the mechanism's title).
    mode : int, optional
        Draw mode (or entry) ``mode`` alone.
    all_modes : bool
        Draw every mode as a grid of small multiples, each titled "mode k", however many (the
        default grid draws the first ``MAX_PANELS``).
    distances : bool
        Show each drawing's distance to singularity (type I and type II) in its title.

    Returns
    -------
    Axes or ndarray of Axes
        The axes drawn on; for a grid a 1-D array, entry k the panel of mode k (k below
        ``MAX_PANELS`` in the default grid).

    Raises
    ------
    UnsupportedOperationError
        The mechanism has no drawing kernel, or matplotlib is missing.
    BadInputError
        Both ``mode`` and ``all_modes``, ``all_modes`` with ``ax``, or axes of the wrong kind.
    NoSuchModeError
        ``mode`` is not a mode of ``state``, or there is no mode to draw.

    Examples
    --------
    >>> import parakin
    >>> m = parakin.load("planar_3rpr", backend="numpy")
    >>> panels = plot(m, m.forward_pose_all(m.home_actuated), all_modes=True)
    >>> [ax.get_title().split("\\n")[0] for ax in panels]
    ['mode 0', 'mode 1', 'mode 2', 'mode 3', 'mode 4', 'mode 5']
    """
    drawing = m.capabilities.drawing
    if drawing is None:
        raise UnsupportedOperationError(f"{m.name} has no drawing kernel: plot is not available")
    if mode is not None and all_modes:
        raise BadInputError("pass mode=k (one mode) or all_modes=True (the grid), not both")
    configurations, labels = _states(state)
    if mode is not None:
        k = _pick(configurations, labels, mode)
        configurations, labels = [configurations[k]], [labels[k] or f"mode {k}"]
    several = isinstance(state, AssemblyModes) or len(configurations) > 1
    as_grid = all_modes or (ax is None and mode is None and several)
    if as_grid and ax is not None:
        raise BadInputError("all_modes draws a grid on a figure of its own: leave ax None (or pass mode=k)")
    if as_grid and not configurations:
        raise NoSuchModeError("no mode to draw: there are 0 modes (count 0)")
    rest: list[Configuration] = []  # modes the default grid leaves out (named in its title)
    labels_rest: list[str] = []
    if as_grid and not all_modes and len(configurations) > MAX_PANELS:
        rest, labels_rest = configurations[MAX_PANELS:], labels[MAX_PANELS:]
        configurations, labels = configurations[:MAX_PANELS], labels[:MAX_PANELS]
    plt = _pyplot()
    picture = compose_scene(m, configurations, distances=distances) if configurations else None
    heading = title or m.manifest.title
    if as_grid:
        assert picture is not None
        near = [is_near_singular(d.distance) for d in picture.drawn]
        titles = [
            "\n".join(t for t in (label or f"#{k}", distance_text(d.distance), "near-singular" * flagged) if t)
            for k, (label, d, flagged) in enumerate(zip(labels, picture.drawn, near, strict=True))
        ]
        note = f"; {DISTANCE_NOTE}" if distances else ""
        what = "assembly modes" if isinstance(state, AssemblyModes) else "configurations"
        at = inputs_text(m, configurations[0].actuated)
        drawn = f"; the first {len(configurations)} drawn" if rest else ""  # the others named below
        lines = [heading, f"{len(configurations) + len(rest)} {what} at {at}{drawn}", f"{axes_note(picture)}{note}"]
        if any(near):
            lines.append(
                f"red titles: near a type II singularity (type II below {NEAR_SINGULAR:g}: the actuators barely "
                "hold the platform): "
                + labels_text([label for label, flagged in zip(labels, near, strict=True) if flagged])
            )
        if rest:
            lines.append(rest_text(m, rest, labels_rest, distances))
        figure, axes = grid(
            plt, picture, titles, "\n".join(lines), many=bool(rest) or len(configurations) > MAX_PANELS, near=near
        )
        if path is not None:
            figure.savefig(path, dpi=110)
            plt.close(figure)
        return axes
    figure = None
    if ax is None:
        assert picture is not None
        figure, ax = new_axes(plt, picture)
    if picture is not None:
        check_axes(ax, picture, m.name)
        overlay = len(configurations) > 1
        colours = (
            plt.cm.tab10(np.linspace(0, 1, 10)) if len(configurations) <= 10 else plt.cm.tab20(np.linspace(0, 1, 20))
        )
        for k, label in enumerate(labels):
            colour = colours[k % len(colours)] if overlay else None
            draw_configuration(ax, picture, k, colour=colour, label=label if overlay else None, base=k == 0)
        decorate(ax, picture)
        if overlay:
            ax.legend(loc="upper left", fontsize=7, ncol=1 + len(labels) // 12, title="assembly modes")
        else:
            ax.legend(handles=part_handles(picture), loc="upper left", fontsize=7)
            details = " · ".join(t for t in (labels[0], distance_text(picture.drawn[0].distance)) if t)
            heading = f"{heading}\n{details}" if details else heading
    ax.set_title(wrap(heading, ax.figure.get_figwidth(), 9), fontsize=9)
    if path is not None:
        (figure or ax.figure).savefig(path, dpi=120)
    if figure is not None and path is not None:
        plt.close(figure)
    return ax


def animate(
    m: LoadedMechanism,
    actuated_path: ArrayLike,
    path: str | None = None,
    start: Configuration | None = None,
    fps: int = 12,
    title: str | None = None,
    dpi: int = 100,
) -> Animation:
    """Animate the mechanism along a path of inputs (``parakin plot NAME --animate OUT.gif``).

    The forward pose is tracked from ``start`` by the runtime's tracker (``track``), never
    re-solved from scratch, so the assembly mode does not jump. Every frame has the same limits
    and shows its inputs (by name, revolute ones in degrees) and its distance to singularity.

    Parameters
    ----------
    m : Mechanism
        The mechanism (it needs a drawing kernel).
    actuated_path : array_like, shape (N, n_a)
        The inputs, N >= 2 (m, rad): ``actuated_line``, ``actuated_loop`` or your own.
    path : str, optional
        Where to write the GIF (matplotlib's PillowWriter).
    start : Configuration, optional
        A solved configuration at the first input (e.g. ``modes.mode(k)``); default the mode
        nearest the home.
    fps : int
        Frames per second, 1 to 100.
    title : str, optional
        The heading (default: the mechanism's title).
    dpi : int
        Resolution of the GIF (6 x 6.5 in: 600 x 650 pixels at 100).

    Returns
    -------
    Animation
        The tracked configurations, their distances to singularity and the matplotlib animation.

    Raises
    ------
    UnsupportedOperationError
        The mechanism has no drawing kernel.
    BadInputError
        ``fps`` out of range, or an input outside its range (naming the frame).
    AssemblyModeChangeError, ConvergenceError, SingularConfigurationError
        The path crosses a singularity or leaves the workspace (naming the frame, as ``track``).

    Examples
    --------
    >>> import parakin
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> done = animate(m, actuated_loop(m, m.home_actuated, 6), "five_bar.gif")
    >>> len(done), sorted(done.distance)
    (6, ['type I', 'type II'])
    """
    from matplotlib.animation import FuncAnimation, PillowWriter

    if m.capabilities.drawing is None:
        raise UnsupportedOperationError(f"{m.name} has no drawing kernel: animate is not available")
    if isinstance(fps, bool) or not isinstance(fps, int | np.integer) or not 0 < fps <= 100:
        raise BadInputError(f"fps (frames per second) must be an integer in [1, 100], got {fps!r}")
    tracked = track(m, actuated_path, start)
    frames = int(np.asarray(tracked.actuated).shape[0])
    configurations = [Configuration(tracked.actuated[k], tracked.passive[k], tracked.pose[k]) for k in range(frames)]
    picture = compose_scene(m, configurations)
    names = sorted({name for d in picture.drawn for name in d.distance})
    distance = {name: np.array([d.distance.get(name, np.nan) for d in picture.drawn]) for name in names}
    plt = _pyplot()
    figure, ax = new_axes(plt, picture, size=6.0)
    heading = title or m.manifest.title

    def frame(k: int) -> list[Any]:
        ax.cla()
        draw_configuration(ax, picture, k)
        decorate(ax, picture)
        ax.legend(handles=part_handles(picture), loc="upper left", fontsize=6)
        values = inputs_text(m, tracked.actuated[k], digits=3)
        details = " · ".join(t for t in (f"frame {k}/{frames - 1}", distance_text(picture.drawn[k].distance)) if t)
        ax.set_title(wrap(f"{heading}\n{values}\n{details}", figure.get_figwidth(), 8), fontsize=8)
        return []

    animation = FuncAnimation(figure, frame, frames=frames, interval=1000.0 / fps, blit=False)
    if path is not None:
        animation.save(path, writer=PillowWriter(fps=int(fps)), dpi=dpi)
        plt.close(figure)
    return Animation(tracked, distance, animation)


def figure_html(figure: Any, alt: str, width: int | None = None, dpi: int = 100) -> str:
    """A matplotlib figure as one self-contained HTML image (PNG inlined as base64), for a page
    built from code (the documentation's tutorials) or any HTML output; the figure is closed.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure, e.g. ``m.plot(modes, all_modes=True)[0].figure``.
    alt : str
        The image's text alternative: what the figure shows.
    width : int, optional
        Display width in CSS pixels (default: the PNG's own).
    dpi : int
        Resolution of the PNG.

    Returns
    -------
    str
        ``<img alt="..." src="data:image/png;base64,...">``.

    Raises
    ------
    UnsupportedOperationError
        matplotlib is not installed.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> figure, ax = plt.subplots()
    >>> figure_html(figure, "an empty plot").startswith('<img alt="an empty plot"')
    True
    """
    import base64
    import html
    import io

    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=dpi)
    _pyplot().close(figure)
    encoded = base64.b64encode(buffer.getvalue()).decode("ascii")
    size = f' width="{int(width)}"' if width else ""
    return f'<img alt="{html.escape(alt)}"{size} src="data:image/png;base64,{encoded}">'


__all__ = ["Animation", "actuated_line", "actuated_loop", "animate", "figure_html", "plot", "track"]
