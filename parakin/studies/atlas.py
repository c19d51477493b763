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

if TYPE_CHECKING:
    import xarray

LENGTH_AXES = ("x", "y", "z")


ANGLE_AXES = ("alpha", "beta", "gamma", "phi")
#: hatches of the flagged regions, one per status code drawn
HATCHES = ("//", "\\\\", "xx", "..", "++")


def _label(name: str) -> str:
    if name in LENGTH_AXES:
        return f"{name} [m]"
    return f"{name} [rad]" if name in ANGLE_AXES else name


def plot_sweep(dataset: xarray.Dataset, quantity: str, path: str | None = None, ax: Any = None) -> Any:
    """Draw ``dataset[quantity]`` (see the module docstring); write a PNG to ``path`` when given.
    Returns the matplotlib axes."""
    if quantity not in dataset.data_vars:
        raise BadInputError(f"{quantity!r} is not in the sweep; it has {sorted(map(str, dataset.data_vars))}")
    data = dataset[quantity].load()
    flags = _flags(dataset, quantity)
    plt = _pyplot()
    dims = [str(d) for d in data.dims]
    title = f"{dataset.attrs.get('mechanism', '')}: {quantity}"
    figure = None
    if len(dims) == 3 and data.dtype == bool:
        if ax is None:
            figure = plt.figure(figsize=(6, 5))
            ax = figure.add_subplot(projection="3d")
        grids = np.meshgrid(*(data[d].values for d in dims), indexing="ij")
        inside = data.values
        ax.scatter(*(g[inside] for g in grids), s=2, alpha=0.4)
        ax.set_xlabel(_label(dims[0]))
        ax.set_ylabel(_label(dims[1]))
        ax.set_zlabel(_label(dims[2]))
    elif len(dims) == 2:
        if ax is None:
            figure, ax = plt.subplots(figsize=(6, 5))
        x, y = data[dims[0]].values, data[dims[1]].values
        values = data.values.T.astype(float)  # rows: second axis
        if data.dtype == bool:
            ax.contourf(x, y, values, levels=[-0.5, 0.5, 1.5], colors=["white", "tab:blue"], alpha=0.6)
            ax.contour(x, y, values, levels=[0.5], colors="tab:blue", linewidths=1.0)
        elif "flag_values" in data.attrs:  # a status: one colour per named code
            codes = [int(c) for c in data.attrs["flag_values"]]
            mesh = ax.pcolormesh(x, y, values, shading="nearest", cmap="tab10", vmin=-0.5, vmax=9.5)
            bar = figure_of(ax).colorbar(mesh, ax=ax, ticks=codes, label=quantity)
            bar.ax.set_yticklabels(str(data.attrs["flag_meanings"]).split())
        elif quantity in ("modes", "branches"):
            counts = np.unique(values[np.isfinite(values)])
            mesh = ax.pcolormesh(x, y, np.ma.masked_invalid(values), shading="nearest", cmap="viridis")
            figure_of(ax).colorbar(mesh, ax=ax, ticks=counts, label=quantity)
        else:
            mesh = ax.pcolormesh(x, y, np.ma.masked_invalid(values), shading="nearest", cmap="magma")
            figure_of(ax).colorbar(mesh, ax=ax, label=quantity)
            if quantity.endswith("distance") and np.isfinite(values).any():
                ax.contour(x, y, np.nan_to_num(values, nan=1.0), levels=[0.02], colors="cyan", linewidths=1.0)
            if np.isnan(values).any():
                ax.contourf(x, y, np.isnan(values).astype(float), levels=[0.5, 1.5], colors=["0.85"], alpha=0.8)
        for (meaning, mask), hatch in zip(flags, HATCHES, strict=False):
            # pcolor (a PolyCollection) carries a hatch; cells outside the flag are masked out
            cells = np.ma.masked_where(~mask.T, np.ones(mask.T.shape))
            ax.pcolor(
                x,
                y,
                cells,
                shading="nearest",
                cmap=_flat("0.85"),
                hatch=hatch,
                edgecolor="0.35",
                lw=0,
                gid=f"flag {meaning}",
            )
        ax.set_xlabel(_label(dims[0]))
        ax.set_ylabel(_label(dims[1]))
    elif len(dims) == 1:
        if ax is None:
            figure, ax = plt.subplots(figsize=(6, 4))
        positions = data[dims[0]].values
        ax.plot(positions, data.values.astype(float))
        for (meaning, mask), hatch in zip(flags, HATCHES, strict=False):
            ax.fill_between(
                positions, 0, 1, where=mask, step="mid", transform=ax.get_xaxis_transform(),
                facecolor="0.85", hatch=hatch, edgecolor="0.35", lw=0, gid=f"flag {meaning}",
            )  # fmt: skip
        ax.set_xlabel(_label(dims[0]))
        ax.set_ylabel(quantity)
    else:
        raise BadInputError(f"{quantity!r} has {len(dims)} axes: plot a slice (dataset.isel(...)) of 1, 2 or 3")
    if flags and len(dims) < 3:
        from matplotlib.patches import Patch

        handles = [
            Patch(facecolor="0.85", edgecolor="0.35", hatch=hatch, label=f"{quantity} missing: {meaning}")
            for (meaning, _), hatch in zip(flags, HATCHES, strict=False)
        ]
        ax.legend(handles=handles, loc="upper right", fontsize="small")
    ax.set_title(title)
    if path is not None:
        (figure or figure_of(ax)).savefig(path, dpi=120, bbox_inches="tight")
    return ax


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
