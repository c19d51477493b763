"""Design studies: named quantities over grids of poses, actuated inputs and parameters, for any
mechanism, from its manifest alone, evaluated chunk by chunk on dask.

A sweep is a regular grid: ``axes`` maps each swept name to its 1-D values, in order; a name is a
pose coordinate of the mechanism's pose kind (``POSE_COORDINATES``; metres and radians, Z-Y-X
Euler angles as ``parakin.pose``), an actuated variable or a parameter (a parameter whose name is
also a pose coordinate or actuated variable, like the SPM's ``beta``, is written ``param_beta``).
Every name that is not swept can be set in ``fixed`` (one finite real number each); unset, pose
coordinates take the home pose, actuated variables the home input and parameters the loaded
mechanism's values. A fixed value for a swept name, an unknown name, or a name that none of the
requested quantities reads is refused (BadInputError naming it), as is an axis that none reads.
Quantities (``QUANTITIES``):

pose space (one configuration per inverse branch; ``branch`` picks the one the distances are measured in,
default the home's, so that a sweep stays in the home's assembly mode):
- ``reachable``: some inverse branch is valid (validity measures, joint limits, actuator ranges);
- ``branches``: how many are;
- ``type_i_distance``: 1/cond of the matrix that maps actuated rates to the twist's inverse (B of
  A twist = B rates, or the worst leg Jacobian): 0 at a serial (type I) singularity;
- ``type_ii_distance``: 1/cond of the closure Jacobian d closure / d passive: 0 at a parallel
  (type II) singularity (both NaN where the pose is unreachable or the matrix not finite; the
  measures of ``parakin.singularity``, which ``parakin plot`` labels and the MJCF export warns by);
actuated space:
- ``modes``: the number of real assembly modes (``forward_pose_all``), NaN where it is not
  defined, with ``modes_status`` saying why (codes of the manifest's ``abi.input_status``, named in
  the variable's CF attributes ``flag_values`` / ``flag_meanings``: 0 'ok', 'degenerate' where the
  elimination degenerates, e.g. parallel joint axes); a missing count is never a number. An axis
  may leave an actuator's range (the manifest's limits, which every solver refuses): its points
  outside are missing with the code 'outside_range' (after the manifest's codes, declared where the
  grid leaves a range), the rest of the grid is computed; a fixed actuated value outside its range
  (every point missing) is refused;
parameter space:
- ``architecture``: the manifest's architecture measure(s) (0: singular at every pose);
- ``workspace_volume``: the volume (product of the axis units) of the reachable part of the pose
  grid ``workspace``, per design.

Results are an ``xarray.Dataset`` with one dimension per axis. The grid is cut into chunks of
whole slabs of the first axis (about ``chunk`` points each): memory is bounded by the chunk, not
the grid. ``scheduler``: None (dask's local threads), 'synchronous', or a ``dask.distributed``
scheduler address (the same call then runs on a cluster). ``progress``: a bar on stderr over the
grid's points, advanced as each chunk finishes: True always, False never, None (the
default) as ``parakin.log.progress`` decides: a sweep of at least ``parakin.log.LARGE_BATCH``
points (workspace points included) on a terminal; on a ``dask.distributed`` scheduler without a
store, the cluster's dashboard shows the tasks instead. With ``store`` (a zarr folder) every
finished chunk is written at once and recorded with the sha256 of each variable's values in it
(``finished.json``), so an interrupted sweep resumes where it stopped. Resuming verifies every
recorded chunk against its checksum and recomputes any that does not verify (a deleted or damaged
chunk file, a record that lists a chunk never written); the returned dataset verifies each chunk
again when it is read and raises BadInputError for one that changed since, never returning it.
A store killed before its first record resumes as an unfinished store of the same sweep.
One sweep writes a store at a time: it holds the store's lock (``.NAME.lock`` next to it, an
advisory ``flock`` that the system releases when the process ends, however it ends) from
before it touches the store until its last chunk is recorded. Another sweep started on the
store meanwhile, in any process or thread, is refused with StoreInUseError naming the store;
started after, it resumes the store.
"""

from __future__ import annotations

import collections
import contextlib
import functools
import hashlib
import itertools
import json
import os
import socket
import threading
import warnings
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from parakin.errors import ArchitectureSingularityWarning, BadInputError, StoreInUseError, UnsupportedOperationError
from parakin.log import progress as bar_over
from parakin.pose import POSE_KINDS, wrap_angle
from parakin.singularity import type_i_distance, type_ii_distance
from parakin.validation import as_array

if TYPE_CHECKING:
    import xarray

    from parakin.mechanism import Mechanism

#: pose coordinates of each pose kind, in ``parakin.pose`` order
POSE_COORDINATES = {kind: info.coordinates for kind, info in POSE_KINDS.items()}
#: a pose coordinate named otherwise than its x-y-z-Z-Y-X-Euler value: the planar turn phi about z
#: is the Euler alpha; every other coordinate of a kind is absent from the pose (zero)
EULER_NAME = {"phi": "alpha"}
#: the ``modes_status`` code of an actuated input outside its range (no solver takes it)
OUTSIDE_RANGE = "outside_range"
#: the sweep's store: its record of finished chunks (format 2: per chunk the sha256 of each variable)
RECORD, RECORD_FORMAT = "finished.json", 2
POSE_QUANTITIES = ("reachable", "branches", "type_i_distance", "type_ii_distance")
QUANTITIES = (*POSE_QUANTITIES, "modes", "architecture", "workspace_volume")
#: the stores this process is writing (resolved paths): threads of one process exclude each other
#: here, as file systems whose flock is emulated by POSIX record locks (NFS) do not between them
_WRITING: set[Path] = set()
_WRITING_GUARD = threading.Lock()
#: the progress bar of each sweep computing in memory in this process, by the sweep's token
_BARS: dict[str, Any] = {}
_BARS_GUARD = threading.Lock()
_SWEEP_IDS = itertools.count()


