"""Drawings of any mechanism from its generated drawing kernel (matplotlib, optional extra 'plot').

The kernel returns named point sets (3 x n, in {B}, metres) for a configuration; the manifest
lists the polylines through them (legs, base and platform outlines). ``plot`` draws one
configuration or every mode of an ``AssemblyModes`` in 3-D, with labelled axes in metres.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from parakin.errors import UnsupportedOperationError
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
        return configurations, [f"mode {k}" for k in indices]
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
    write a PNG to ``path`` when given. Returns the matplotlib axes."""
    drawing = m.capabilities.drawing
    if drawing is None:
        raise UnsupportedOperationError(f"{m.name} has no drawing kernel: plot is not available")
    plt = _pyplot()
    figure = None
    if ax is None:
        figure = plt.figure(figsize=(7, 7))
        ax = figure.add_subplot(projection="3d")
    colours = plt.cm.tab10(np.linspace(0, 1, 10))
    configurations, labels = _states(state)
    everything: list[Array] = []
    for number, (config, label) in enumerate(zip(configurations, labels, strict=True)):
        points = m.drawing(config)
        colour = colours[number % 10]
        for line_number, vertices in enumerate(drawing.polylines.values()):
            xyz = np.stack([points[s][:, i] for s, i in vertices], axis=-1)
            everything.append(xyz)
            legend = f"{label}" if line_number == 0 and label else None
            ax.plot(*xyz, color=colour, marker="o", markersize=3, linewidth=1.5, label=legend)
    for axis, name in zip(("x", "y", "z"), ("x", "y", "z"), strict=True):
        getattr(ax, f"set_{axis}label")(f"{name} [m]")
    if everything:
        cloud = np.concatenate(everything, axis=-1)
        centre, half = cloud.mean(-1), max(float(np.ptp(cloud, axis=-1).max()) / 2, 1e-9)
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
        ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_title(title or m.manifest.title, fontsize=9)
    if any(labels):
        ax.legend(loc="upper left", fontsize=8)
    if path is not None:
        (figure or ax.figure).savefig(path, dpi=120)
    if figure is not None and path is not None:
        plt.close(figure)
    return ax


__all__ = ["plot"]
