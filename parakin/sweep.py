"""Design studies: named quantities over grids of poses, actuated inputs and parameters, for any
mechanism, from its manifest alone, evaluated chunk by chunk on dask.

A sweep is a regular grid: ``axes`` maps each swept name to its 1-D values, in order; a name is a
pose coordinate of the mechanism's pose kind (``POSE_COORDINATES``; metres and radians, Z-Y-X
Euler angles as ``parakin.pose``), an actuated variable or a parameter (a parameter whose name is
also a pose coordinate or actuated variable, like the SPM's ``beta``, is written ``param_beta``). Pose coordinates that are
not swept take ``fixed`` values (default: the home pose). Quantities (``QUANTITIES``):

pose space (one configuration per inverse branch; ``branch`` picks one, default the first valid):
- ``reachable``: some inverse branch is valid (validity measures, joint limits, actuator ranges);
- ``branches``: how many are;
- ``type_i_distance``: 1/cond of the matrix that maps actuated rates to the twist's inverse (B of
  A twist = B rates, or the worst leg Jacobian): 0 at a serial (type I) singularity;
- ``type_ii_distance``: 1/cond of the closure Jacobian d closure / d passive: 0 at a parallel
  (type II) singularity (both NaN where the pose is unreachable);
actuated space:
- ``modes``: the number of real assembly modes (``forward_pose_all``; -1 where the elimination
  degenerates);
parameter space:
- ``architecture``: the manifest's architecture measure(s) (0: singular at every pose);
- ``workspace_volume``: the volume (product of the axis units) of the reachable part of the pose
  grid ``workspace``, per design.

Results are an ``xarray.Dataset`` with one dimension per axis. The grid is cut into chunks of
whole slabs of the first axis (about ``chunk`` points each): memory is bounded by the chunk, not
the grid. ``scheduler``: None (dask's local threads), 'synchronous', or a ``dask.distributed``
scheduler address (the same call then runs on a cluster). With ``store`` (a zarr folder) every
finished chunk is written at once and recorded, so an interrupted sweep resumes where it stopped.
"""

from __future__ import annotations

import functools
import hashlib
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from parakin.errors import BadInputError, UnsupportedOperationError
from parakin.validation import as_array

if TYPE_CHECKING:
    import xarray

    from parakin.mechanism import Mechanism

#: pose coordinates of each pose kind, in ``parakin.pose`` order
POSE_COORDINATES = {
    "transform": ("x", "y", "z", "alpha", "beta", "gamma"),
    "rotation": ("alpha", "beta", "gamma"),
    "planar": ("x", "y", "phi"),
    "translation": ("x", "y", "z"),
}
POSE_QUANTITIES = ("reachable", "branches", "type_i_distance", "type_ii_distance")
QUANTITIES = (*POSE_QUANTITIES, "modes", "architecture", "workspace_volume")


def _needs_dask() -> tuple[Any, Any]:
    try:
        import dask.array as da
        import xarray as xr
    except ImportError as error:  # pragma: no cover - the sweep extra is part of dev
        raise UnsupportedOperationError("sweeps need dask and xarray: pip install 'parakin[sweep]'") from error
    return da, xr


@functools.lru_cache(maxsize=64)
def _mechanism(source: str, backend: str, parameters: tuple[tuple[str, float], ...]) -> Mechanism:
    """One loaded mechanism per design and process (workers load their own)."""
    import warnings

    import parakin

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        values: dict[str, Any] = dict(parameters)
        return parakin.load(source, backend=backend, **values)


def _pose_from(kind: str, values: dict[str, np.ndarray]) -> np.ndarray:
    from parakin.pose import pose_from_xyz_euler

    n = next(iter(values.values())).shape[0]
    zero = np.zeros(n)
    if kind == "planar":
        six = [values["x"], values["y"], zero, values["phi"], zero, zero]
    else:
        six = [values.get(name, zero) for name in POSE_COORDINATES["transform"]]
    return pose_from_xyz_euler(np.stack(six, axis=-1))