def _needs_dask() -> tuple[Any, Any]:
    try:
        import dask.array as da
        import xarray as xr
    except ImportError as error:  # pragma: no cover - the sweep extra is part of dev
        raise UnsupportedOperationError("sweeps need dask and xarray: pip install 'parakin[sweep]'") from error
    return da, xr


@functools.lru_cache(maxsize=64)
def _mechanism(source: str, backend: str, parameters: tuple[tuple[str, float], ...], limits: Limits = ()) -> Mechanism:
    """One loaded mechanism per design, joint limits and process (workers load their own)."""
    from parakin.loading import load

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ArchitectureSingularityWarning)
        values: dict[str, Any] = dict(parameters)
        return load(source, backend=backend, limits=dict(limits) or None, **values)


#: joint limits and actuated ranges as a hashable key: ((name, (low, high)), ...)
Limits = tuple[tuple[str, tuple[float, float]], ...]


def _limits_of(m: Mechanism) -> Limits:
    """The mechanism's passive joint limits and actuated ranges, overrides included: a worker
    loads the mechanism the caller passed, not the package's defaults."""
    return tuple(sorted((k, (float(lo), float(hi))) for k, (lo, hi) in {**m.limits, **m.actuated_ranges}.items()))


def _six_index(name: str) -> int:
    """Where the pose coordinate ``name`` stands in x, y, z, alpha, beta, gamma (``EULER_NAME``)."""
    return POSE_COORDINATES["transform"].index(EULER_NAME.get(name, name))


def _pose_from(kind: str, values: dict[str, np.ndarray]) -> np.ndarray:
    from parakin.pose import pose_from_xyz_euler

    n = next(iter(values.values())).shape[0]
    six = np.zeros((n, 6))
    for name in POSE_COORDINATES[kind]:
        six[:, _six_index(name)] = values[name]
    return pose_from_xyz_euler(six)


def _pose_quantities(
    m: Mechanism,
    coordinates: dict[str, np.ndarray],
    wanted: Sequence[str],
    branch: int | None,
    onto_reachable: bool = False,
):
    from parakin.results import Configuration

    pose = _pose_from(m.manifest.pose_kind, coordinates)
    inverse = m.inverse_pose(pose, strict=False, onto_reachable=onto_reachable)
    low, high = m.actuated_bounds
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
    state = Configuration(theta, q, inverse.pose)  # the pose reached (a lower-mobility reading)
    if "type_ii_distance" in wanted:
        measure = type_ii_distance(m, state)
        if measure is None:
            raise UnsupportedOperationError(f"{m.name} has no passive joints: no type II singularity to measure")
        out["type_ii_distance"] = np.where(reachable, measure, np.nan)
    if "type_i_distance" in wanted:
        measure = type_i_distance(m, state)
        if measure is None:
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
        limits = tuple((name, (low, high)) for name, low, high in spec["limits"])
        m = _mechanism(spec["source"], spec["backend"], tuple(sorted(parameters.items())), limits)
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
        pose_values = {**spec["fixed"], **coordinates}
        pose_values = {k: np.broadcast_to(v, (n,)) for k, v in pose_values.items() if k in spec["pose_names"]}
        computed = _pose_quantities(m, pose_values, pose_wanted, spec["branch"], spec["onto_reachable"])
        out.update({q: computed[q] for q in pose_wanted})
    if "modes" in wanted:
        theta = np.stack(
            [
                np.broadcast_to(coordinates.get(a, spec["fixed"].get(a, m.home_actuated[k])), (n,))
                for k, a in enumerate(m.actuated_names)
            ],
            axis=-1,
        )
        low, high = m.actuated_bounds
        inside = ((theta >= low) & (theta <= high)).all(-1)  # outside: no input of any solver
        counts = m.count_modes(theta[inside])
        defined = counts["status"] == m.manifest.abi.input_status.index("ok")
        modes = np.full(n, np.nan)
        status = np.zeros(n, dtype=np.int32)
        if not inside.all():  # only a grid that leaves a range declares (and can hold) the code
            status[~inside] = spec["status_names"].index(OUTSIDE_RANGE)
        modes[inside] = np.where(defined, counts["count"], np.nan)  # a missing count is no number
        status[inside] = counts["status"]
        out["modes"], out["modes_status"] = modes, status
    if "architecture" in wanted:
        for name, value in m.architecture().items():
            out[f"architecture_{name}"] = np.full(n, value)
    if "workspace_volume" in wanted:
        grid = spec["workspace"]
        mesh = np.meshgrid(*grid.values(), indexing="ij")
        points = {k: v.ravel() for k, v in zip(grid, mesh, strict=True)}
        pose_values = {k: v for k, v in {**spec["fixed"], **points}.items() if k in spec["pose_names"]}
        total = mesh[0].size
        reachable = 0
        for start in range(0, total, spec["chunk"]):
            part = {k: np.broadcast_to(v, (total,))[start : start + spec["chunk"]] for k, v in pose_values.items()}
            found = _pose_quantities(m, part, ["reachable"], spec["branch"], spec["onto_reachable"])
            reachable += int(found["reachable"].sum())
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
        elif q == "modes":
            names += ["modes", "modes_status"]
        else:
            names.append(q)
    return names


