"""Plots of sweeps (``parakin.sweep``): the maps a designer reads, from the Dataset alone.

``plot_sweep(dataset, quantity)`` picks the drawing from the quantity's dimensions:
- one swept axis: a curve;
- two: a map (colour = the quantity). Reachability is drawn as a filled region; a singularity
  distance as a colour map with its zero set (and unreachable poses) marked; a mode count with one
  colour per count; a parameter grid is a design-space map;
- a quantity with a status variable (``<quantity>_status``, CF ``flag_values`` / ``flag_meanings``,
  0: defined) is missing (NaN) where the status is not 0: each such code is drawn as its own hatched
  region (a span on a curve) named in the legend, never as a value; a status variable itself is
  drawn as a map of its named codes;
- three pose axes of a boolean quantity (a reachable workspace): a 3-D point cloud of the true
  points.
Pose axes are labelled with their units (m for x, y, z; rad for the angles).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from parakin.errors import BadInputError
from parakin.interfaces.plot import _pyplot
from parakin.singularity import NEAR_SINGULAR

if TYPE_CHECKING:
    import xarray

LENGTH_AXES = ("x", "y", "z")


ANGLE_AXES = ("alpha", "beta", "gamma", "phi")
#: hatches of the flagged regions, one per status code drawn
HATCHES = ("//", "\\\\", "xx", "..", "++")


#: the grey of values that are not defined (an unreachable pose), and of flagged regions under their hatch
MISSING_GREY = "0.85"
#: pose-space quantities: a value is missing exactly where the pose is unreachable
POSE_SPACE = ("reachable", "branches", "type_i_distance", "type_ii_distance")


def _label(name: str, units: str | None = None) -> str:
    """An axis or colour-bar label: the name and its unit (``units`` as the sweep wrote it on the
    coordinate; without one, metres for x, y, z and radians for the pose angles)."""
    if units is None:
        units = "m" if name in LENGTH_AXES else "rad" if name in ANGLE_AXES else ""
    return f"{name} [{units}]" if units else name


def _axis_label(data: Any, dim: str) -> str:
    return _label(dim, data[dim].attrs.get("units"))


def plot_sweep(dataset: xarray.Dataset, quantity: str, path: str | None = None, ax: Any = None) -> Any:
    """Draw one quantity of a sweep: a curve, a map or a 3-D point cloud (module docstring).

    Every axis is labelled with its unit, and every region and line drawn has a legend entry
    below the axes: reachable and unreachable, values that are not defined (grey), the
    near-singularity contour, and each status code's hatched region.

    Parameters
    ----------
    dataset : xarray.Dataset
        The result of ``parakin.sweep`` (or a slice of it, ``dataset.isel(...)``).
    quantity : str
        One of its data variables.
    path : str, optional
        Write a PNG there (120 dpi).
    ax : matplotlib.axes.Axes, optional
        Draw into these axes (a 3-D one for a point cloud).

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    BadInputError
        ``quantity`` is not in the sweep, or it has more than three axes (or three that are not
        a boolean workspace).
    UnsupportedOperationError
        matplotlib is not installed.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from parakin import sweep
    >>> from parakin.studies.atlas import plot_sweep
    >>> axes = {"x": np.linspace(-0.5, 0.5, 21), "y": np.linspace(-0.4, 0.6, 21)}
    >>> ds = sweep("five_bar", ["type_ii_distance"], axes, backend="numpy", progress=False)
    >>> ax = plot_sweep(ds, "type_ii_distance")
    >>> ax.get_xlabel(), [text.get_text() for text in ax.get_legend().get_texts()]
    ('x [m]', ['type_ii_distance = 0.02 (near a singularity)', 'unreachable pose (no valid inverse branch)'])
    """
    if quantity not in dataset.data_vars:
        raise BadInputError(f"{quantity!r} is not in the sweep; it has {sorted(map(str, dataset.data_vars))}")
    data = dataset[quantity].load()
    flags = _flags(dataset, quantity)
    plt = _pyplot()
    dims = [str(d) for d in data.dims]
    title = f"{dataset.attrs.get('mechanism', '')}: {quantity}"
    value_label = _label(quantity, data.attrs.get("units", ""))
    figure = None
    handles: list[Any] = []
    if len(dims) == 3 and data.dtype == bool:
        if ax is None:
            figure = plt.figure(figsize=(6, 5))
            ax = figure.add_subplot(projection="3d")
        grids = np.meshgrid(*(data[d].values for d in dims), indexing="ij")
        inside = data.values
        ax.scatter(*(g[inside] for g in grids), s=2, alpha=0.4, label=f"{quantity}: true")
        ax.set_xlabel(_axis_label(data, dims[0]))
        ax.set_ylabel(_axis_label(data, dims[1]))
        ax.set_zlabel(_axis_label(data, dims[2]))
        ax.legend(loc="upper right", fontsize="small")
    elif len(dims) == 2:
        if ax is None:
            figure, ax = plt.subplots(figsize=(6, 5))
        handles = _map(ax, data, quantity, value_label, flags)
        ax.set_xlabel(_axis_label(data, dims[0]))
        ax.set_ylabel(_axis_label(data, dims[1]))
    elif len(dims) == 1:
        if ax is None:
            figure, ax = plt.subplots(figsize=(6, 4))
        positions = data[dims[0]].values
        (line,) = ax.plot(positions, data.values.astype(float), label=value_label)
        handles.append(line)
        for (meaning, mask), hatch in zip(flags, HATCHES, strict=False):
            ax.fill_between(
                positions, 0, 1, where=mask, step="mid", transform=ax.get_xaxis_transform(),
                facecolor=MISSING_GREY, hatch=hatch, edgecolor="0.35", lw=0, gid=f"flag {meaning}",
            )  # fmt: skip
        ax.set_xlabel(_axis_label(data, dims[0]))
        ax.set_ylabel(value_label)
    else:
        raise BadInputError(f"{quantity!r} has {len(dims)} axes: plot a slice (dataset.isel(...)) of 1, 2 or 3")
    if len(dims) < 3:
        from matplotlib.patches import Patch

        handles += [
            Patch(facecolor=MISSING_GREY, edgecolor="0.35", hatch=hatch, label=f"{quantity} missing: {meaning}")
            for (meaning, _), hatch in zip(flags, HATCHES, strict=False)
        ]
        if handles:  # below the axes: a legend never hides the map
            ax.legend(
                handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=1, fontsize="small",
                frameon=False,
            )  # fmt: skip
    ax.set_title(title)
    if path is not None:
        (figure or figure_of(ax)).savefig(path, dpi=120, bbox_inches="tight")
    return ax


def _map(ax: Any, data: Any, quantity: str, value_label: str, flags: list[tuple[str, np.ndarray]]) -> list[Any]:
    """A two-axis map of ``data`` on ``ax``; returns the legend handles of what it drew."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    dims = [str(d) for d in data.dims]
    x, y = data[dims[0]].values, data[dims[1]].values
    values = data.values.T.astype(float)  # rows: second axis
    handles: list[Any] = []
    if data.dtype == bool:
        ax.contourf(x, y, values, levels=[-0.5, 0.5, 1.5], colors=["white", "tab:blue"], alpha=0.6)
        ax.contour(x, y, values, levels=[0.5], colors="tab:blue", linewidths=1.0)
        handles += [
            Patch(facecolor="tab:blue", alpha=0.6, edgecolor="tab:blue", label=f"{quantity}: true"),
            Patch(facecolor="white", edgecolor="tab:blue", label=f"{quantity}: false"),
        ]
        return handles
    if "flag_values" in data.attrs:  # a status: one colour per named code
        codes = [int(c) for c in data.attrs["flag_values"]]
        mesh = ax.pcolormesh(x, y, values, shading="nearest", cmap="tab10", vmin=-0.5, vmax=9.5)
        bar = figure_of(ax).colorbar(mesh, ax=ax, ticks=codes, label=quantity)
        bar.ax.set_yticklabels(str(data.attrs["flag_meanings"]).split())
        return handles
    if quantity in ("modes", "branches"):
        counts = np.unique(values[np.isfinite(values)])
        mesh = ax.pcolormesh(x, y, np.ma.masked_invalid(values), shading="nearest", cmap="viridis")
        figure_of(ax).colorbar(mesh, ax=ax, ticks=counts, label=value_label)
    else:
        mesh = ax.pcolormesh(x, y, np.ma.masked_invalid(values), shading="nearest", cmap="magma")
        figure_of(ax).colorbar(mesh, ax=ax, label=value_label)
        if quantity.endswith("distance") and np.isfinite(values).any():
            ax.contour(x, y, np.nan_to_num(values, nan=1.0), levels=[NEAR_SINGULAR], colors="cyan", linewidths=1.0)
            handles.append(
                Line2D([], [], color="cyan", lw=1.0, label=f"{quantity} = {NEAR_SINGULAR:g} (near a singularity)")
            )
    # missing values not explained by a status flag: grey, cell by cell (no interpolated edge, so
    # no white hole inside an unreachable island)
    flagged = np.zeros(values.shape, dtype=bool)
    for _, mask in flags:
        flagged |= mask.T
    plain = np.isnan(values) & ~flagged
    if plain.any():
        cells = np.ma.masked_where(~plain, np.ones(values.shape))
        ax.pcolormesh(x, y, cells, shading="nearest", cmap=_flat(MISSING_GREY), gid="missing")
        meaning = "unreachable pose (no valid inverse branch)" if quantity in POSE_SPACE else f"{quantity} not defined"
        handles.append(Patch(facecolor=MISSING_GREY, edgecolor="0.35", label=meaning))
    for (meaning, mask), hatch in zip(flags, HATCHES, strict=False):
        # pcolor (a PolyCollection) carries a hatch; cells outside the flag are masked out
        cells = np.ma.masked_where(~mask.T, np.ones(mask.T.shape))
        ax.pcolor(
            x, y, cells, shading="nearest", cmap=_flat(MISSING_GREY), hatch=hatch, edgecolor="0.35", lw=0,
            gid=f"flag {meaning}",
        )  # fmt: skip
    return handles


def _flags(dataset: xarray.Dataset, quantity: str) -> list[tuple[str, np.ndarray]]:
    """(meaning, mask) of each code of ``quantity``'s status variable that is set somewhere; code
    0 means defined and is no flag."""
    status = dataset.data_vars.get(f"{quantity}_status")
    if status is None or "flag_values" not in status.attrs:
        return []
    values = np.asarray(status.load().values)
    codes = [int(c) for c in status.attrs["flag_values"]]
    meanings = str(status.attrs.get("flag_meanings", "")).split()
    return [
        (meaning, values == code)
        for code, meaning in zip(codes, meanings, strict=False)
        if code and (values == code).any()
    ]


def _flat(colour: str) -> Any:
    """A colour map of one colour (a flagged region's fill under its hatch)."""
    from matplotlib.colors import ListedColormap

    return ListedColormap([colour])


def figure_of(ax: Any) -> Any:
    return ax.get_figure()


__all__ = ["plot_sweep"]