def _inverse_condition(matrix: np.ndarray) -> np.ndarray:
    """sigma_min / sigma_max per matrix (..., r, c); NaN where not finite."""
    finite = np.isfinite(matrix).all(axis=(-2, -1))
    values = np.linalg.svd(np.where(finite[..., None, None], matrix, 0.0), compute_uv=False)
    ratio = values[..., -1] / np.where(values[..., 0] > 0, values[..., 0], 1.0)
    return np.where(finite, ratio, np.nan)


def _pose_quantities(m: Mechanism, coordinates: dict[str, np.ndarray], wanted: Sequence[str], branch: int | None):
    from parakin.results import Configuration

    pose = _pose_from(m.manifest.pose_kind, coordinates)
    inverse = m.inverse_pose(pose, strict=False)
    low = np.array([v.limits[0] for v in m.manifest.actuated])
    high = np.array([v.limits[1] for v in m.manifest.actuated])
    with np.errstate(invalid="ignore"):
        ranged = ((inverse.actuated >= low) & (inverse.actuated <= high)).all(-1)
    valid = inverse.valid & ranged
    out: dict[str, np.ndarray] = {"reachable": np.asarray(valid.any(-1)), "branches": np.asarray(valid.sum(-1))}
    if not {"type_i_distance", "type_ii_distance"} & set(wanted):
        return out
    chosen = np.full(valid.shape[0], branch) if branch is not None else np.argmax(valid, axis=-1)
    reachable = np.take_along_axis(valid, chosen[:, None], axis=-1)[:, 0]
    rows = np.arange(valid.shape[0])
    theta = np.where(reachable[:, None], inverse.actuated[rows, chosen], m.home_actuated)
    q = np.where(reachable[:, None], inverse.passive[rows, chosen], m.home_passive)
    state = Configuration(theta, q, pose)
    if "type_ii_distance" in wanted:
        if not m.passive_names:
            raise UnsupportedOperationError(f"{m.name} has no passive joints: no type II singularity to measure")
        jacobian = m.backend.call("loop_closure", theta, q, m.params)["jacobian"]
        out["type_ii_distance"] = np.where(reachable, _inverse_condition(jacobian), np.nan)
    if "type_i_distance" in wanted:
        if m.capabilities.rates is not None:
            measure = _inverse_condition(m.rate_jacobians(state)["b"])
        elif m.capabilities.legs:
            measure = np.min([_inverse_condition(j) for j in m.leg_jacobians(state).values()], axis=0)
        else:
            raise UnsupportedOperationError(f"{m.name} has no rate model: type_i_distance is not available")
        out["type_i_distance"] = np.where(reachable, measure, np.nan)
    return out


def _grid_volume(workspace: Mapping[str, np.ndarray]) -> float:
    """Volume of one cell of a regular grid (product of the spacings)."""
    return float(np.prod([(v[-1] - v[0]) / (len(v) - 1) if len(v) > 1 else 1.0 for v in workspace.values()]))