def _variable_kinds(
    pose_names: Sequence[str], actuated_names: Sequence[str], parameter_axes: Mapping[str, str]
) -> dict[str, str]:
    """Each name a sweep takes (axis or fixed) -> its kind."""
    kinds = dict.fromkeys(pose_names, "pose coordinate")
    kinds.update(dict.fromkeys(actuated_names, "actuated variable"))
    kinds.update(dict.fromkeys(parameter_axes, "parameter"))
    return kinds


def _pose_unit(name: str) -> str:
    """The unit of a pose coordinate: metres for a position, radians for an angle."""
    return "m" if name in ("x", "y", "z") else "rad"


def _axis_units(m: Mechanism, kinds: Mapping[str, str], parameter_axes: Mapping[str, str]) -> dict[str, str]:
    """Each name a sweep takes -> its unit (the manifest's for actuated variables and parameters;
    "" for a pure number), written on the dataset's coordinates for the maps' axis labels."""
    actuated = {v.name: v.unit for v in m.manifest.actuated}
    parameters = {p.name: p.unit for p in m.manifest.parameters}
    units = {}
    for name, kind in kinds.items():
        if kind == "pose coordinate":
            units[name] = _pose_unit(name)
        elif kind == "actuated variable":
            units[name] = actuated.get(name, "")
        else:
            units[name] = parameters.get(parameter_axes[name], "")
    return units


def _readers(quantities: Sequence[str]) -> dict[str, list[str]]:
    """Kind of variable -> the requested quantities that read it (a parameter: every quantity;
    workspace_volume reads the pose coordinates outside its workspace grid as fixed values)."""
    return {
        "pose coordinate": [q for q in quantities if q in (*POSE_QUANTITIES, "workspace_volume")],
        "actuated variable": [q for q in quantities if q == "modes"],
        "parameter": list(quantities),
    }


def _unread(kind: str, quantities: Sequence[str]) -> str:
    """Why a name is refused: no requested quantity reads it."""
    return (
        f"a {kind}, which none of the quantities {list(quantities)} reads (pose coordinates: "
        f"{', '.join(POSE_QUANTITIES)}, workspace_volume (fixed only); actuated variables: modes; parameters: "
        "every quantity); remove it"
    )


def _fixed_values(
    fixed: object,
    kinds: Mapping[str, str],
    readers: Mapping[str, list[str]],
    grid: Mapping[str, np.ndarray],
    workspace: Mapping[str, np.ndarray],
    quantities: Sequence[str],
) -> dict[str, float]:
    """The user's ``fixed`` values, checked: a known name that is neither swept nor a workspace
    axis and that some requested quantity reads, and one finite real number (SI)."""
    from parakin.validation import in_magnitude, real_number

    if fixed is None:
        return {}
    if not isinstance(fixed, Mapping):
        raise BadInputError(f"fixed must be a mapping {{name: value}}, got {type(fixed).__name__}")
    values: dict[str, float] = {}
    for name, value in fixed.items():
        if name not in kinds:
            raise BadInputError(f"fixed {name!r} is not a name of this sweep; choose from {sorted(kinds)}")
        if name in grid:
            raise BadInputError(
                f"fixed {name!r} is swept (an axis): it takes the axis values; remove it from fixed or from the axes"
            )
        if name in workspace:
            raise BadInputError(f"fixed {name!r} is a workspace axis: remove it from fixed or from workspace")
        if not readers[kinds[name]]:
            raise BadInputError(f"fixed {name!r}: {_unread(kinds[name], quantities)}")
        label = f"fixed {name!r}"
        array = as_array(value, label, (), finite=False)
        if array.ndim != 0:
            raise BadInputError(f"{label} must be one number, got shape {array.shape}; sweep it as an axis")
        values[name] = in_magnitude(real_number(float(array), label), label)
    return values


def _home_pose(m: Mechanism) -> np.ndarray:
    """(6,) x, y, z, alpha, beta, gamma of the home configuration where it closes, else of a closed
    configuration near it (zeros when none is found)."""
    from parakin.errors import ParakinError
    from parakin.pose import xyz_euler_from_pose
    from parakin.studies.sampling import sample_configurations

    try:
        solved = m.forward_pose(m.home_actuated, strict=False)
        if bool(solved.converged):
            return xyz_euler_from_pose(solved.pose)
        near = sample_configurations(m, 16, seed=0)
        return xyz_euler_from_pose(near.pose[0]) if near.pose.shape[0] else np.zeros(6)
    except ParakinError:
        return np.zeros(6)


