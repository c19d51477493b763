"""Drawings of any mechanism from its generated drawing kernel (matplotlib, optional extra 'plot').

The kernel returns named point sets (3 x n, in {B}, metres) for a configuration; the manifest
lists the polylines through them (legs, base and platform outlines). ``plot`` draws one
configuration or every mode of an ``AssemblyModes`` in 3-D, with labelled axes in metres; on
given 2-D axes it draws the x-y plane, which is exact only for a drawing that lies in one plane
z = const (a planar mechanism), so any other drawing on 2-D axes is refused.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from parakin.errors import BadInputError, UnsupportedOperationError
from parakin.results import Array, AssemblyModes, Configuration

if TYPE_CHECKING:
    from parakin.mechanism import Mechanism


def _pyplot() -> Any:
    try:
        import matplotlib
    except ImportError as error:
        raise UnsupportedOperationError("plotting needs matplotlib: pip install 'parakin[plot]'") from error
    if matplotlib.get_backend().lower() not in ("agg", "module://matplotlib_inline.backend_inline"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _states(state: Configuration | AssemblyModes) -> tuple[list[Configuration], list[str]]:
    if isinstance(state, AssemblyModes):
        indices = np.nonzero(np.asarray(state.valid))[0]
        configurations = [Configuration(state.actuated, state.passive[k], state.poses[k]) for k in indices]
        # modes numbered as AssemblyModes.mode(k) numbers them: 0 .. count - 1, not by slot
        return configurations, [f"mode {n}" for n in range(len(indices))]
    actuated = np.asarray(state.actuated)
    if actuated.ndim > 1:  # a batch: one drawing per entry
        passive, pose = np.asarray(state.passive), np.asarray(state.pose)
        count = actuated.shape[0]
        return [Configuration(actuated[k], passive[k], pose[k]) for k in range(count)], [f"#{k}" for k in range(count)]
    return [state], [""]


def plot(
    m: Mechanism,
    state: Configuration | AssemblyModes,
    path: str | None = None,
    ax: Any = None,
    title: str | None = None,
) -> Any:
    """Draw the mechanism in one configuration, a batch, or every valid mode of ``AssemblyModes``;
    write a PNG to ``path`` when given. ``ax``: axes to draw into, 3-D, or 2-D for a drawing that
    lies in one plane z = const (BadInputError for any other). Returns the matplotlib axes."""
    drawing = m.capabilities.drawing
    if drawing is None:
        raise UnsupportedOperationError(f"{m.name} has no drawing kernel: plot is not available")
    plt = _pyplot()
    configurations, labels = _states(state)
    lines: list[tuple[int, str | None, Array]] = []  # (configuration number, legend, 3 x n vertices)
    for number, (config, label) in enumerate(zip(configurations, labels, strict=True)):
        points = m.drawing(config)
        for line_number, vertices in enumerate(drawing.polylines.values()):
            legend = label if line_number == 0 and label else None
            lines.append((number, legend, np.stack([points[s][:, i] for s, i in vertices], axis=-1)))
    cloud = np.concatenate([xyz for _, _, xyz in lines], axis=-1) if lines else np.zeros((3, 0))
    figure = None
    if ax is None:
        figure = plt.figure(figsize=(7, 7))
        ax = figure.add_subplot(projection="3d")
    planar_axes = not hasattr(ax, "set_zlim")  # matplotlib's 2-D Axes (3-D ones are Axes3D)
    if planar_axes and cloud.size:
        height = float(np.ptp(cloud[2]))
        if height > 1e-9 * max(1.0, float(np.abs(cloud).max())):
            raise BadInputError(
                f"the drawing of {m.name} spans {height:.3g} m in z: it needs 3-D axes "
                "(figure.add_subplot(projection='3d'), or ax=None); 2-D axes draw planar drawings only"
            )
    colours = plt.cm.tab10(np.linspace(0, 1, 10))
    for number, legend, xyz in lines:
        shown = xyz[:2] if planar_axes else xyz
        ax.plot(*shown, color=colours[number % 10], marker="o", markersize=3, linewidth=1.5, label=legend)
    names = ("x", "y") if planar_axes else ("x", "y", "z")
    for name in names:
        getattr(ax, f"set_{name}label")(f"{name} [m]")
    if cloud.size:
        centre, half = cloud.mean(-1), max(float(np.ptp(cloud, axis=-1).max()) / 2, 1e-9)
        for index, name in enumerate(names):
            getattr(ax, f"set_{name}lim")(centre[index] - half, centre[index] + half)
    if planar_axes:
        ax.set_aspect("equal")
    ax.set_title(title or m.manifest.title, fontsize=9)
    if any(labels):
        ax.legend(loc="upper left", fontsize=8)
    if path is not None:
        (figure or ax.figure).savefig(path, dpi=120)
    if figure is not None and path is not None:
        plt.close(figure)
    return ax


__all__ = ["plot"]