def _evaluate(spec: dict[str, Any], coordinates: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Every requested quantity at the flat points ``coordinates`` (name -> (n,) values)."""
    n = next(iter(coordinates.values())).shape[0]
    parameter_axes = [axis for axis in coordinates if axis in spec["parameter_axes"]]
    parameter_names = [spec["parameter_axes"][axis] for axis in parameter_axes]
    designs = np.stack([coordinates[a] for a in parameter_axes], axis=-1) if parameter_axes else np.zeros((n, 0))
    unique, group = np.unique(designs, axis=0, return_inverse=True)
    group = group.reshape(-1)
    results: dict[str, np.ndarray] = {}
    for d, design in enumerate(unique):
        members = np.flatnonzero(group == d)
        parameters = {**spec["parameters"], **dict(zip(parameter_names, map(float, design), strict=True))}
        m = _mechanism(spec["source"], spec["backend"], tuple(sorted(parameters.items())))
        local = {name: values[members] for name, values in coordinates.items()}
        part = _evaluate_design(m, spec, local, members.size)
        for key, value in part.items():
            results.setdefault(key, np.full(n, np.nan))[members] = value
    return results


def _evaluate_design(m: Mechanism, spec: dict[str, Any], coordinates: dict[str, np.ndarray], n: int):
    wanted = spec["quantities"]
    out: dict[str, np.ndarray] = {}
    pose_wanted = [q for q in wanted if q in POSE_QUANTITIES]
    if pose_wanted:
        pose_values = {**spec["fixed"], **{k: v for k, v in coordinates.items() if k in spec["pose_names"]}}
        pose_values = {k: np.broadcast_to(v, (n,)) for k, v in pose_values.items()}
        computed = _pose_quantities(m, pose_values, pose_wanted, spec["branch"])
        out.update({q: computed[q] for q in pose_wanted})
    if "modes" in wanted:
        theta = np.stack(
            [np.broadcast_to(coordinates.get(a, m.home_actuated[k]), (n,)) for k, a in enumerate(m.actuated_names)],
            axis=-1,
        )
        counts = m.count_modes(theta)
        out["modes"] = np.where(counts["status"] == 0, counts["count"], -1)
    if "architecture" in wanted:
        for name, value in m.architecture().items():
            out[f"architecture_{name}"] = np.full(n, value)
    if "workspace_volume" in wanted:
        grid = spec["workspace"]
        mesh = np.meshgrid(*grid.values(), indexing="ij")
        points = {k: v.ravel() for k, v in zip(grid, mesh, strict=True)}
        pose_values = {**spec["fixed"], **points}
        total = mesh[0].size
        reachable = 0
        for start in range(0, total, spec["chunk"]):
            part = {k: np.broadcast_to(v, (total,))[start : start + spec["chunk"]] for k, v in pose_values.items()}
            reachable += int(_pose_quantities(m, part, ["reachable"], spec["branch"])["reachable"].sum())
        out["workspace_volume"] = np.full(n, reachable * _grid_volume(grid))
    return out


def _block(spec: dict[str, Any], axes: dict[str, np.ndarray], names: list[str], location) -> np.ndarray:
    """One chunk of the grid: (slab..., len(names)) float values."""
    slices = [np.asarray(values)[start:stop] for (start, stop), values in zip(location, axes.values(), strict=True)]
    mesh = np.meshgrid(*slices, indexing="ij")
    shape = mesh[0].shape
    flat = {name: grid.ravel() for name, grid in zip(axes, mesh, strict=True)}
    values = _evaluate(spec, flat)
    return np.stack([np.asarray(values[name], dtype=float).reshape(shape) for name in names], axis=-1)


def _output_names(m: Mechanism, quantities: Sequence[str]) -> list[str]:
    names: list[str] = []
    for q in quantities:
        if q == "architecture":
            if m.capabilities.architecture is None:
                raise UnsupportedOperationError(f"{m.name} declares no architecture measure")
            names += [f"architecture_{name}" for name in m.capabilities.architecture.measures]
        else:
            names.append(q)
    return names


def sweep(
    mechanism: str | Path | Mechanism,
    quantities: Sequence[str],
    axes: Mapping[str, Any],
    *,
    fixed: Mapping[str, float] | None = None,
    workspace: Mapping[str, Any] | None = None,
    branch: int | None = None,
    chunk: int = 65_536,
    scheduler: str | None = None,
    store: str | Path | None = None,
    progress: bool = False,
    backend: str = "auto",
) -> xarray.Dataset:
    """Evaluate ``quantities`` over the grid ``axes`` (see the module docstring); returns a labelled
    ``xarray.Dataset`` (lazy, over the zarr ``store`` when one is given)."""
    from parakin.errors import ParakinError
    from parakin.mechanism import Mechanism as MechanismClass
    from parakin.pose import xyz_euler_from_pose
    from parakin.validation import integer_in_range

    da, xr = _needs_dask()
    m = mechanism if isinstance(mechanism, MechanismClass) else _mechanism(str(mechanism), backend, ())
    source = str(m.package.path)
    backend_name = m.backend.name
    if isinstance(quantities, str):
        quantities = [quantities]
    unknown = [q for q in quantities if q not in QUANTITIES]
    if unknown or not quantities:
        raise BadInputError(f"unknown quantities {unknown}; choose from {QUANTITIES}")
    chunk = integer_in_range(chunk, "chunk", 1, 10**9)
    if branch is not None:
        n_branches = len(m.capabilities.inverse.combinations) if m.capabilities.inverse else 0
        branch = integer_in_range(branch, "branch", 0, max(n_branches - 1, 0))
    kind = m.manifest.pose_kind
    pose_names = POSE_COORDINATES[kind]
    parameter_axes = {}
    for p in m.manifest.parameters:
        shadowed = p.name in pose_names or p.name in m.actuated_names
        parameter_axes[f"param_{p.name}" if shadowed else p.name] = p.name
    allowed = {*pose_names, *m.actuated_names, *parameter_axes}
    grid = {}
    for name, values in axes.items():
        if name not in allowed:
            raise BadInputError(
                f"axis {name!r} is not a pose coordinate {pose_names}, an actuated variable "
                f"{m.actuated_names} or a parameter {sorted(parameter_axes)}"
            )
        array = as_array(values, f"axis {name!r}", ())
        if array.ndim != 1 or array.size == 0:
            raise BadInputError(f"axis {name!r} must be a non-empty 1-D array, got shape {array.shape}")
        grid[name] = array
    if not grid:
        raise BadInputError("a sweep needs at least one axis")
    if any(q in POSE_QUANTITIES for q in quantities) and m.capabilities.inverse is None:
        raise UnsupportedOperationError(f"{m.name} has no closed-form inverse: pose-space quantities need one")
    if "modes" in quantities and m.capabilities.forward is None:
        raise UnsupportedOperationError(f"{m.name} has no forward elimination: 'modes' is not available")
    try:  # the home configuration's pose where it closes, else a closed configuration near it
        from parakin.sampling import sample_configurations

        solved = m.forward_pose(m.home_actuated, strict=False)
        if bool(solved.converged):
            home = xyz_euler_from_pose(solved.pose)
        else:
            near = sample_configurations(m, 16, seed=0)
            home = xyz_euler_from_pose(near.pose[0]) if near.pose.shape[0] else np.zeros(6)
    except ParakinError:
        home = np.zeros(6)
    home_values = dict(zip(POSE_COORDINATES["transform"], home, strict=True))
    if kind == "planar":
        home_values["phi"] = home_values["alpha"]
    fixed_values = {name: float(home_values[name]) for name in pose_names}
    for name, value in (fixed or {}).items():
        if name not in pose_names:
            raise BadInputError(f"fixed {name!r} is not a pose coordinate {pose_names}")
        fixed_values[name] = float(as_array(value, f"fixed {name!r}", ()))
    workspace_grid = {}
    if "workspace_volume" in quantities:
        if not workspace:
            raise BadInputError("workspace_volume needs workspace={coordinate: values} (the pose grid per design)")
        for name, values in workspace.items():
            if name not in pose_names:
                raise BadInputError(f"workspace axis {name!r} is not a pose coordinate {pose_names}")
            array = as_array(values, f"workspace {name!r}", ())
            steps = np.diff(array) if array.ndim == 1 else np.zeros(0)
            if array.ndim != 1 or array.size < 2 or not (steps > 0).all() or np.ptp(steps) > 1e-9 * abs(steps[0]):
                raise BadInputError(
                    f"workspace axis {name!r} must be evenly spaced ascending values (at least 2): its cells "
                    "give the volume"
                )
            workspace_grid[name] = array
    names = _output_names(m, quantities)
    spec = {
        "source": source,
        "backend": backend_name,
        "parameters": dict(m.parameters),
        "parameter_axes": parameter_axes,
        "pose_names": pose_names,
        "fixed": fixed_values,
        "quantities": list(quantities),
        "branch": branch,
        "workspace": workspace_grid,
        "chunk": chunk,
    }
    shape = tuple(v.size for v in grid.values())
    slab = int(np.prod(shape[1:], dtype=np.int64))
    rows = max(1, chunk // max(slab, 1))
    chunks = ((rows,) * (shape[0] // rows) + ((shape[0] % rows,) if shape[0] % rows else ()),) + tuple(
        (s,) for s in shape[1:]
    )
    template = da.zeros(shape, chunks=chunks, dtype=float)

    def compute_block(_: np.ndarray, block_info: dict | None = None) -> np.ndarray:
        assert block_info is not None
        return _block(spec, grid, names, block_info[0]["array-location"])

    values = template.map_blocks(compute_block, new_axis=len(shape), chunks=(*chunks, (len(names),)), dtype=float)
    dims = list(grid)
    data = {}
    for k, name in enumerate(names):
        array = values[..., k]
        if name == "reachable":
            array = array.astype(bool)
        elif name in ("branches", "modes"):
            array = array.astype(np.int32)
        data[name] = (dims, array)
    # everything that determines the values: a store of any other sweep is refused, not reused
    digest = hashlib.sha256()
    for name, values in [*grid.items(), *(("workspace " + k, v) for k, v in workspace_grid.items())]:
        digest.update(name.encode())
        digest.update(np.ascontiguousarray(values, dtype=float).tobytes())
    described = {k: v for k, v in spec.items() if k != "workspace"}
    fingerprint = json.dumps({**described, "grids": digest.hexdigest()}, sort_keys=True, default=str)
    attributes = {
        "mechanism": m.name,
        "pose_kind": kind,
        "fixed": json.dumps(fixed_values),
        "spec": fingerprint,
        "workspace": json.dumps({k: [float(v[0]), float(v[-1]), int(v.size)] for k, v in workspace_grid.items()}),
    }
    dataset = xr.Dataset(data, coords={name: values for name, values in grid.items()}, attrs=attributes)
    if store is None:
        return _compute(dataset, scheduler, progress)
    return _compute_into(dataset, Path(store), chunks[0], scheduler, progress, xr)


def _client(scheduler: str | None) -> Any:
    if scheduler is None or scheduler in ("threads", "synchronous", "processes"):
        return None
    from distributed import Client

    try:
        return Client(scheduler, timeout=30)
    except (OSError, ValueError, TimeoutError) as error:
        raise BadInputError(f"no dask scheduler at {scheduler!r}: {error}") from error


def _compute(dataset: xarray.Dataset, scheduler: str | None, progress: bool) -> xarray.Dataset:
    import contextlib

    from dask.diagnostics import ProgressBar

    client = _client(scheduler)
    local = scheduler if scheduler in ("threads", "synchronous", "processes") else None
    try:
        with ProgressBar() if progress and client is None else contextlib.nullcontext():
            return dataset.compute(scheduler=client or local)
    finally:
        if client is not None:
            client.close()


def _compute_into(
    dataset: xarray.Dataset, store: Path, rows: tuple[int, ...], scheduler: str | None, progress: bool, xr: Any
) -> xarray.Dataset:
    """Write the sweep chunk by chunk into a zarr store, skipping chunks a previous run finished
    (recorded in ``finished.json`` inside the store, replaced atomically after each write)."""
    import dask

    first = next(iter(dataset.dims))
    bounds = np.cumsum((0, *rows))
    record = store / "finished.json"
    if store.exists():
        saved = json.loads(record.read_text()) if record.exists() else {}
        if saved.get("spec") != dataset.attrs["spec"]:
            raise BadInputError(f"{store} holds another sweep; remove it or choose another store")
        finished = set(saved.get("chunks", []))
    else:
        dataset.to_zarr(str(store), compute=False, mode="w")
        finished = set()

    def save() -> None:
        scratch = record.with_suffix(".tmp")
        scratch.write_text(json.dumps({"spec": dataset.attrs["spec"], "chunks": sorted(finished)}))
        scratch.replace(record)

    save()
    pending = [k for k in range(len(rows)) if k not in finished]
    client = _client(scheduler)
    local = scheduler if scheduler in ("threads", "synchronous", "processes") else None
    workers = max(1, len(client.scheduler_info()["workers"])) if client is not None else 2
    try:
        for start in range(0, len(pending), workers):
            batch = pending[start : start + workers]
            parts = [dataset.isel({first: slice(int(bounds[k]), int(bounds[k + 1]))}) for k in batch]
            computed = dask.compute(*parts, scheduler=client or local)
            for k, part in zip(batch, computed, strict=True):
                region = {first: slice(int(bounds[k]), int(bounds[k + 1]))}
                part.drop_vars(list(part.coords)).to_zarr(str(store), region=region)
                finished.add(k)
            save()
            if progress:
                print(f"sweep: {len(finished)}/{len(rows)} chunks written to {store}", flush=True)
    finally:
        if client is not None:
            client.close()
    result = xr.open_zarr(str(store))
    result.attrs["chunks_computed"] = len(pending)  # this run's work (0: everything was done before)
    return result


__all__ = ["POSE_COORDINATES", "QUANTITIES", "sweep"]