def home_branch(m: Mechanism) -> int | None:
    """The inverse branch of the home: the valid branch whose actuated values at the home pose are
    the home input.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism with an inverse.

    Returns
    -------
    int or None
        The branch index, or None where no valid branch gives the home input back (to 1e-9
        relative; angles modulo a whole turn) or the mechanism has no inverse.

    Examples
    --------
    >>> import parakin
    >>> home_branch(parakin.load("planar_3rrr", backend="numpy"))
    0
    """
    if m.capabilities.inverse is None:
        return None
    pose = m.platform_pose(m.home_actuated, m.home_passive)
    inverse = m.inverse_pose(pose, strict=False)
    difference = inverse.actuated - m.home_actuated
    with np.errstate(invalid="ignore"):
        difference = np.where(m._angular_actuated, wrap_angle(difference), difference)
        gap = np.where(inverse.valid, np.abs(difference).max(-1), np.inf)
    k = int(np.argmin(gap))
    return k if gap[k] <= 1e-9 * (1.0 + np.abs(m.home_actuated).max(initial=0.0)) else None


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
    progress: bool | None = None,
    backend: str = "auto",
    onto_reachable: bool = False,
) -> xarray.Dataset:
    """Evaluate ``quantities`` over the grid ``axes`` (the module docstring says how).

    Parameters
    ----------
    mechanism : str or Path or Mechanism
        A mechanism name, a package folder, or a loaded mechanism (its parameters and limits).
    quantities : sequence of str
        Names from ``QUANTITIES``: pose space (reachable, branches, type_i_distance,
        type_ii_distance), actuated space (modes), parameter space (architecture,
        workspace_volume).
    axes : mapping of str to array_like, each 1-D
        The grid: pose coordinates (m, rad), actuated variables or parameters (their manifest
        units) to their values, in order; the first axis is cut into chunks.
    fixed : mapping of str to float, optional
        Values of names not swept (default: the home pose and input, the loaded parameters).
    workspace : mapping of str to array_like, optional
        The pose grid of ``workspace_volume`` per design: evenly spaced ascending values.
    branch : int, optional
        The inverse branch the distances (type_i_distance, type_ii_distance) are measured in,
        NaN where it is not valid (default: the branch of the home pose, ``home_branch``; the
        first valid one at each pose where the home is no branch of the inverse).
    chunk : int
        About this many grid points per chunk (memory is bounded by the chunk).
    scheduler : str, optional
        None (dask's local threads), 'synchronous', 'processes', or a ``dask.distributed``
        scheduler address.
    store : str or Path, optional
        A zarr folder: each finished chunk is written and checksummed; a rerun resumes.
    progress : bool, optional
        A bar over the grid's points: True always, False never, None as
        ``parakin.log.progress`` decides.
    backend : str
        The backend a mechanism given by name is loaded with.
    onto_reachable : bool
        Pose-space quantities at the pose a lower-mobility platform reaches for each grid pose
        (``Mechanism.inverse_pose(onto_reachable=True)``: a 3-RPS swept over its height and
        tilt gets reachability, branches and distances at the reached poses, the parasitic
        coordinates as it takes them); default False: at the grid pose as given.

    Returns
    -------
    xarray.Dataset
        One variable per quantity (with ``modes_status`` for modes) over one dimension per
        axis, each coordinate carrying its ``units``; lazy over the store when one is given.

    Raises
    ------
    BadInputError
        An unknown quantity, axis or fixed name, a name no quantity reads, a fixed value for a
        swept name, an axis that is not a non-empty 1-D array, a workspace grid that is not
        evenly spaced, a store that is a file or holds another sweep, or a chunk that fails its
        checksum on read.
    UnsupportedOperationError
        Quantities the mechanism cannot compute (no closed-form inverse, no forward
        elimination), ``onto_reachable`` where its inverse reads no pose onto a reachable set,
        or dask and xarray are not installed.
    StoreInUseError
        Another sweep is writing ``store``.

    Examples
    --------
    >>> from parakin import sweep
    >>> ds = sweep("five_bar", ["reachable", "type_ii_distance"], {"x": [0.0, 0.5], "y": [0.33]}, backend="numpy")
    >>> ds["reachable"].values.tolist(), ds["type_ii_distance"].values.round(3).tolist()
    ([[True], [False]], [[0.666], [nan]])
    >>> ds["x"].attrs["units"]
    'm'
    """
    from parakin.mechanism import Mechanism as MechanismClass
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
    elif {"type_i_distance", "type_ii_distance"} & set(quantities):
        branch = home_branch(m)
    kind = m.manifest.pose_kind
    if kind not in POSE_COORDINATES:
        raise UnsupportedOperationError(
            f"{m.name}: pose kind {kind!r} has no sweep coordinates {sorted(POSE_COORDINATES)}"
        )
    pose_names = POSE_COORDINATES[kind]
    parameter_axes = {}
    for p in m.manifest.parameters:
        shadowed = p.name in pose_names or p.name in m.actuated_names
        parameter_axes[f"param_{p.name}" if shadowed else p.name] = p.name
    if not isinstance(axes, Mapping):
        raise BadInputError(f"axes must be a mapping {{name: 1-D values}}, got {type(axes).__name__}")
    kinds = _variable_kinds(pose_names, m.actuated_names, parameter_axes)
    readers = _readers(quantities)
    grid = {}
    for name, values in axes.items():
        if name not in kinds:
            raise BadInputError(
                f"axis {name!r} is not a pose coordinate {pose_names}, an actuated variable "
                f"{m.actuated_names} or a parameter {sorted(parameter_axes)}"
            )
        if not readers[kinds[name]]:
            raise BadInputError(f"axis {name!r}: {_unread(kinds[name], quantities)}")
        array = as_array(values, f"axis {name!r}", ())
        if array.ndim != 1 or array.size == 0:
            raise BadInputError(f"axis {name!r} must be a non-empty 1-D array, got shape {array.shape}")
        grid[name] = array
    if not grid:
        raise BadInputError("a sweep needs at least one axis")
    if any(q in POSE_QUANTITIES for q in quantities) and m.capabilities.inverse is None:
        raise UnsupportedOperationError(f"{m.name} has no closed-form inverse: pose-space quantities need one")
    if not isinstance(onto_reachable, bool):
        raise BadInputError(f"onto_reachable must be True or False, got {onto_reachable!r}")
    if onto_reachable:
        if not any(q in POSE_QUANTITIES or q == "workspace_volume" for q in quantities):
            raise BadInputError(
                f"onto_reachable (--onto-reachable) reads grid poses onto the reachable set, and none of {list(quantities)} is a "
                f"pose-space quantity {POSE_QUANTITIES}: leave it out"
            )
        # refused here, before any chunk runs, in inverse_pose's words (full mobility, no reading)
        m.inverse_pose(m.platform_pose(m.home_actuated, m.home_passive), strict=False, onto_reachable=True)
    if "modes" in quantities and m.capabilities.forward is None:
        raise UnsupportedOperationError(f"{m.name} has no forward elimination: 'modes' is not available")
    workspace_grid = {}
    if "workspace_volume" in quantities:
        if not workspace or not isinstance(workspace, Mapping):
            raise BadInputError("workspace_volume needs workspace={coordinate: values} (the pose grid per design)")
        swept_pose = [name for name in grid if kinds[name] == "pose coordinate"]
        if swept_pose:
            raise BadInputError(
                f"axis {swept_pose[0]!r}: workspace_volume integrates over the workspace grid with the other "
                "pose coordinates fixed; put it in workspace= or in fixed=, or sweep the pose in a separate sweep"
            )
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
    given = _fixed_values(fixed, kinds, readers, grid, workspace_grid, quantities)
    fixed_parameters = {parameter_axes[k]: v for k, v in given.items() if kinds[k] == "parameter"}
    if fixed_parameters:  # the design of the unswept parameters (load validates their domains)
        m = _mechanism(source, backend_name, tuple(sorted({**m.parameters, **fixed_parameters}.items())), _limits_of(m))
    fixed_values = {k: v for k, v in given.items() if kinds[k] != "parameter"}
    unset = [n for n in pose_names if readers["pose coordinate"] and n not in {*grid, *workspace_grid, *given}]
    if unset:  # the home configuration's pose where it closes, else a closed configuration near it
        home = _home_pose(m)
        for name in unset:
            fixed_values[name] = float(home[_six_index(name)])
    status_names = tuple(m.manifest.abi.input_status)
    if "modes" in quantities:
        low, high = m.actuated_bounds
        leaves = False
        for k, name in enumerate(m.actuated_names):
            taken = grid.get(name, np.array([fixed_values.get(name, m.home_actuated[k])]))
            outside = (taken < low[k]) | (taken > high[k])
            if name in fixed_values and outside.any():
                raise BadInputError(
                    f"fixed {name!r} = {fixed_values[name]:g} is outside its actuated range [{low[k]:g}, {high[k]:g}] "
                    "(no solver takes it: every point of the sweep would be missing); choose a value inside"
                )
            leaves = leaves or bool(outside.any())
        if leaves and OUTSIDE_RANGE not in status_names:
            status_names = (*status_names, OUTSIDE_RANGE)
    names = _output_names(m, quantities)
    spec = {
        "status_names": status_names,
        "source": source,
        "backend": backend_name,
        "parameters": dict(m.parameters),  # with the fixed ones
        "limits": [[name, low, high] for name, (low, high) in _limits_of(m)],  # with load(limits=...)
        "parameter_axes": parameter_axes,
        "pose_names": pose_names,
        "fixed": fixed_values,
        "quantities": list(quantities),
        "branch": branch,
        "onto_reachable": onto_reachable,
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

    token = f"{os.getpid()}-{next(_SWEEP_IDS)}"  # this call's progress bar, in this process

    def compute_block(_: np.ndarray, block_info: dict | None = None) -> np.ndarray:
        assert block_info is not None
        block = _block(spec, grid, names, block_info[0]["array-location"])
        _advance(token, int(np.prod(block.shape[:-1], dtype=np.int64)))
        return block

    values = template.map_blocks(compute_block, new_axis=len(shape), chunks=(*chunks, (len(names),)), dtype=float)
    dims = list(grid)
    data = {}
    for k, name in enumerate(names):
        array, attributes = values[..., k], {}
        if name == "reachable":
            array = array.astype(bool)
        elif name == "branches":
            array = array.astype(np.int32)
        elif name == "modes_status":  # CF flag attributes: the codes are named where they are stored
            array = array.astype(np.int32)
            attributes = {
                "long_name": "why modes is missing (0: it is defined)",
                "flag_values": list(range(len(status_names))),
                "flag_meanings": " ".join(status_names),
            }
        data[name] = (dims, array, attributes)
    # everything that determines the values: a store of any other sweep is refused, not reused
    digest = hashlib.sha256()
    for name, values in [*grid.items(), *(("workspace " + k, v) for k, v in workspace_grid.items())]:
        digest.update(name.encode())
        digest.update(np.ascontiguousarray(values, dtype=float).tobytes())
    described = {k: v for k, v in spec.items() if k != "workspace"}
    fingerprint = json.dumps({**described, "grids": digest.hexdigest()}, sort_keys=True, default=str)
    described_attributes = {
        "mechanism": m.name,
        "pose_kind": kind,
        "fixed": json.dumps(fixed_values),
        "spec": fingerprint,
        "workspace": json.dumps({k: [float(v[0]), float(v[-1]), int(v.size)] for k, v in workspace_grid.items()}),
    }
    units = _axis_units(m, kinds, parameter_axes)
    coordinates = {name: (name, values, {"units": units[name]}) for name, values in grid.items()}
    if "workspace_volume" in data:  # the product of the workspace axes' units
        dims_w, array_w, attributes_w = data["workspace_volume"]
        powers = collections.Counter(_pose_unit(name) for name in workspace_grid)
        volume_unit = " ".join(unit if n == 1 else f"{unit}^{n}" for unit, n in sorted(powers.items()))
        data["workspace_volume"] = (dims_w, array_w, {**attributes_w, "units": volume_unit})
    dataset = xr.Dataset(data, coords=coordinates, attrs=described_attributes)
    # the bar's decision (parakin.log.progress) weighs the points computed, workspace points included
    size = int(np.prod(shape, dtype=np.int64)) * int(np.prod([v.size for v in workspace_grid.values()], dtype=np.int64))
    if store is None:
        return _compute(dataset, token, scheduler, progress, size)
    return _compute_into(dataset, Path(store), chunks[0], scheduler, progress, size)


def _client(scheduler: str | None) -> Any:
    if scheduler is None or scheduler in ("threads", "synchronous", "processes"):
        return None
    from distributed import Client

    try:
        return Client(scheduler, timeout=30)
    except (OSError, ValueError, TimeoutError) as error:
        raise BadInputError(f"no dask scheduler at {scheduler!r}: {error}") from error


def _advance(token: str, points: int) -> None:
    """``points`` more grid points done for the sweep ``token``: its bar, where this process
    holds one (a worker process of a cluster or of the 'processes' scheduler holds none)."""
    with _BARS_GUARD:
        bar = _BARS.get(token)
    if bar is not None:
        bar.update(points)


def _compute(
    dataset: xarray.Dataset, token: str, scheduler: str | None, progress: bool | None, size: int
) -> xarray.Dataset:
    """The sweep computed in memory, with a bar over the grid's points: each block adds its
    points as it finishes (``_advance``), whichever tasks dask fuses it into."""
    client = _client(scheduler)
    local = scheduler if scheduler in ("threads", "synchronous", "processes") else None
    # a dask.distributed cluster reports to its own dashboard instead; worker processes cannot
    # reach this process's bar
    show = False if client is not None or local == "processes" else progress
    try:
        with bar_over(_points(dataset), f"sweep of {dataset.attrs['mechanism']}", "point", show, size=size) as bar:
            with _BARS_GUARD:
                _BARS[token] = bar
            try:
                return dataset.compute(scheduler=client or local)
            finally:
                with _BARS_GUARD:
                    _BARS.pop(token, None)
    finally:
        if client is not None:
            client.close()


def _points(dataset: xarray.Dataset) -> int:
    """The number of grid points of a sweep (the product of its axes' sizes)."""
    return int(np.prod([int(size) for size in dataset.sizes.values()], dtype=np.int64))


def _checksum(values: np.ndarray) -> str:
    """sha256 of one variable's values in one chunk: dtype, shape and little-endian bytes, every
    NaN as the canonical NaN (its payload bits are not data, and a store may not keep them)."""
    array = np.asarray(values)
    if array.dtype.kind == "f":
        array = np.where(np.isnan(array), np.nan, array)
    array = np.ascontiguousarray(array, dtype=array.dtype.newbyteorder("<"))
    digest = hashlib.sha256(f"{array.dtype.str} {array.shape}".encode())
    digest.update(array.tobytes())
    return digest.hexdigest()


def _read_chunk(store: Path, name: str, k: int, region: slice, expected: str | None) -> np.ndarray:
    """Chunk ``k`` (rows ``region`` of the first axis) of variable ``name`` read from the zarr
    store, verified against its recorded checksum ``expected``; BadInputError when it cannot be
    read or does not match (it is then never returned)."""
    import zarr

    try:
        values = np.asarray(zarr.open_array(str(store / name), mode="r")[region])
    # any failure to read (a damaged compressed stream, missing metadata, a codec error) is the
    # same verdict: the chunk is not the one recorded
    except Exception as error:
        raise BadInputError(
            f"sweep store {store}: chunk {k} of {name!r} cannot be read ({type(error).__name__}: {error}); "
            "run the same sweep with this store again to recompute it"
        ) from error
    if expected is None or _checksum(values) != expected:
        raise BadInputError(
            f"sweep store {store}: chunk {k} of {name!r} does not match the checksum recorded when it was "
            "written (changed or never written); run the same sweep with this store again to recompute it"
        )
    return values


def _read_record(store: Path) -> dict[str, Any] | None:
    """The store's record, or None where it is missing or unreadable (a kill, a damaged file)."""
    try:
        record = json.loads((store / RECORD).read_text())
    except (OSError, ValueError):
        return None
    return record if isinstance(record, dict) else None


def _write_record(store: Path, spec: str, finished: Mapping[int, Mapping[str, str]]) -> None:
    """Replace the record atomically (a scratch file renamed over it): a kill leaves the old or
    the new record, never a partial one."""
    scratch = store / (RECORD + ".tmp")
    chunks = {str(k): dict(sums) for k, sums in sorted(finished.items())}
    scratch.write_text(json.dumps({"format": RECORD_FORMAT, "spec": spec, "chunks": chunks}))
    scratch.replace(store / RECORD)


def _store_spec(store: Path) -> str | None:
    """The spec a zarr store's own attributes name (written before any record), or None."""
    try:
        metadata = json.loads((store / "zarr.json").read_text())
        spec = metadata.get("attributes", {}).get("spec")
    except (OSError, ValueError, AttributeError):
        return None
    return spec if isinstance(spec, str) else None


def _recorded(record: Mapping[str, Any] | None, names: Sequence[str]) -> dict[int, dict[str, str]]:
    """Chunk -> {variable: checksum} of a record; entries without a checksum for every variable
    (an older record, an edited one) are left out: such a chunk is recomputed."""
    if record is None or record.get("format") != RECORD_FORMAT or not isinstance(record.get("chunks"), dict):
        return {}
    recorded = {}
    for key, sums in record["chunks"].items():
        if isinstance(sums, dict) and str(key).isdigit() and all(isinstance(sums.get(n), str) for n in names):
            recorded[int(key)] = {n: sums[n] for n in names}
    return recorded


def _structure_matches(store: Path, dataset: xarray.Dataset, rows: tuple[int, ...]) -> bool:
    """Every variable of the sweep is an array of the store with its shape, dtype and chunk rows."""
    import zarr

    try:
        for name, variable in dataset.data_vars.items():
            array = zarr.open_array(str(store / str(name)), mode="r")
            if array.shape != variable.shape or array.dtype != variable.dtype or array.chunks[0] != rows[0]:
                return False
    # an array whose metadata is missing or unreadable: the structure is not the sweep's
    except Exception:
        return False
    return True


def _lock_file(store: Path) -> Path:
    """The file whose lock a sweep holds while it writes ``store``: next to the store (which is
    renamed and rebuilt under it), named after the store's resolved path, so that every path
    to one store names one lock."""
    resolved = store.resolve()
    return resolved.with_name(f".{resolved.name}.lock")


def _holds_lock(store: Path) -> bool:
    """Whether this process is writing ``store`` (holds its lock)."""
    with _WRITING_GUARD:
        return store.resolve() in _WRITING


@contextlib.contextmanager
def _writing(store: Path) -> Iterator[None]:
    """Hold the store's lock while the block runs, or raise StoreInUseError naming the store and
    the process that holds it. The lock is an advisory ``flock`` on ``_lock_file(store)``: the
    system drops it when the holder ends, even by SIGKILL, so a killed sweep never leaves a
    store locked. The lock file stays (removing it would let two processes lock two files)."""
    key = store.resolve()
    path = _lock_file(store)
    with _WRITING_GUARD:
        if key in _WRITING:
            raise StoreInUseError(
                f"another sweep is writing the store {store} (in this process, pid {os.getpid()}); "
                "run again when it has finished to resume the store"
            )
        _WRITING.add(key)
    try:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            handle = open(path, "a+")  # noqa: SIM115 - held open for the lock's lifetime
        except OSError as error:
            raise BadInputError(f"sweep store {store}: cannot open its lock file {path} ({error})") from error
        with handle:
            _lock(handle, store, path)
            try:
                # who holds it, for the message of a sweep refused meanwhile
                handle.seek(0)
                handle.truncate()
                handle.write(f"pid {os.getpid()} on {socket.gethostname()}\n")
                handle.flush()
                yield
            finally:
                handle.seek(0)
                handle.truncate()
    finally:
        with _WRITING_GUARD:
            _WRITING.discard(key)


def _lock(handle: Any, store: Path, path: Path) -> None:
    """Take the exclusive lock of the open lock file ``handle`` without waiting."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - no flock (Windows): threads of this process only
        return
    try:
        fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError as error:
        handle.seek(0)
        holder = handle.read().strip()
        raise StoreInUseError(
            f"another sweep is writing the store {store}{f' ({holder})' if holder else ''}; run again when "
            "it has finished to resume the store"
        ) from error
    except OSError as error:  # a file system without locks: writing unlocked could lose chunks
        raise BadInputError(
            f"sweep store {store}: its lock file {path} cannot be locked ({error}); choose a store on a file "
            "system with file locks"
        ) from error


def _scratch(store: Path) -> Path:
    """The folder a store is built in before it is renamed into place, emptied. Only a process
    holding the store's lock (``_writing``) builds, renames or removes it, so one found there
    is what a sweep killed during initialisation left: its maker is gone, never a live sweep's."""
    import shutil

    scratch = store.with_name(f".{store.name}.initialising")
    if scratch.exists():
        shutil.rmtree(scratch)
    return scratch


def _initialise(dataset: xarray.Dataset, store: Path) -> None:
    """Create the store's metadata and an empty record in a scratch folder next to it, then rename
    it into place: the store appears complete with its record, or not at all (a kill leaves only
    the scratch folder, which the next run replaces)."""
    scratch = _scratch(store)
    dataset.to_zarr(str(scratch), compute=False, mode="w", consolidated=False)
    _write_record(scratch, dataset.attrs["spec"], {})
    scratch.rename(store)


def _compute_into(
    dataset: xarray.Dataset,
    store: Path,
    rows: tuple[int, ...],
    scheduler: str | None,
    progress: bool | None,
    size: int,
) -> xarray.Dataset:
    """Write the sweep chunk by chunk into a zarr store, skipping the chunks a previous run
    finished and that still verify against the checksums in the record (``RECORD``, replaced
    atomically after each batch of writes); returns the dataset read back chunk by chunk, verified.
    The writing holds the store's lock (``_writing``): a sweep started meanwhile is refused."""
    bounds = np.cumsum((0, *rows))
    if store.exists() and not store.is_dir():
        raise BadInputError(f"store {store} is a file, not a sweep store (a folder); choose another path")
    with _writing(store):
        finished, pending, unverified = _write_store(dataset, store, rows, scheduler, progress, size)
    result = _verified_view(dataset, store, bounds, finished)
    result.attrs["chunks_computed"] = len(pending)  # this run's work (0: everything was done before)
    result.attrs["chunks_unverified"] = unverified  # recorded chunks that failed verification (recomputed)
    return result


def _write_store(
    dataset: xarray.Dataset,
    store: Path,
    rows: tuple[int, ...],
    scheduler: str | None,
    progress: bool | None,
    size: int,
) -> tuple[dict[int, dict[str, str]], list[int], int]:
    """``_compute_into``'s writing, under the store's lock: the finished chunks with their
    checksums, the chunks this run computed and how many recorded ones failed verification."""
    import dask

    first = next(iter(dataset.dims))
    bounds = np.cumsum((0, *rows))
    names = [str(name) for name in dataset.data_vars]
    spec = dataset.attrs["spec"]
    if store.exists() and not any(store.iterdir()):
        store.rmdir()  # an empty folder: nothing of anyone's to keep
    if not store.exists():
        _initialise(dataset, store)
        recorded: dict[int, dict[str, str]] = {}
    else:
        record = _read_record(store)
        # without a (readable) record, the store's own attributes say whose it is: a store killed
        # before its first record resumes as an unfinished store of this sweep
        owner = record.get("spec") if record is not None else _store_spec(store)
        if owner != spec:
            raise BadInputError(f"{store} holds another sweep; remove it or choose another store")
        if record is None or not _structure_matches(store, dataset, rows):
            # nothing verified to keep, or metadata a kill or an edit left partial: initialise anew
            store.rename(_scratch(store))
            _initialise(dataset, store)
            record = None
        recorded = _recorded(record, names)
    finished: dict[int, dict[str, str]] = {}
    for k, sums in recorded.items():
        if k >= len(rows):
            continue
        region = slice(int(bounds[k]), int(bounds[k + 1]))
        try:
            for name in names:
                _read_chunk(store, name, k, region, sums[name])
        except BadInputError:
            continue  # recomputed below
        finished[k] = sums
    unverified = len(recorded) - len(finished)
    _write_record(store, spec, finished)
    pending = [k for k in range(len(rows)) if k not in finished]
    client = _client(scheduler)
    local = scheduler if scheduler in ("threads", "synchronous", "processes") else None
    workers = max(1, len(client.scheduler_info()["workers"])) if client is not None else 2
    # a bar over the grid's points (a chunk is ``rows[k]`` slabs of the first axis)
    slab = _points(dataset) // max(int(bounds[-1]), 1)
    bar = bar_over(
        _points(dataset), f"sweep of {dataset.attrs['mechanism']} into {store.name}", "point", progress, size=size
    )
    bar.update(slab * sum(rows[k] for k in finished))
    try:
        for start in range(0, len(pending), workers):
            batch = pending[start : start + workers]
            parts = [dataset.isel({first: slice(int(bounds[k]), int(bounds[k + 1]))}) for k in batch]
            computed = dask.compute(*parts, scheduler=client or local)
            for k, part in zip(batch, computed, strict=True):
                rows_k = {first: slice(int(bounds[k]), int(bounds[k + 1]))}
                with warnings.catch_warnings():  # zarr lists the record among the group's members
                    warnings.filterwarnings("ignore", message=f"Object at {RECORD} is not recognized")
                    part.drop_vars(list(part.coords)).to_zarr(str(store), region=rows_k, consolidated=False)
                # the checksums of the arrays written, recorded only after the write returned
                finished[k] = {name: _checksum(part[name].values) for name in names}
            _write_record(store, spec, finished)
            bar.update(slab * sum(rows[k] for k in batch))
    finally:
        bar.close()
        if client is not None:
            client.close()
    return finished, pending, unverified


def _verified_view(
    dataset: xarray.Dataset, store: Path, bounds: np.ndarray, finished: Mapping[int, Mapping[str, str]]
) -> xarray.Dataset:
    """``dataset`` with every variable read lazily from the store, one chunk per task, each chunk
    verified against its recorded checksum when it is read (coordinates and attributes are the
    sweep's own, not read back)."""
    import dask.array as da
    import xarray as xr

    data = {}
    for name, variable in dataset.data_vars.items():
        sums = {k: finished[k][str(name)] for k in finished}
        read = functools.partial(_read_block, str(store), str(name), tuple(int(b) for b in bounds), sums)
        meta = np.empty((0,) * variable.ndim, dtype=variable.dtype)
        array = da.map_blocks(read, chunks=variable.data.chunks, dtype=variable.dtype, meta=meta)
        data[name] = (variable.dims, array, variable.attrs)
    return xr.Dataset(data, coords=dataset.coords, attrs=dict(dataset.attrs))


def _read_block(
    store: str, name: str, bounds: tuple[int, ...], sums: Mapping[int, str], block_info: dict | None = None
) -> np.ndarray:
    """One verified chunk of ``name`` (a dask block of the first axis)."""
    assert block_info is not None
    k = int(block_info[None]["chunk-location"][0])
    return _read_chunk(Path(store), name, k, slice(bounds[k], bounds[k + 1]), sums.get(k))


__all__ = ["POSE_COORDINATES", "QUANTITIES", "sweep"]
