"""Every assembly mode of a batch of inputs: the generated C pipeline, or the same algorithm
vectorised in NumPy for the Python backends.

Steps per input (both versions, ``generator/templates/c_driver.c.j2`` for C): the generated
univariate polynomial; every real root isolated (``parakin.solvers.polynomial.isolate_real_roots``,
complete: roots are separated by the roots of the derivative); for each root x branch the
generated back substitution; the passive joints from the inverse kernels (the branch whose
actuated values match); closure and alignment; a Newton polish; wrapping, joint limits, input
independence and repeats. Each slot ends with an outcome, so every root is accounted for.
"""

from __future__ import annotations

import ctypes
import functools
import os
import weakref
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from parakin.errors import NEWTON_NO_CONVERGENCE, NEWTON_OK, NEWTON_SINGULAR, NEWTON_WRONG_BASIN, BadInputError
from parakin.log import logger
from parakin.pose import pose_vector, wrap_angle
from parakin.results import Array, AssemblyModes
from parakin.solvers.certify import (
    UNIT,
    Certificate,
    certify_roots,
    certify_roots_compiled,
    cluster_labels,
    homogeneous_group,
)
from parakin.solvers.exact_certify import certify_root_exactly, realness_in_chart
from parakin.solvers.path_tracking import (
    PATH_DIVERGED,
    PATH_FAILED,
    PATH_REACHED,
    PathPairs,
    Paths,
    is_known,
    near_home,
    path_coefficients,
    path_pairs,
    phase_normalised,
    real_phase,
    track,
    track_symmetric,
    typical_root_size,
)
from parakin.solvers.polynomial import isolate_real_roots
from parakin.solvers.projective import family_system, projective_family, projective_table, to_affine, to_projective
from parakin.solvers.subfamily_membership import outside_subfamily

if TYPE_CHECKING:
    from parakin.packages.manifest import Forward, Homotopy
    from parakin.solvers.loaded import LoadedMechanism as Mechanism  # the interface parakin.Mechanism implements

#: inputs per chunk of the NumPy pipeline: bounds its temporaries whatever the batch
CHUNK = 4096
CERTIFY_CHUNK = 256
#: the least work a thread of a compiled batch gets: homotopy paths, or closed-form inputs
THREAD_PATHS = 64
THREAD_INPUTS = 512
#: paths re-tracked per call of the NumPy tracker in a partial re-track (bounds its temporaries)
RETRACK_PATHS = 1024
#: two ends this close relative to their size may be one root (``suspect_paths``)
TWIN = 1e-4


#: the start instances, numbered as the generated C driver numbers them (its START_*): the first
#: stored, the second stored ('alternative'), the one near home (the manifest's ``near``)
START_FIRST, START_ALTERNATIVE, START_NEAR = 0, 1, 2
#: a re-track's start: each input's own first start (the one near home where it is near home:
#: ``first_instances``)
OWN_START = -1


class Retrack(NamedTuple):
    """A re-track in projective space (``parakin.solvers.projective``) from start instance
    ``instance`` (0 the first, 1 the second, ``OWN_START`` each input's own first): every path,
    or with ``redo`` (inputs, paths) only those, the others keeping their earlier ends ``ends``
    (inputs, paths, unknowns)."""

    instance: int
    redo: np.ndarray | None = None
    ends: np.ndarray | None = None

    def rows(self, a: int, b: int) -> Retrack:
        """This re-track for the inputs a:b of its batch."""
        if self.redo is None or self.ends is None:
            return self
        return Retrack(self.instance, self.redo[a:b], self.ends[a:b])


#: the start instances an input not certified complete is tracked from again, all its paths in
#: projective space, after the paths of its first run that no certified box holds alone were
#: (``suspect_paths``): its missing roots are mostly near infinity, where affine paths meet or
#: escape. The second instance's segment is another path through parameter space
RETRACKS = (START_ALTERNATIVE, START_FIRST)
#: an end this large (the largest of its unknowns, in the mechanism's own length scale:
#: ``length_scale``) is far: a root there is 1e6 times the mechanism's size, at or near infinity
#: (near a degenerate input roots of 1e6-1e8 are still certified, some only in exact arithmetic:
#: rus6 3e-3 from home along a random direction, 24 roots of 3e5-9e7, all 80 certified).
#: At a degenerate input (a home configuration, often) some of the family's roots go to infinity:
#: their paths grow as s^(-1/c) (c their winding number) and, with the input rounded, end at
#: 1e8-1e9 or beyond, where no certificate holds (rus6 at home: 24 of 80 paths, each ending
#: uncertified at 3e8-7e8 in the projective re-track). Budget: an input whose missing roots are
#: all accounted for by far, uncertified ends of its suspect paths' projective re-track, at least
#: one of them seen heading to infinity by ``toward_infinity``, is not tracked again from
#: ``RETRACKS``; its ``at_infinity`` counts them and the verdict says so. Far ends alone do not stop
#: the search: rus6 has roots of 1e7 at ordinary inputs, which the later runs certify (5 of 10^4
#: census inputs were left incomplete when they did). Only work is skipped: nothing is certified
#: that was not.
#: Far ends are still tried in exact arithmetic (``certify_inputs``): some succeed (rus6 3e-3
#: from home along a random direction: complete only with them)
FAR_ROOT = 1e6
#: the values of s (1 at the start, 0 at the input) at which ``toward_infinity`` reads a path's
#: homogenising coordinate w, relative to its point on the patch: toward a root at infinity |w|
#: falls as s^(1/c) (c the path's winding number; planar_3rrr at home: 0.36, 0.11, 0.036, c = 2),
#: toward a finite root, singular or not, it tends to the root's own, nonzero
PROBE_S = (1e-3, 1e-4, 1e-5)
#: the least factor |w| falls by from each of ``PROBE_S`` to the next: 10^(1/c) for c <= 5
PROBE_FALL = 1.5


#: what the solvers read from a fixed object (a manifest, its homotopy) on every call, by kind and
#: the object's identity; each entry keeps its object, so an identity is never reused meanwhile
_FIXED: dict[tuple[str, int], tuple[Any, Any]] = {}


def _fixed(kind: str, owner: Any, compute: Callable[[], Any]) -> Any:
    """``compute()`` for ``owner``, computed once per owner object (``_FIXED``)."""
    known = _FIXED.get((kind, id(owner)))
    if known is None or known[0] is not owner:
        known = (owner, compute())
        _FIXED[(kind, id(owner))] = known
    return known[1]


def _codes(m: Mechanism) -> dict[str, int]:
    return _outcome_codes(m.manifest.abi.mode_outcomes)


@functools.cache
def _outcome_codes(outcomes: tuple[str, ...]) -> dict[str, int]:
    return {name: code for code, name in enumerate(outcomes)}


def _allocate(info: Forward, m: Mechanism, count: int) -> dict[str, np.ndarray]:
    slots = info.degree * len(info.combinations)
    n_p = len(m.passive_names)
    return {
        "poses": np.empty((count, slots, 4, 4)),
        "passive": np.empty((count, slots, n_p)),
        "residual": np.empty((count, slots)),
        "conditioning": np.empty((count, slots)),
        "roots": np.empty((count, slots)),
        "outcome": np.empty((count, slots), dtype=np.int32),
        "root_kind": np.empty((count, slots), dtype=np.int32),
        "count": np.empty(count, dtype=np.int32),
        "real_roots": np.empty(count, dtype=np.int32),
        "near_roots": np.empty(count, dtype=np.int32),
        "at_infinity": np.empty(count, dtype=np.int32),
        "status": np.empty(count, dtype=np.int32),
        # a homotopy's complex endpoints (re, im) per path, for the certificate
        "endpoints": np.full((count, slots, info.homotopy.start.shape[1] if info.homotopy else 0, 2), np.nan),
        **({"end_size": np.zeros((count, slots))} if info.homotopy else {}),
    }


def length_scale(m: Mechanism) -> float:
    """The size of the geometry: the largest length parameter (1 m where none is nonzero, and
    where the closure does not scale with the length parameters: ``scales_with_lengths``). The
    thresholds on closure residuals and pose distances are multiples of it, so the same geometry
    in millimetres or kilometres gets the same modes, scaled; and the all-modes solver works in
    this size (``Mechanism._unit_free``: a size of 1 m is not rescaled). Cached per mechanism
    and parameter values (every all-modes call asks)."""
    key = np.ascontiguousarray(m.params, dtype=float).tobytes()
    known = _SIZES.get(m)
    if known is not None and known[0] == key:
        return known[1]
    lengths = [abs(v) for p, v in zip(m.manifest.parameters, m.params, strict=True) if p.unit == "m"]
    largest = max((v for v in lengths if np.isfinite(v)), default=0.0)
    size = float(largest) if largest > 0 and scales_with_lengths(m) else 1.0
    _SIZES[m] = (key, size)
    return size


#: parameter units whose scaling with a mechanism's size is known: a length, an angle, a number
SCALED_UNITS = ("m", "rad", "")


def length_unit(size: float) -> float:
    """The unit the all-modes solver divides every length by (``Mechanism._unit_free``): the power
    of two nearest ``size`` (``length_scale``) in log scale, exact in binary floating point; 1
    where ``size`` is not positive. The generator places its start near home in these numbers."""
    return float(np.exp2(np.round(np.log2(size)))) if size > 0 else 1.0


#: per mechanism object: (its parameter values, its ``length_scale``)
_SIZES: weakref.WeakKeyDictionary[Any, tuple[bytes, float]] = weakref.WeakKeyDictionary()


#: per mechanism object: (its parameter values, whether its closure scales with its lengths)
_SCALES: weakref.WeakKeyDictionary[Any, tuple[bytes, bool]] = weakref.WeakKeyDictionary()
#: the test of ``scales_with_lengths``: every length halved (exact in binary floating point)
SCALE_TEST_UNIT = 2.0
#: the degrees in the lengths a closure row may have (a rotation error 0, a position
#: difference 1, a squared distance 2, ...)
SCALE_DEGREES = np.arange(-2, 5)


def scales_with_lengths(m: Mechanism) -> bool:
    """Whether the mechanism's loop closure is the same geometry when every length (parameters,
    actuated and passive variables in m) is divided by one unit: each residual row then scales
    by a power of the unit (its degree in the lengths). A model that writes a length as a
    number instead of a parameter (a user's ``R_B = 0.2`` in a joint's point) does not: its
    closure with the length parameters rescaled is another mechanism, whose modes do not close
    this one (the skew 3-RRS fixture: modes 0.09-0.17 m off, the home lost). Tested at one
    generic configuration near the home (rows that vanish at both scales say nothing); cached
    per mechanism and parameter values.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism (its ``params``, home and the kernel ``loop_closure``).

    Returns
    -------
    bool
        True where every nonzero residual row scales by a power of the unit (to 1e-9 relative);
        also True where the test cannot be evaluated (a closure undefined there).

    Examples
    --------
    >>> import parakin
    >>> from parakin.solvers.modes import scales_with_lengths
    >>> scales_with_lengths(parakin.load("five_bar", backend="numpy"))
    True
    """
    key = np.ascontiguousarray(m.params, dtype=float).tobytes()
    known = _SCALES.get(m)
    if known is not None and known[0] == key:
        return known[1]
    manifest = m.manifest
    parameters = np.array([p.unit == "m" for p in manifest.parameters], dtype=bool)
    actuated = np.array([v.unit == "m" for v in manifest.actuated], dtype=bool)
    passive = np.array([v.unit == "m" for v in manifest.passive], dtype=bool)
    lengths = [abs(v) for v, is_length in zip(m.params, parameters, strict=True) if is_length and np.isfinite(v)]
    size = max(lengths, default=1.0) or 1.0
    # a generic configuration near the home: every variable moved by an irrational fraction
    theta = np.asarray(m.home_actuated, dtype=float)
    q = np.asarray(m.home_passive, dtype=float)
    moves = 0.05 * np.sin(1.0 + np.arange(theta.size + q.size))
    theta = theta + moves[: theta.size] * np.where(actuated, size, 1.0)
    q = q + moves[theta.size :] * np.where(passive, size, 1.0)
    unit = SCALE_TEST_UNIT
    with np.errstate(all="ignore"):
        here = m.backend.call("loop_closure", theta, q, m.params)["residual"]
        scaled = m.backend.call(
            "loop_closure",
            np.where(actuated, theta / unit, theta),
            np.where(passive, q / unit, q),
            np.where(parameters, m.params / unit, m.params),
        )["residual"]
    result = bool(_rows_scale(np.asarray(here, dtype=float), np.asarray(scaled, dtype=float), unit))
    _SCALES[m] = (key, result)
    return result


def _rows_scale(here: np.ndarray, scaled: np.ndarray, unit: float) -> bool:
    """Whether each residual row ``here`` (n_r,) is its row ``scaled`` (n_r,) times a power of
    ``unit`` (``SCALE_DEGREES``), to 1e-9 relative plus 1e-12 of the largest row (rounding in a
    row that cancels); rows below 1e-9 of the largest at both scales are not tested, and a
    closure undefined at either is taken to scale."""
    if not (np.isfinite(here).all() and np.isfinite(scaled).all()):
        return True
    largest = max(np.abs(here).max(initial=0.0), np.abs(scaled).max(initial=0.0))
    tested = (np.abs(here) > 1e-9 * largest) | (np.abs(scaled) > 1e-9 * largest)
    candidates = scaled[tested, None] * unit ** SCALE_DEGREES.astype(float)
    slack = 1e-9 * np.abs(here[tested, None]) + 1e-12 * largest
    return bool((np.abs(candidates - here[tested, None]) <= slack).any(-1).all())


def _settings(m: Mechanism) -> dict[str, float | int]:
    tol = m.tolerances
    size = length_scale(m)
    return {
        "polish_iterations": int(tol["polish_iterations"]),
        "tolerance": tol["polish"] * size,
        # what a Newton that stalls (singular, or linear near a double root) must reach to be a
        # mode: the real part of a near-real pair closes to ~1e-9, a real root to rounding
        "closure": min(tol["closure"], 100 * tol["polish"]) * size,
        "candidate": tol["candidate"] * size,
        # a pose difference mixes rotation (unitless) and position: scaled down, never up
        "duplicate": tol["duplicate"] * min(size, 1.0),
        "factor_zero": tol["factor_zero"],
        "singular_ratio": tol["singular_ratio"],
        "validity": tol["validity"],
        "degenerate": tol["degenerate"],
        "leading_tolerance": tol["leading"],
        "near_tolerance": tol["near_real"],
        "path_tolerance": tol["path_tolerance"],
        "real_endpoint": tol["real_endpoint"],
        "near_real_endpoint": tol["near_real_endpoint"],
    }


def _limits(m: Mechanism) -> tuple[Array, Array]:
    """Per passive variable (low, high), from the mechanism's limits (manifest and overrides)."""
    lower, upper = np.full(len(m.passive_names), -np.inf), np.full(len(m.passive_names), np.inf)
    lower[m._limit_index], upper[m._limit_index] = m._limit_low, m._limit_high
    return lower, upper


def _modes_job(m: Mechanism, theta: Array, out: dict[str, np.ndarray], lower: Array, upper: Array) -> ctypes.Structure:
    backend = m.backend
    values = {
        "n": theta.shape[0],
        "actuated": theta,
        "actuated_stride": theta.shape[-1],
        "params": m.params,
        "lower": lower,
        "upper": upper,
        **_settings(m),
        **out,
    }
    return backend.job(backend.ModesJob, values)  # type: ignore[attr-defined]


class _SingleInput:
    """A job for one input over buffers allocated once: a single call then costs the C pipeline
    and one copy of each result array, not the building of a job structure."""

    def __init__(self, m: Mechanism) -> None:
        self.limits = m.limits
        self.params = m.params
        self.theta = np.zeros((1, len(m.manifest.actuated)))
        self.out = _allocate(m.capabilities.forward, m, 1)  # type: ignore[arg-type]
        self.bounds = _limits(m)
        self.job = _modes_job(m, self.theta, self.out, *self.bounds)
        self.pointer = ctypes.byref(self.job)

    def run(self, m: Mechanism, theta: Array) -> dict[str, np.ndarray]:
        self.theta[...] = theta
        m.backend.forward_pose_all(self.pointer)  # type: ignore[attr-defined]
        return {key: value.copy() for key, value in self.out.items()}


def compiled_modes(m: Mechanism, theta: Array) -> dict[str, np.ndarray]:
    """The generated C pipeline over a flat batch (n, n_a): one foreign call."""
    if theta.shape[0] == 1:
        # one job per thread (the buffers are reused); rebuilt if the parameters or limits were
        # replaced, since the job points at their arrays
        single = getattr(m._single_input, "job", None)
        if single is None or single.params is not m.params or single.limits is not m.limits:
            single = m._single_input.job = _SingleInput(m)
        return single.run(m, theta)
    out = _allocate(m.capabilities.forward, m, theta.shape[0])  # type: ignore[arg-type]
    theta_c = np.ascontiguousarray(theta, dtype=float)
    limits = _limits(m)
    parts = _thread_parts(m, theta.shape[0])
    # one job per contiguous slice of the batch; the foreign call releases the GIL, so the
    # slices run in parallel (the C pipeline keeps its state on its own stack)
    jobs = [_modes_job(m, theta_c[a:b], {k: v[a:b] for k, v in out.items()}, *limits) for a, b in parts]
    if len(jobs) == 1:
        m.backend.forward_pose_all(ctypes.byref(jobs[0]))  # type: ignore[attr-defined]
    else:
        with ThreadPoolExecutor(len(jobs)) as pool:
            list(pool.map(lambda job: m.backend.forward_pose_all(ctypes.byref(job)), jobs))  # type: ignore[attr-defined]
    return out


def threads() -> int:
    """Threads a compiled batch spreads over: ``$PARAKIN_THREADS``, else every core."""
    setting = os.environ.get("PARAKIN_THREADS", "")
    try:
        return max(1, int(setting)) if setting else _cores()
    except ValueError:
        raise BadInputError(f"PARAKIN_THREADS must be a positive integer, got {setting!r}") from None


@functools.cache
def _cores() -> int:
    """The machine's cores (asked once: ``os.cpu_count`` reads the system each time)."""
    return max(1, os.cpu_count() or 1)


def _thread_parts(m: Mechanism, count: int) -> list[tuple[int, int]]:
    """Contiguous slices of a batch, one per thread, each worth the cost of starting a thread:
    THREAD_PATHS homotopy paths, or THREAD_INPUTS inputs of a closed form."""
    homotopy = m.capabilities.forward.homotopy  # type: ignore[union-attr]
    least = max(1, THREAD_PATHS // homotopy.start.shape[0]) if homotopy is not None else THREAD_INPUTS
    parts = max(1, min(threads(), count // least))
    edges = np.linspace(0, count, parts + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:], strict=True)]


def numpy_modes(m: Mechanism, theta: Array, info: Forward, retrack: Retrack | None = None) -> dict[str, np.ndarray]:
    """The same pipeline by the method ``info``, vectorised over the batch, in chunks of
    ``CHUNK`` inputs; kernels from the mechanism's backend. ``retrack``: a homotopy's paths
    tracked again in projective space (for inputs whose first answer was not certified complete)."""
    count = theta.shape[0]
    out = _allocate(info, m, count)
    for start in range(0, count, CHUNK):
        part = _numpy_chunk(
            m, theta[start : start + CHUNK], info, None if retrack is None else retrack.rows(start, start + CHUNK)
        )
        for key, value in part.items():
            out[key][start : start + CHUNK] = value
    return out


def _numpy_chunk(m: Mechanism, theta: Array, info: Forward, retrack: Retrack | None = None) -> dict[str, np.ndarray]:
    finite_input = np.asarray(np.isfinite(theta).all(-1))
    theta = np.where(finite_input[:, None], theta, 0.0)
    if info.homotopy is not None:
        found = _homotopy_candidates(m, theta, info, retrack)
    else:
        found = _polynomial_candidates(m, theta, info)
    return _settle(m, theta, finite_input, found)


def _homotopy_candidates(
    m: Mechanism, theta: Array, info: Forward, retrack: Retrack | None = None
) -> dict[str, np.ndarray]:
    """Every path of the generated homotopy followed to the inputs (``parakin.solvers.path_tracking``); real
    and near-real endpoints become candidates (passive values from the generated kernel), the
    others are accounted for as complex, at infinity or failed. ``retrack``: again, in
    projective space (``Retrack``)."""
    homotopy = info.homotopy
    assert homotopy is not None
    codes = _codes(m)
    tol = _settings(m)
    n = theta.shape[0]
    free, angles = _family(m, info, theta)
    own = retrack is None or retrack.instance == OWN_START
    instance = _first_of(homotopy, free, angles) if own else np.full(n, retrack.instance)  # type: ignore[union-attr]
    start = _start_rows(homotopy, instance)
    paths = start.shape[1]
    table = _table(m, info, free, angles, instance)
    tolerance = float(tol["path_tolerance"])
    if retrack is not None and retrack.redo is not None and retrack.ends is not None:
        ended = _track_some(homotopy, table, start, retrack.redo, retrack.ends, tolerance)
    else:
        ended = _track_family(homotopy, table, start, n, tolerance, projective=retrack is not None)
    if retrack is None and (ended.status == PATH_FAILED).any():
        ended = _retry_failed(m, theta, ended, float(tol["path_tolerance"]), info)
    reached = ended.status == PATH_REACHED
    with np.errstate(invalid="ignore"):
        end_size = np.abs(ended.z).max(-1)  # each end's size: its typical root size, and far ends
    typical = typical_root_size(end_size.reshape(n, paths), reached.reshape(n, paths))
    z, imaginary = phase_normalised(ended.z, list(homotopy.homogeneous), np.repeat(typical, paths))
    real = reached & (imaginary < tol["real_endpoint"])
    near = reached & ~real & (imaginary < tol["near_real_endpoint"])
    kinds = m.manifest.abi.root_kinds
    kind = np.select(
        [real, near, reached, ended.status == PATH_DIVERGED],
        [kinds.index("simple"), kinds.index("near_real"), kinds.index("complex"), kinds.index("at_infinity")],
        kinds.index("failed"),
    )
    outcome = np.select(
        [real | near, reached, ended.status == PATH_DIVERGED],
        [-1, codes["complex"], codes["at_infinity"]],
        codes["path_failed"],
    )
    candidate = real | near
    q = np.full((n * paths, len(m.passive_names)), np.nan)
    if candidate.any():
        with np.errstate(all="ignore"):
            q[candidate] = m.backend.call(f"{info.method}_passive", z[candidate].real, m.params)["passive"]
    pose = np.tile(np.eye(4), (n * paths, 1, 1))
    if candidate.any():
        theta_paths = np.repeat(theta, paths, axis=0)[candidate]
        with np.errstate(all="ignore"):
            pose[candidate] = m.backend.call("platform_pose", theta_paths, np.nan_to_num(q[candidate]), m.params)[
                "pose"
            ]
    shape = (n, paths)
    failed = (ended.status == PATH_FAILED).reshape(shape)
    endpoints = np.where(reached[:, None], ended.z, np.nan)
    size = np.where(ended.status == PATH_DIVERGED, np.inf, end_size)
    return {
        # how large each path's end is, however it ended (inf: diverged): ``FAR_ROOT``
        "end_size": np.nan_to_num(size, nan=0.0).reshape(shape),
        "endpoints": np.stack([endpoints.real, endpoints.imag], axis=-1).reshape(shape + (-1, 2)),
        "pose": pose.reshape(shape + (4, 4)),
        "q": q.reshape(shape + (-1,)),
        "outcome": outcome.reshape(shape).astype(np.int32),
        "root": imaginary.reshape(shape),
        "kind": kind.reshape(shape).astype(np.int32),
        "has_root": np.ones(shape, bool),
        # the paths of an input whose solution set is not isolated end singular or fail
        "degenerate": failed.any(-1),
        "real_roots": real.reshape(shape).sum(-1),
        "near_roots": near.reshape(shape).sum(-1),
        "at_infinity": (ended.status == PATH_DIVERGED).reshape(shape).sum(-1),
    }


def first_instances(m: Mechanism, info: Forward, theta: Array) -> np.ndarray:
    """(inputs,) the start instance each input's paths begin at: ``START_NEAR`` (the manifest's
    ``near``) where its family values lie near the home's
    (``parakin.solvers.path_tracking.near_home``), else ``START_FIRST``; as the generated C
    driver chooses."""
    homotopy = info.homotopy
    assert homotopy is not None
    if homotopy.near is None:
        return np.full(theta.shape[0], START_FIRST)
    return _first_of(homotopy, *_family(m, info, theta))


def _first_of(homotopy: Homotopy, free: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """``first_instances`` from the inputs' family values (``_family``)."""
    near = homotopy.near
    if near is None:
        return np.full(free.shape[0], START_FIRST)
    close = near_home(near.center, near.scale, near.radius, free, angles, homotopy.circle_constants)
    return np.where(close, START_NEAR, START_FIRST)


def _starts(homotopy: Homotopy) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    """(instance, solutions) of each start, indexed by START_*; a package without a start near
    home repeats its first there (no input takes it: ``first_instances``)."""
    near = homotopy.near
    return (
        (homotopy.start_instance, homotopy.start),
        (homotopy.alternative_instance, homotopy.alternative),
        (near.instance, near.solutions) if near is not None else (homotopy.start_instance, homotopy.start),
    )


def _start_rows(homotopy: Homotopy, instance: np.ndarray) -> np.ndarray:
    """The start solutions (inputs, paths, unknowns) of each input's start ``instance`` (START_*)."""
    solutions = [pair[1] for pair in _starts(homotopy)]
    if (instance == instance[:1]).all():
        return np.broadcast_to(
            solutions[int(instance[0]) if instance.size else START_FIRST], (instance.size,) + homotopy.start.shape
        )
    return np.stack([solutions[int(k)] for k in instance])


def _track_family(
    homotopy: Homotopy, table: np.ndarray, start: np.ndarray, count: int, tolerance: float, projective: bool = False
) -> Paths:
    """The paths of ``count`` inputs from ``start`` (inputs, paths, unknowns): one of each
    symmetric pair when the family has a sign symmetry
    (``parakin.solvers.path_tracking.track_symmetric``), as the generated C driver does;
    ``projective``: tracked on the homogenised family and returned as affine endpoints. The
    pairs are the first start's: every start instance keeps its order."""
    pairs = path_pairs(homotopy.exponents, homotopy.equation, homotopy.start)
    if projective:
        family = projective_family(homotopy.exponents, homotopy.equation, pairs)
        extended = projective_table(family, table)

        def on_patch(per_input: int):
            return family_system(extended, family.exponents, family.equation, per_input)

        return to_affine(track_symmetric(on_patch, to_projective(family, start), count, tolerance, family.pairs))

    def system_for(per_input: int):
        return family_system(table, homotopy.exponents, homotopy.equation, per_input)

    return track_symmetric(system_for, start, count, tolerance, pairs)


def _track_some(
    homotopy: Homotopy, table: np.ndarray, start: np.ndarray, redo: np.ndarray, ends: np.ndarray, tolerance: float
) -> Paths:
    """The paths ``redo`` (inputs, paths) of the inputs of ``table`` tracked again in projective
    space from ``start`` (inputs, paths, unknowns), the others reached at their earlier ``ends`` (inputs, paths, unknowns):
    one per symmetric pair (``redo`` is closed under partners), each path with its own input's
    coefficients, ``RETRACK_PATHS`` at a time."""
    count, paths, size = ends.shape
    pairs = path_pairs(homotopy.exponents, homotopy.equation, homotopy.start)
    redo = redo | redo[:, pairs.partner] if pairs is not None else redo.copy()
    tracked = redo.copy()
    if pairs is not None:
        tracked[:, pairs.second] = False
    family = projective_family(homotopy.exponents, homotopy.equation, pairs)
    extended = projective_table(family, table)
    z = np.array(ends, dtype=complex)
    status = np.where(np.isfinite(z).all(-1), PATH_REACHED, PATH_FAILED).astype(np.int32)
    rows, columns = np.nonzero(tracked)
    every = family_system(extended, family.exponents, family.equation, 1)  # path index = its input
    for a in range(0, rows.size, RETRACK_PATHS):
        r, c = rows[a : a + RETRACK_PATHS], columns[a : a + RETRACK_PATHS]

        def system(index: np.ndarray, z: np.ndarray, s: np.ndarray, r: np.ndarray = r):
            return every(r[index], z, s)

        again = to_affine(track(system, to_projective(family, start[r, c]), tolerance))
        z[r, c], status[r, c] = again.z, again.status
    if pairs is not None:  # the partner of a path tracked ends at the image of its end
        source = np.full(paths, -1)
        source[pairs.second] = pairs.first
        images = np.nonzero(redo & (source >= 0)[None, :])
        z[images] = z[images[0], source[images[1]]] * pairs.flip
        status[images] = status[images[0], source[images[1]]]
    steps = np.zeros(count * paths, dtype=np.int32)
    return Paths(z.reshape(-1, size), status.reshape(-1), steps, np.full(count * paths, np.nan))


def toward_infinity(m: Mechanism, info: Forward, theta: Array, paths: np.ndarray) -> np.ndarray:
    """Per input and path (inputs, P): which of the paths ``paths`` (inputs, P) of the inputs
    ``theta`` (inputs, n_a) head to infinity: tracked in projective space from the first start
    (``parakin.solvers.projective``) to each s of ``PROBE_S`` in turn, their w relative to the
    point falls by ``PROBE_FALL`` or more from each to the next. Evidence, not a proof (a path
    toward a finite root of size beyond 1e5 could show the same): it decides only where work
    stops and what the verdict says of the paths (``certified_modes``); it certifies nothing.

    Parameters
    ----------
    m : Mechanism
        The mechanism (its own length scale).
    info : Forward
        A homotopy's method.
    theta : ndarray, shape (inputs, n_a)
        Actuated values, m or rad.
    paths : ndarray of bool, shape (inputs, P)
        The paths to follow.

    Returns
    -------
    ndarray of bool, shape (inputs, P)
        True where the path heads to infinity; False elsewhere and where not asked.
    """
    homotopy = info.homotopy
    assert homotopy is not None
    heading = np.zeros(paths.shape, dtype=bool)
    rows, columns = np.nonzero(paths)
    if not rows.size:
        return heading
    family = projective_family(homotopy.exponents, homotopy.equation, path_pairs(
        homotopy.exponents, homotopy.equation, homotopy.start))  # fmt: skip
    free, angles = _family(m, info, theta)
    instance = _first_of(homotopy, free, angles)  # each input's paths from where they began
    every = family_system(
        projective_table(family, _table(m, info, free, angles, instance)), family.exponents, family.equation, 1
    )
    tolerance = float(_settings(m)["path_tolerance"])
    z = to_projective(family, _start_rows(homotopy, instance)[rows, columns])
    alive = np.ones(rows.size, dtype=bool)
    size = np.full((len(PROBE_S), rows.size), np.nan)
    high = 1.0
    for k, low in enumerate(PROBE_S):
        live = np.nonzero(alive)[0]
        if not live.size:
            break

        def system(index: np.ndarray, point: np.ndarray, s: np.ndarray, r=rows[live], a=low, b=high):
            value, jacobian, rate = every(r[index], point, a + (b - a) * s)  # s in [0, 1] onto [a, b]
            return value, jacobian, rate * (b - a)

        ended = track(system, z[live], tolerance)
        z[live], alive[live] = ended.z, ended.status == PATH_REACHED
        size[k, live] = np.abs(ended.z[:, -1]) / np.abs(ended.z).max(-1)
        high = low
    with np.errstate(invalid="ignore"):
        falls = (size[1:] * PROBE_FALL <= size[:-1]).all(0)
    heading[rows, columns] = alive & falls
    return heading


def suspect_paths(endpoints: np.ndarray, unique: np.ndarray) -> np.ndarray:
    """Per input and path (inputs, paths): the paths worth tracking again, those whose end no
    certified box holds or that ended near another path's end (within ``TWIN`` of its size:
    certified boxes are at most ``certify.NEAR`` wide, so two paths on one root are this close):
    a path that jumped ends on another's root. Only a choice of work; the certificate decides."""
    z = endpoints[..., 0] + 1j * endpoints[..., 1]
    finite = np.asarray(np.isfinite(z).all(-1))
    z = np.where(finite[..., None], z, np.inf)
    scale = 1.0 + np.abs(z).max(-1)
    distance = np.zeros(z.shape[:2] + z.shape[1:2])
    with np.errstate(invalid="ignore"):
        for k in range(z.shape[-1]):  # unknown by unknown: (inputs, paths, paths) at a time
            distance = np.maximum(distance, np.abs(z[:, :, None, k] - z[:, None, :, k]))
        distance /= scale[:, :, None]
    twin = (distance <= TWIN) & ~np.eye(z.shape[1], dtype=bool)  # inf - inf is NaN: not a twin
    return ~unique | twin.any(-1) | ~finite


def _monomials(m: Mechanism, info: Forward):
    def evaluate(values: np.ndarray) -> np.ndarray:
        out = m.backend.call(
            f"{info.method}_monomials", np.ascontiguousarray(values.real), np.ascontiguousarray(values.imag)
        )
        return out["re"] + 1j * out["im"]

    return evaluate


def _target_coefficients(m: Mechanism, info: Forward, free: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """The coefficients (inputs, terms) of the system at the inputs themselves, angles as (cos,
    sin, 1): real but for a patch of homogeneous unknowns. The kernel's real input is written in
    place (free values, then (cos, sin, 1) per angle) and its imaginary input is one shared row of
    zeros; each entry is x + 0.0 (a -0.0 becomes 0.0, as x + 0j would make it)."""
    rows, size, circles = free.shape[0], free.shape[1], angles.shape[1]
    real = np.empty((rows, size + 3 * circles))
    with np.errstate(all="ignore"):
        np.add(free, 0.0, out=real[:, :size])
        np.cos(angles, out=real[:, size::3])
        np.sin(angles, out=real[:, size + 1 :: 3])
        np.add(real[:, size:], 0.0, out=real[:, size:])
        real[:, size + 2 :: 3] = 1.0
        out = m.backend.call(f"{info.method}_monomials", real, _zeros(real.shape[1]))
        return out["re"] + 1j * out["im"]


def _certificate_system(m: Mechanism, info: Forward, theta: Array) -> np.ndarray:
    """The target system's term coefficients at the inputs (n, T) complex: ``_target_coefficients``
    at ``_family``'s values, or the same numbers in one foreign call where the compiled package
    has them for this method (``NAME_target_coefficients``: the same kernels, its (re, im) joined
    here as ``_target_coefficients`` joins them)."""
    targets = getattr(m.backend, "target_coefficients", None)
    homotopy = info.homotopy
    if targets is None or homotopy is None or info is not m.capabilities.forward:
        return _target_coefficients(m, info, *_family(m, info, theta))
    theta = np.ascontiguousarray(theta, dtype=float)
    params = np.ascontiguousarray(m.params, dtype=float)
    out = np.empty((theta.shape[0], homotopy.exponents.shape[0], 2))
    targets(theta.shape[0], theta.ctypes.data, theta.shape[-1], params.ctypes.data, out.ctypes.data)
    return out[..., 0] + 1j * out[..., 1]


@functools.cache
def _zeros(size: int) -> np.ndarray:
    """Zeros (size,), read only: shared by every call (a kernel input shared by every row)."""
    zeros = np.zeros(size)
    zeros.flags.writeable = False
    return zeros


def _family(m: Mechanism, info: Forward, theta: Array) -> tuple[np.ndarray, np.ndarray]:
    """The family's free values and angles at the inputs (the generated ``*_family`` kernel)."""
    homotopy = info.homotopy
    assert homotopy is not None
    values = m.backend.call(f"{info.method}_family", theta, m.params)
    return values["free"][:, : len(homotopy.free)], values["angles"][:, : len(homotopy.circles)]


def _path_table(m: Mechanism, info: Forward, theta: Array, which: int | np.ndarray) -> np.ndarray:
    """Coefficients in s (inputs, powers, terms) from the start instance ``which`` (START_*), one
    for every input or one per input (an array)."""
    return _table(m, info, *_family(m, info, theta), which)


def _table(m: Mechanism, info: Forward, free: np.ndarray, angles: np.ndarray, which: int | np.ndarray) -> np.ndarray:
    """``_path_table`` from the inputs' family values (``_family``)."""
    homotopy = info.homotopy
    assert homotopy is not None
    which = np.broadcast_to(np.asarray(which), (free.shape[0],))
    instances = [pair[0] for pair in _starts(homotopy)]
    monomials = _monomials(m, info)
    table = np.empty((free.shape[0], homotopy.powers, homotopy.exponents.shape[0]), dtype=complex)
    for k in np.unique(which):
        rows = which == k
        with np.errstate(all="ignore"):
            table[rows] = path_coefficients(
                monomials, free[rows], angles[rows], instances[k], homotopy.powers, homotopy.circle_constants
            )
    return table


def _certified_group(homotopy: Homotopy) -> list[int] | None:
    """The unknowns the certificate treats as one projective group (``certify.homogeneous_group``)."""
    if not homotopy.homogeneous or homotopy.patch_equation is None:
        return None
    return homogeneous_group(homotopy.exponents, homotopy.equation, homotopy.patch_equation, list(homotopy.homogeneous))


class PathCertificate(NamedTuple):
    """Per input of a flat batch (n,): ``certified`` the distinct roots certified (clusters of
    overlapping Krawczyk boxes, a lower bound on the roots; complete where it equals the root
    count); per path (n, P): ``unique`` its box holds exactly one root, ``real`` +1 that root is
    certified real, -1 certified non-real, 0 undecided; ``centre`` (n, P, n_z) and ``radii``
    (n, P, n_z) the box (NaN where not ``unique``); ``labels`` (n, P) the cluster of overlapping
    boxes each path's belongs to, by its first member (-1 where not ``unique``:
    ``certify.cluster_labels``), kept with the boxes wherever they change (``_recount``)."""

    certified: np.ndarray
    unique: np.ndarray
    real: np.ndarray
    centre: np.ndarray
    radii: np.ndarray
    labels: np.ndarray

    def rows(self, index: np.ndarray) -> PathCertificate:
        return PathCertificate(*(value[index] for value in self))


def _joined(parts: list[PathCertificate]) -> PathCertificate:
    return PathCertificate(*(np.concatenate(values) for values in zip(*parts, strict=True)))


def certify(m: Mechanism, info: Forward, theta: Array, endpoints: np.ndarray, exact: bool = False) -> PathCertificate:
    """``certify_inputs`` in chunks: the Krawczyk tables take about a megabyte per input of a
    chunk, so memory stays bounded whatever the batch (``CERTIFY_CHUNK`` inputs in all, shared
    by the ``threads()`` that certify chunks side by side; NumPy releases the GIL in the array
    work). Each input's certificate is its own: the same whatever the chunks."""
    workers = threads()
    size = max(1, CERTIFY_CHUNK // workers)
    if theta.shape[0] <= size:  # one chunk (a control loop's one input)
        return certify_inputs(m, info, theta, endpoints, exact)

    def chunk(a: int) -> PathCertificate:
        return certify_inputs(m, info, theta[a : a + size], endpoints[a : a + size], exact)

    starts = range(0, theta.shape[0], size)
    if workers > 1 and len(starts) > 1:
        with ThreadPoolExecutor(min(workers, len(starts))) as pool:
            parts = list(pool.map(chunk, starts))
    else:
        parts = [chunk(a) for a in starts]
    if len(parts) != 1:
        return _joined(parts) if parts else certify_inputs(m, info, theta, endpoints, exact)
    return parts[0]


def certify_inputs(
    m: Mechanism, info: Forward, theta: Array, endpoints: np.ndarray, exact: bool = False
) -> PathCertificate:
    """Per input (flat batch): how many distinct roots of the system at the inputs are certified
    by Krawczyk boxes around the paths' endpoints, and per path whether its box holds exactly one
    root and whether that root is real (``parakin.solvers.certify``); the answer is complete where
    the first equals the root count. With ``exact``, the finite endpoints of incomplete inputs
    that double precision cannot certify, and the certified roots whose realness it cannot
    decide, are tested again in exact dyadic arithmetic (``parakin.solvers.exact_certify``)."""
    homotopy = info.homotopy
    assert homotopy is not None
    coefficients = _certificate_system(m, info, theta)
    roots = endpoints[..., 0] + 1j * endpoints[..., 1]
    pairs = _fixed("pairs", homotopy, lambda: path_pairs(homotopy.exponents, homotopy.equation, homotopy.start))
    paired = _paired_ends(pairs, roots)
    result = _certify_endpoints(homotopy, coefficients, roots, pairs, paired, m.backend)
    # the certificate's arrays are its own (fresh from the test): updated in place from here
    counts, unique, real = result.certified_distinct.copy(), result.unique, result.real
    centre, radii, labels = result.center, result.radii, result.labels
    if labels is None:  # a certificate without its clusters' labels
        labels = cluster_labels(centre, np.where(unique[..., None], radii, 0.0), unique, m.backend)[0]
    if not exact or homotopy.root_count is None:
        return PathCertificate(counts, unique, real, centre, radii, labels)
    undecided = unique & (real == 0)
    if counts.size == 1 and counts[0] >= homotopy.root_count.count and not undecided.any():
        return PathCertificate(counts, unique, real, centre, radii, labels)  # one input, complete and decided
    short = counts < homotopy.root_count.count
    again = np.nonzero(short | undecided.any(-1))[0]
    if not again.size:  # every input complete and decided (the usual case)
        return PathCertificate(counts, unique, real, centre, radii, labels)
    finite = np.isfinite(roots).all(-1) & np.isfinite(coefficients).all(-1)[:, None]
    source = np.full(roots.shape[:2], -1)  # the earlier path whose end this one's is the image of
    if pairs is not None:
        source[np.ix_(np.nonzero(paired)[0], pairs.second)] = pairs.first
    for i in again:
        retry = (~unique[i] & finite[i] & short[i]) | undecided[i]
        for p in np.nonzero(retry)[0]:
            if pairs is not None and source[i, p] >= 0:  # the image of an earlier path's end: its box's image
                q = source[i, p]
                unique[i, p], real[i, p] = unique[i, q], real[i, q]
                centre[i, p], radii[i, p] = centre[i, q] * pairs.flip, radii[i, q]
                continue
            start = centre[i, p] if unique[i, p] else roots[i, p]
            if unique[i, p] and homotopy.patch_equation is not None:  # decided in the real chart
                real[i, p] = realness_in_chart(
                    coefficients[i], homotopy.exponents, homotopy.equation, homotopy.patch_equation,
                    _certified_group(homotopy) or [], start,
                )  # fmt: skip
                continue
            exact_box = certify_root_exactly(
                coefficients[i], homotopy.exponents, homotopy.equation, start, homotopy.patch_equation is None
            )
            if exact_box.unique and not unique[i, p]:
                unique[i, p], centre[i, p], radii[i, p] = True, exact_box.center, exact_box.radius
                real[i, p] = exact_box.real
            elif exact_box.unique and (abs(exact_box.center - centre[i, p]) + exact_box.radius <= radii[i, p]).all():
                # the same root: the exact polydisc lies inside the box, coordinate by coordinate
                # (each box radius is in its coordinate's own size), and the box holds one root
                real[i, p] = exact_box.real
            elif exact_box.unique and exact_box.real != 0:
                # a box narrower than the exact polydisc in some coordinate (one measured in a
                # tiny typical size): the polydisc, which holds exactly one root as well, is this
                # path's box in its place, with its decided realness (the clusters are counted
                # again below: a lower bound on the distinct roots whichever box each path has)
                centre[i, p], radii[i, p], real[i, p] = exact_box.center, exact_box.radius, exact_box.real
        labels[i] = cluster_labels(centre[i], np.where(unique[i][:, None], radii[i], 0.0), unique[i], m.backend)[0]
        counts[i] = int((labels[i] == np.arange(labels.shape[-1])).sum())
    return PathCertificate(counts, unique, real, centre, radii, labels)


def _configuration(m: Mechanism, info: Forward, theta: Array, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Passive values (k, n_p) and poses (k, 4, 4) of real roots z (k, n_z) of the family at the
    inputs ``theta`` (k, n_a), from the generated kernels (identity where a pose is undefined)."""
    with np.errstate(all="ignore"):
        q = m.backend.call(f"{info.method}_passive", np.ascontiguousarray(z), m.params)["passive"]
        pose = m.backend.call("platform_pose", theta, q if np.isfinite(q).all() else np.nan_to_num(q), m.params)["pose"]
    defined = np.asarray(np.isfinite(pose).all((-2, -1)))
    return q, pose if defined.all() else np.where(defined[:, None, None], pose, np.eye(4))


#: two modes whose rotations differ by at most this, and their positions by at most this times
#: the size of the input's workspace (its modes' largest position), are one pose
SAME_POSE = 1e-9


def _same_pose(outcome: np.ndarray, poses: np.ndarray, mode: int, duplicate: int) -> None:
    """Mark, in slot order, each mode (n, slots) whose pose (n, slots, 4, 4) repeats an earlier
    mode's as ``duplicate``, in place. Distinct certified roots can be one pose: a formulation's
    second name for it (a quaternion's q -> -q, Euler angles (a + pi, pi - b, c + pi)), which
    gives the same pose to rounding; distinct poses of a near-fold differ by far more.

    Every pair of modes of an input is compared at once (``_pose_pairs``); slot order then only
    matters among the few slots that have a pair, walked in order as before (a slot marked a
    repeat is no longer an earlier mode)."""
    if outcome.shape[0] == 1:  # one input (a control loop's call): over its modes only
        _same_pose_one(outcome[0], poses[0], mode, duplicate)
        return
    valid = outcome == mode
    rows = np.nonzero(valid.sum(-1) >= 2)[0]  # an input with one mode has no repeat
    if not rows.size:
        return
    for a in range(0, rows.size, SAME_POSE_ROWS):
        part = rows[a : a + SAME_POSE_ROWS]
        same = _pose_pairs(poses[part], valid[part])  # (k, slot, earlier slot), modes only
        pairs = np.count_nonzero(same)
        if not pairs:
            continue
        if pairs <= SAME_POSE_PAIRS:  # the pairs one by one, in slot order (each slot's earlier are settled)
            local = outcome[part].tolist()
            for row, slot, earlier in zip(*(index.tolist() for index in np.nonzero(same)), strict=True):
                line = local[row]
                if line[slot] == mode and line[earlier] == mode:
                    line[slot] = duplicate
            outcome[part] = local
            continue
        block = outcome[part]
        for s in np.nonzero(same.any((0, 2)))[0]:
            earlier = block[:, :s] == mode
            repeat = (block[:, s] == mode) & (same[:, s, :s] & earlier).any(-1)
            block[:, s] = np.where(repeat, duplicate, block[:, s])
        outcome[part] = block


def _same_pose_one(line: np.ndarray, poses: np.ndarray, mode: int, duplicate: int) -> None:
    """``_same_pose`` for one input's outcomes (slots,) and poses (slots, 4, 4), in place: the
    pairs of its modes compared as ``_pose_pairs`` compares them, walked in slot order."""
    slots = np.nonzero(line == mode)[0]
    if slots.size < 2:
        return
    # positions first, over every pair, coordinate by coordinate (3, k, k: a maximum over whole
    # planes, not over a short trailing axis); the rotations only of the pairs whose positions
    # agree (most have none: Stewart's 40 modes)
    position = np.ascontiguousarray(poses[slots, :3, 3].T)
    largest = np.abs(position).max()
    moved = np.abs(position[:, :, None] - position[:, None, :]).max(0)
    later, earlier = np.nonzero(_lower_triangle(slots.size) & (moved <= SAME_POSE * largest))
    if not later.size:
        return
    turned = np.abs(poses[slots[later], :3, :3] - poses[slots[earlier], :3, :3]).max((-2, -1))
    chosen = turned <= SAME_POSE
    for a, b in zip(slots[later[chosen]].tolist(), slots[earlier[chosen]].tolist(), strict=True):
        if line[a] == mode and line[b] == mode:
            line[a] = duplicate


@functools.cache
def _lower_triangle(size: int) -> np.ndarray:
    """The pairs (later, earlier) of ``size`` slots, earlier < later: (size, size), read only."""
    tri = np.tri(size, k=-1, dtype=bool)
    tri.flags.writeable = False
    return tri


#: inputs whose pairs of slots ``_same_pose`` compares at once (temporaries k x slots x slots x 3)
SAME_POSE_ROWS = 64
#: pairs of one pose walked one by one in Python; more (a degenerate batch) slot by slot in NumPy
SAME_POSE_PAIRS = 256


def _pose_pairs(poses: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """Per input (k,) and pair of slots (s, t), t < s, both modes (``valid`` (k, slots)): whether
    their poses (k, slots, 4, 4) are one (``SAME_POSE``: rotations within it, positions within it
    times the largest position of the input's modes). Positions first, over every pair (the pose
    entries lead the temporaries: maxima over whole planes, not over short trailing axes); the
    rotations only of the pairs whose positions agree."""
    slots = valid.shape[-1]
    position = np.ascontiguousarray(np.moveaxis(poses[..., :3, 3], -1, 0))  # (3, k, slots)
    largest = np.where(valid, np.abs(position), 0.0).max(0).max(-1)
    moved = np.abs(position[..., :, None] - position[..., None, :]).max(0)  # (k, slots, slots)
    pair = valid[:, :, None] & valid[:, None, :] & np.tri(slots, k=-1, dtype=bool)
    same = pair & (moved <= SAME_POSE * largest[:, None, None])
    if same.any():
        i, s, t = np.nonzero(same)
        rotation = np.abs(poses[i, s, :3, :3] - poses[i, t, :3, :3]).max((-2, -1))
        same[i, s, t] = rotation <= SAME_POSE
    return same


def _real_centres(centres: np.ndarray, homogeneous: tuple[int, ...] | list[int]) -> np.ndarray:
    """The real parts of certified centres (k, n_z), each first scaled, where the family has a
    homogeneous group, so that its largest homogeneous entry is real and positive: the real
    point of ``path_tracking.phase_normalised``, without its measure of the imaginary part."""
    return real_phase(centres, homogeneous).real


def _repeats_partner(
    valid: np.ndarray, poses: np.ndarray, rows: np.ndarray, columns: np.ndarray, pose: np.ndarray, partner: np.ndarray
) -> np.ndarray:
    """Per candidate (k,) of input ``rows`` (k,) in slot ``columns`` (k,) with pose ``pose`` (k, 4,
    4): whether its partner slot (``partner`` (slots,), a sign symmetry's pairs of paths) is an
    earlier mode (``valid`` (n, slots)) of its input with that pose, compared as
    ``_repeats_earlier_mode`` compares a candidate with each earlier mode (the same numbers): a
    True here is a True there; a False says nothing."""
    hint = partner[columns]
    found = (hint < columns) & valid[rows, hint]
    if not found.any():
        return found
    if valid.shape[0] == 1:  # one input: its size once, its poses without the row index
        sizes = np.where(valid[0, :, None], np.abs(poses[0, :, :3, 3]), 0.0).max()
        apart = np.abs(poses[0][hint] - pose)  # (k, 4, 4): each entry's difference, as below
    else:
        sizes = np.where(valid[rows][..., None], np.abs(poses[rows, :, :3, 3]), 0.0).max((-2, -1))
        apart = np.abs(poses[rows, hint] - pose)
    largest = np.maximum(sizes, np.abs(pose[:, :3, 3]).max(-1))
    moved = apart[:, :3, 3].T  # (3, k): a maximum of three, NaN-propagating
    close = np.maximum(np.maximum(moved[0], moved[1]), moved[2]) <= SAME_POSE * largest
    turned = apart[:, :3, :3].reshape(rows.size, 9).max(-1)
    return found & close & (turned <= SAME_POSE)


def _repeats_earlier_mode(
    valid: np.ndarray, poses: np.ndarray, rows: np.ndarray, columns: np.ndarray, pose: np.ndarray
) -> np.ndarray:
    """Per candidate (k,) of input ``rows`` (k,) in slot ``columns`` (k,) with pose ``pose`` (k, 4, 4):
    whether a mode (``valid`` (n, slots)) in an earlier slot of its input has that pose
    (``SAME_POSE``, positions relative to the largest position of the input's modes and the
    candidate, as ``_pose_pairs``)."""
    found = np.zeros(rows.shape, dtype=bool)
    candidate, slot = np.nonzero(valid[rows] & (np.arange(valid.shape[-1]) < columns[:, None]))
    if not candidate.size:
        return found
    inputs = np.unique(rows) if valid.shape[0] > 1 else rows[:1]  # one input: row 0 (candidates exist)
    sizes = np.zeros(valid.shape[0])
    sizes[inputs] = np.where(valid[inputs][..., None], np.abs(poses[inputs, :, :3, 3]), 0.0).max((-2, -1))
    largest = np.maximum(sizes[rows], np.abs(pose[:, :3, 3]).max(-1))[candidate]
    # positions first, coordinate by coordinate (3, pairs); the rotations only of the pairs whose
    # positions agree
    moved = np.abs(poses[rows[candidate], slot, :3, 3] - pose[candidate, :3, 3]).T
    close = np.nonzero(np.maximum(np.maximum(moved[0], moved[1]), moved[2]) <= SAME_POSE * largest)[0]
    if close.size:
        rotation = poses[rows[candidate[close]], slot[close], :3, :3] - pose[candidate[close], :3, :3]
        turned = np.abs(rotation).reshape(close.size, 9).max(-1)
        found[candidate[close[turned <= SAME_POSE]]] = True
    return found


def _decided(
    m: Mechanism, cert: PathCertificate, outcome: np.ndarray, kind: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``reconcile``'s decision by the certificate (n inputs, P slots), in place on ``outcome``
    and ``kind`` (n, P): certified roots grouped by overlapping boxes, each group real, non-real
    or undecided. Returns the slots (rows, columns) of the real roots the first pass did not
    settle (to settle again from their certified centres), and per input (n,) the real roots and
    the undecided ones."""
    codes, kinds = _codes(m), m.manifest.abi.root_kinds
    labels = cert.labels
    paths = labels.shape[-1]
    if (labels == np.where(cert.unique, np.arange(paths), -1)).all():  # no two boxes overlap
        first = cert.unique
        real = first & (cert.real == 1)
        nonreal = first & (cert.real == -1)
        undecided = first & ~real & ~nonreal
        in_real, in_nonreal, in_undecided = real, nonreal, undecided
    else:
        member = (labels[..., :, None] == np.arange(paths)) & cert.unique[..., None]  # (n, path, group)
        positive = (member & (cert.real == 1)[..., None]).any(-2)
        negative = (member & (cert.real == -1)[..., None]).any(-2)
        first = labels == np.arange(paths)
        real = first & positive & ~negative
        nonreal = first & negative & ~positive
        undecided = first & ~real & ~nonreal
        group = np.where(labels >= 0, labels, 0)
        in_real = np.take_along_axis(real, group, -1) & cert.unique
        in_nonreal = np.take_along_axis(nonreal, group, -1) & cert.unique
        in_undecided = np.take_along_axis(undecided, group, -1) & cert.unique
    mode = codes["mode"]
    kept = (
        (outcome == mode)
        | (outcome == codes["outside_limits"])
        | (outcome == codes["false_closure"])
        | (outcome == codes["input_independent"])
    )
    # a real root the first pass did not settle (called complex, not closed, a pose repeat): again
    # from its certified centre
    redo = real & ~kept
    outcome[~cert.unique & (outcome == mode)] = codes["uncertified"]
    outcome[in_nonreal] = codes["complex"]
    outcome[in_undecided] = codes["uncertified"]
    if in_real is not real:  # an overlapping box's root is its cluster's first's duplicate
        outcome[in_real & ~first] = codes["duplicate"]
    kind[in_real] = kinds.index("simple")
    kind[in_nonreal] = kinds.index("complex")
    kind[in_undecided] = kinds.index("near_real")
    rows, columns = np.nonzero(redo)
    return rows, columns, real.sum(-1), undecided.sum(-1)


def _decided_one(
    m: Mechanism, cert: PathCertificate, outcome: np.ndarray, kind: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """``_decided`` for one input (``outcome`` and ``kind`` (1, P)) whose certified boxes do not
    overlap (each is its own group), slot by slot in plain Python (a few dozen slots: cheaper
    than a score of array operations on them); None where boxes overlap (``_decided`` then)."""
    unique, real, labels = cert.unique[0].tolist(), cert.real[0].tolist(), cert.labels[0].tolist()
    if labels != [p if alone else -1 for p, alone in enumerate(unique)]:
        return None
    mode, uncertified, complex_code, kept, simple, complex_kind, near_real = _fixed(
        "decision codes", m.manifest, lambda: _decision_codes(m)
    )
    before, kinds_before = outcome[0].tolist(), kind[0].tolist()
    line, kind_line = before.copy(), kinds_before.copy()
    redo, real_roots, undecided = [], 0, 0
    for p, alone in enumerate(unique):
        if not alone:  # no box holds this slot's root alone: no mode
            if line[p] == mode:
                line[p] = uncertified
        elif real[p] == 1:  # a real root: a mode unless a check rejects it (settled again if the first pass did not)
            real_roots += 1
            kind_line[p] = simple
            if line[p] not in kept:
                redo.append(p)
        elif real[p] == -1:
            line[p], kind_line[p] = complex_code, complex_kind
        else:  # realness undecided
            undecided += 1
            line[p], kind_line[p] = uncertified, near_real
    if line != before:  # (as a rule the first pass's outcomes and kinds stand)
        outcome[0] = line
    if kind_line != kinds_before:
        kind[0] = kind_line
    columns = np.array(redo, dtype=np.intp)
    return np.zeros(columns.size, dtype=np.intp), columns, np.array([real_roots]), np.array([undecided])


def _decision_codes(m: Mechanism) -> tuple[int, int, int, tuple[int, ...], int, int, int]:
    """The outcome and root-kind codes ``_decided_one`` writes and reads (fixed per package)."""
    codes, kinds = _codes(m), m.manifest.abi.root_kinds
    kept = (codes["mode"], codes["outside_limits"], codes["false_closure"], codes["input_independent"])
    return (
        codes["mode"], codes["uncertified"], codes["complex"], kept,
        kinds.index("simple"), kinds.index("complex"), kinds.index("near_real"),
    )  # fmt: skip


def reconcile(m: Mechanism, info: Forward, theta: Array, out: dict[str, np.ndarray], cert: PathCertificate) -> dict:
    """The modes of a homotopy's inputs decided by the certificate, not by thresholds on the
    endpoints: certified roots are grouped by overlapping boxes (and, where the family's sign
    symmetry keeps the pose, their images: one mode); a group whose root is certified real is
    a mode unless a physical check rejects it (it is settled again from its certified centre if
    the first pass had rejected its endpoint), one certified non-real is "complex" (a near-real
    pair is never a mode), one undecided is "uncertified", and so is a real-looking endpoint
    that no box holds alone. Returns the updated arrays and ``undecided`` (n,): certified roots
    whose realness is not decided (the input is then not complete)."""
    homotopy = info.homotopy
    assert homotopy is not None
    codes = _codes(m)
    n = cert.unique.shape[0]
    # the arrays changed here are copies (the caller's stay as they were); the others are shared
    out = dict(out, outcome=out["outcome"].copy(), root_kind=out["root_kind"].copy())
    outcome, kind = out["outcome"], out["root_kind"]
    mode = codes["mode"]
    decided = _decided_one(m, cert, outcome, kind) if n == 1 else None
    if decided is not None:  # one input whose boxes do not overlap (a control loop's call)
        rows, columns, real_roots, undecided_count = decided
    else:
        rows, columns, real_roots, undecided_count = _decided(m, cert, outcome, kind)
    if rows.size:
        # one input: its actuated values shared by the candidates (the kernels read the one row)
        q, pose = _configuration(
            m,
            info,
            theta[0] if n == 1 else theta[rows],
            _real_centres(cert.centre[rows, columns], homotopy.homogeneous),
        )
        # a pose repeat of the first pass whose certified centre gives an earlier mode's pose
        # again (a formulation's second name for it: prs3's 16 of 32 roots) is that repeat:
        # polishing it again would only mark it a duplicate again
        duplicate = outcome[rows, columns] == codes["duplicate"]
        valid = outcome == mode
        pairs = _fixed("pairs", homotopy, lambda: path_pairs(homotopy.exponents, homotopy.equation, homotopy.start))
        if pairs is not None and pairs.partner.size == valid.shape[-1] and duplicate.any():
            # the earlier mode a repeat repeats is, as a rule, its path's partner's (q and -q):
            # that one pair first, every earlier mode only for the candidates it does not settle
            repeat = duplicate & _repeats_partner(valid, out["poses"], rows, columns, pose, pairs.partner)
            rest = duplicate & ~repeat
            if rest.any():
                repeat[rest] = _repeats_earlier_mode(valid, out["poses"], rows[rest], columns[rest], pose[rest])
        else:
            repeat = duplicate & _repeats_earlier_mode(valid, out["poses"], rows, columns, pose)
        if not repeat.all():
            rows, columns, q, pose = rows[~repeat], columns[~repeat], q[~repeat], pose[~repeat]
            # the arrays changed below are copies (the caller's stay as they were)
            out.update({key: out[key].copy() for key in ("passive", "poses", "residual", "conditioning")})
            q, pose, result, residual, conditioning = _check_candidates(
                m, theta[rows], q, pose, np.full(rows.size, -1, dtype=np.int32)
            )
            outcome[rows, columns] = np.where(result < 0, mode, result)
            out["passive"][rows, columns] = np.nan_to_num(q)
            out["poses"][rows, columns] = pose
            out["residual"][rows, columns] = residual
            out["conditioning"][rows, columns] = conditioning
    _same_pose(outcome, out["poses"], mode, codes["duplicate"])
    if n == 1:  # one input: its counts as plain numbers (the same arrays, a few operations fewer)
        defined = bool(np.isfinite(theta).all())
        out["count"] = np.array([np.count_nonzero(outcome == mode)], dtype=np.int32)
        out["real_roots"] = np.array([real_roots[0] if defined else out["real_roots"][0]], dtype=np.int32)
        out["near_roots"] = np.array([undecided_count[0] if defined else out["near_roots"][0]], dtype=np.int32)
        out["undecided"] = np.array([undecided_count[0]], dtype=np.int64)
        return out
    finite = np.isfinite(theta).all(-1)
    out["count"] = (outcome == mode).sum(-1).astype(np.int32)
    out["real_roots"] = np.where(finite, real_roots, out["real_roots"]).astype(np.int32)
    out["near_roots"] = np.where(finite, undecided_count, out["near_roots"]).astype(np.int32)
    out["undecided"] = undecided_count.astype(np.int64)
    return out


def certified_modes(
    m: Mechanism, info: Forward, theta: Array, out: dict[str, np.ndarray], exact: bool
) -> dict[str, np.ndarray]:
    """A homotopy's arrays ``out`` (flat batch ``theta``) certified and completed: every input's
    endpoints certified (``exact``: what double precision cannot certify or decide is tested in
    exact arithmetic, ``certify_inputs``); the complex conjugates of its certified non-real roots
    added (``add_conjugates``); an input still short of the root count is tracked again in
    projective space (its suspect paths, then ``RETRACKS``: every path from the second start
    instance, then the first), each run's certified roots merged into the input's slots that no
    certified box holds (``merge_roots``) until it is complete; then the modes are the certified
    real roots (``reconcile``). Never a silent loss: the certificate says what remains. An input
    whose missing roots are all accounted for, after the suspect paths' re-track, by paths that
    end far (``FAR_ROOT``) or head to infinity, at least one of them seen heading there
    (``toward_infinity``), is not tracked again: a degenerate input (a home, often), whose slots
    for those paths become roots at infinity (``_mark_at_infinity``); it stays not complete.

    Returns ``out`` updated, with ``certified`` (n,) the distinct certified roots,
    ``path_certified`` (n, P) the slots whose root has a box of its own, ``retracked`` (n,) and
    ``undecided`` (n,) (``reconcile``)."""
    homotopy = info.homotopy
    assert homotopy is not None and homotopy.root_count is not None
    if theta.shape[0] == 0:  # an empty batch: nothing to certify
        paths = out["endpoints"].shape[1]
        empty = {"certified": np.zeros(0, np.int64), "path_certified": np.zeros((0, paths), bool)}
        return out | empty | {"retracked": np.zeros(0, bool), "undecided": np.zeros(0, np.int64)}
    found = certify(m, info, theta, out["endpoints"], exact)
    count = homotopy.root_count.count
    retracked = np.zeros(theta.shape[0], dtype=bool)
    if theta.shape[0] == 1 and found.certified[0] >= count:  # one input, complete (the usual case)
        return reconcile(m, info, theta, out, found) | {
            "certified": found.certified, "path_certified": found.unique, "retracked": retracked
        }  # fmt: skip
    finite = np.isfinite(theta).all(-1)
    incomplete = np.nonzero((found.certified < count) & finite)[0]
    add_conjugates(m, info, theta, out, found, incomplete)
    # the inputs whose missing roots' paths were seen heading to infinity: searched no further
    far = np.zeros(theta.shape[0], dtype=bool)
    for instance in (None, *RETRACKS) if incomplete.size else ():  # none: every input complete
        short = np.nonzero((found.certified < count) & finite & ~far)[0]
        if not short.size:
            break
        retracked[short] = True
        if instance is None:  # the suspect paths only, projectively, from the same start
            ends = out["endpoints"][short]
            plan = Retrack(OWN_START, suspect_paths(ends, found.unique[short]), ends[..., 0] + 1j * ends[..., 1])
        else:
            plan = Retrack(instance)
        again = numpy_modes(m, theta[short], info, retrack=plan)
        second = certify(m, info, theta[short], again["endpoints"], exact)
        merge_roots(out, found, short, again, second)
        add_conjugates(m, info, theta, out, found, short[found.certified[short] < count])
        if instance is None and plan.redo is not None:  # the re-tracked paths that end far or head there
            # a far end counts whether or not a box holds it: an exact box there may hold a root
            # already counted (it adds no distinct root: rus6 at home, 8 of the 24 far ends)
            left = plan.redo & ~second.unique
            far_end = plan.redo & (again["end_size"] > FAR_ROOT)
            # a path the re-track took to a finite end is no path toward infinity: only failed ones are probed
            open_paths = left & ~far_end & (again["root_kind"] == m.manifest.abi.root_kinds.index("failed"))
            could = found.certified[short] + left.sum(-1) >= count  # the probe could account for all
            probed = toward_infinity(m, info, theta[short], open_paths & could[:, None])
            heading = far_end | probed
            # only paths seen heading to infinity stop the work: a far end alone may be a large
            # finite root (rus6 has roots of size 1e7 at ordinary inputs) that a later run certifies
            explained = (found.certified[short] + heading.sum(-1) >= count) & probed.any(-1)
            far[short] = explained
            _mark_at_infinity(m, out, found, short[explained], heading[explained])
    if (
        incomplete.size and retracked.any()
    ):  # marked at infinity, or a slot whose path escaped may now hold a certified root
        at_infinity = out["root_kind"][retracked] == m.manifest.abi.root_kinds.index("at_infinity")
        out["at_infinity"][retracked] = at_infinity.sum(-1)
    out = reconcile(m, info, theta, out, found)
    return out | {"certified": found.certified, "path_certified": found.unique, "retracked": retracked}


def _mark_at_infinity(
    m: Mechanism, out: dict[str, np.ndarray], found: PathCertificate, rows: np.ndarray, heading: np.ndarray
) -> None:
    """The inputs ``rows`` whose missing roots' paths head to infinity (``heading`` (rows, P),
    ``toward_infinity`` or far ends), in place: as many of their slots that no certified box
    holds, those paths' own first, become roots at infinity (outcome and kind); ``certified_modes``
    counts them in ``at_infinity`` once every run is merged, so that every slot stays accounted
    for once."""
    codes, kinds = _codes(m), m.manifest.abi.root_kinds
    for i, own in zip(rows, heading, strict=True):
        free = np.nonzero(~found.unique[i])[0]
        marked = free[np.argsort(~own[free], kind="stable")][: int(own.sum())]
        out["outcome"][i, marked] = codes["at_infinity"]
        out["root_kind"][i, marked] = kinds.index("at_infinity")


def _slot_keys(out: dict[str, np.ndarray], paths: int) -> list[str]:
    """The arrays of ``out`` that hold one entry per slot (n, P, ...), a slot per path."""
    return [key for key, value in out.items() if value.ndim >= 2 and value.shape[1] == paths]


def _place(
    out: dict[str, np.ndarray], found: PathCertificate, i: int, values: dict[str, np.ndarray], box: tuple
) -> bool:
    """Put a certified root (``box``: centre (n_z,), radii (n_z,), realness) with its slot's
    ``values`` into a slot of input ``i`` whose path has no certified root of its own (else a
    slot whose box overlaps an earlier one: the same root twice), in place; only if the box
    overlaps no certified box of the input (a root already held is not added twice). Returns
    whether it was placed."""
    centre, radii, real = box
    unique = found.unique[i]
    # disjoint as in ``certify.cluster_labels`` (with its rounding margins)
    gap = np.abs(found.centre[i] - centre) * (1 - 8 * UNIT)
    apart = (gap > (np.where(unique[:, None], found.radii[i], 0.0) + radii) * (1 + 8 * UNIT)).any(-1)
    if (unique & ~apart).any():
        return False
    free = np.nonzero(~unique)[0]
    if not free.size:
        labels, _ = cluster_labels(found.centre[i], np.where(unique[:, None], found.radii[i], 0.0), unique)
        free = np.nonzero(unique & (labels != np.arange(unique.size)))[0]
        if not free.size:
            return False
    slot = int(free[0])
    for key, value in values.items():
        out[key][i, slot] = value
    found.unique[i, slot], found.real[i, slot] = True, real
    found.centre[i, slot], found.radii[i, slot] = centre, radii
    return True


def _recount(found: PathCertificate, rows: np.ndarray) -> None:
    """The distinct certified roots of the inputs ``rows`` after slots changed, in place."""
    if rows.size:
        unique = found.unique[rows]
        radii = np.where(unique[..., None], found.radii[rows], 0.0)
        labels = cluster_labels(found.centre[rows], radii, unique)[0]
        found.labels[rows] = labels
        found.certified[rows] = (labels == np.arange(labels.shape[-1])).sum(-1)


def merge_roots(
    out: dict[str, np.ndarray], found: PathCertificate, rows: np.ndarray, again: dict[str, np.ndarray],
    second: PathCertificate,
) -> None:  # fmt: skip
    """Another run ``again`` (its certificate ``second``) of the inputs ``rows`` of ``out``
    (certificate ``found``), in place: each root it certified that no certified box of the input
    overlaps takes a free slot (``_place``) with that run's values. Each box holds exactly one
    root and boxes of distinct clusters are disjoint, so the clusters stay a lower bound on the
    distinct roots whatever run each box came from."""
    paths = found.unique.shape[1]
    keys = [key for key in _slot_keys(out, paths) if key in again]  # what both runs hold per slot
    for k, i in enumerate(rows):
        for p in np.nonzero(second.unique[k])[0]:
            values = {key: again[key][k, p] for key in keys}
            _place(out, found, int(i), values, (second.centre[k, p], second.radii[k, p], second.real[k, p]))
    _recount(found, rows)


def add_conjugates(
    m: Mechanism, info: Forward, theta: Array, out: dict[str, np.ndarray], found: PathCertificate, rows: np.ndarray
) -> None:
    """The complex conjugates of the certified non-real roots of the inputs ``rows``, in place,
    where the system has real coefficients (no complex patch; exactly real as rounded): F(conj z)
    = conj F(z), so the conjugate of a box holding exactly one root holds exactly one root, its
    conjugate, and a box that misses the real space is disjoint from its conjugate. Each such
    image that overlaps no certified box takes a free slot (``_place``), as a complex root."""
    homotopy = info.homotopy
    assert homotopy is not None
    if not rows.size or homotopy.patch_equation is not None:
        return
    coefficients = _target_coefficients(m, info, *_family(m, info, theta[rows]))
    real_system = np.asarray(np.isfinite(coefficients).all(-1) & (coefficients.imag == 0).all(-1))
    codes, kinds = _codes(m), m.manifest.abi.root_kinds
    paths = found.unique.shape[1]
    keys = _slot_keys(out, paths)
    for i in rows[real_system]:
        for p in np.nonzero(found.unique[i] & (found.real[i] == -1))[0]:
            values = {key: out[key][i, p].copy() for key in keys}
            values["endpoints"][..., 1] *= -1
            values["outcome"], values["root_kind"] = codes["complex"], kinds.index("complex")
            box = (np.conj(found.centre[i, p]), found.radii[i, p].copy(), -1)
            _place(out, found, int(i), values, box)
    _recount(found, rows)


def _paired_ends(pairs: PathPairs | None, roots: np.ndarray) -> np.ndarray:
    """Per input (n,): whether its paths' ends (n, P, n_z) pair up as tracked, z_second = S
    z_first exactly (or both absent); all False without pairs (an input retried after a failed
    path may not pair up)."""
    if pairs is None:
        return np.zeros(roots.shape[0], dtype=bool)
    image = roots[:, pairs.first] * pairs.flip
    later = roots[:, pairs.second]
    return ((later == image) | (np.isnan(later) & np.isnan(image))).all((-2, -1))


def _pair_order(pairs: PathPairs, paths: int) -> np.ndarray | None:
    """Where each of ``paths`` paths stands in the first paths of ``pairs`` followed by their
    partners (an index array (paths,)), or None where the pairs do not cover every path exactly
    once."""
    joined = np.concatenate([pairs.first, pairs.second])
    if joined.size != paths or not np.array_equal(np.sort(joined), np.arange(paths)):
        return None
    order = np.argsort(joined)
    order.flags.writeable = False
    return order


def _certify_endpoints(
    homotopy: Homotopy,
    coefficients: np.ndarray,
    roots: np.ndarray,
    pairs: PathPairs | None,
    paired: np.ndarray,
    backend: Any = None,
) -> Certificate:
    """``certify_roots`` of every endpoint (in the package's C where its compiled ``backend``
    has the certificate, ``certify_roots_compiled``: the same test, every bound rounded
    outward, and a double-word second attempt where double precision stalls); with a sign
    symmetry, only the first path of each pair where the other ended at its image S z (as
    tracked): a box B holding exactly one root of F gives S B holding exactly one root, since
    F(S z) = D F(z) with D = diag(+-1), so the image's certificate is the image of the box (an
    input whose ends do not pair up, after a retry, is certified path by path)."""
    in_c = getattr(backend, "certify", None) is not None and getattr(backend, "certify_workspace", None) is not None

    group, patch = _certified_group(homotopy), homotopy.patch_equation

    def certified(c: np.ndarray, z: np.ndarray, clusters: bool = True) -> Certificate:
        if in_c:
            return certify_roots_compiled(
                backend, c, homotopy.exponents, homotopy.equation, z, homogeneous=group, patch_equation=patch,
                clusters=clusters,
            )  # fmt: skip
        return certify_roots(c, homotopy.exponents, homotopy.equation, z, homogeneous=group, patch_equation=patch)

    if pairs is None or not paired.any():
        return certified(coefficients, roots)
    first, second = pairs.first, pairs.second
    n, paths, size = roots.shape
    order = _fixed("pair_order", pairs, lambda: _pair_order(pairs, paths))
    if order is not None and paired.all():
        # every input paired (the usual case) and the pairs cover every path once: each array
        # is its first paths' values and their images side by side, put in path order (the
        # values the general assembly below writes, slot by slot)
        part = certified(coefficients, roots[:, first], clusters=False)
        source = order % first.size  # each path's first path: itself or its partner
        unique, real, radius, radii = (
            np.take(value, source, axis=1) for value in (part.unique, part.real, part.radius, part.radii)
        )
        centre = np.take(np.concatenate([part.center, part.center * pairs.flip], axis=1), order, axis=1)
        labels, distinct = cluster_labels(centre, np.where(unique[..., None], radii, 0.0), unique, backend)
        count = (labels == np.arange(paths)).sum(-1)
        return Certificate(unique, radius, real, distinct, count, centre, radii, labels)
    unique, real = np.zeros((n, paths), bool), np.zeros((n, paths), np.int8)
    radius, centre = np.full((n, paths), np.nan), np.full((n, paths, size), np.nan + 0j)
    radii = np.full((n, paths, size), np.nan)
    everyone = bool(paired.all())  # the usual case: plain column indexing, no index grids

    def cells(rows: np.ndarray, columns: np.ndarray) -> tuple:
        return (slice(None), columns) if everyone else np.ix_(np.nonzero(rows)[0], columns)

    for rows, columns in ((paired, first), (~paired, np.arange(paths))):
        if not rows.any():
            continue
        part = certified(coefficients[rows], roots[rows][:, columns], clusters=False)  # counted below, all paths
        block = cells(rows, columns)
        unique[block], real[block], radius[block] = part.unique, part.real, part.radius
        centre[block], radii[block] = part.center, part.radii
    mirror, source = cells(paired, second), cells(paired, first)
    unique[mirror], real[mirror], radius[mirror] = unique[source], real[source], radius[source]
    centre[mirror], radii[mirror] = centre[source] * pairs.flip, radii[source]
    labels, distinct = cluster_labels(centre, np.where(unique[..., None], radii, 0.0), unique, backend)
    count = (labels == np.arange(paths)).sum(-1)
    return Certificate(unique, radius, real, distinct, count, centre, radii, labels)


def _retry_failed(m: Mechanism, theta: Array, ended: Paths, tolerance: float, info: Forward) -> Paths:
    """Inputs where a path failed (it came too close to another: the corrector could not converge
    at any step size) are tracked again from the second generated start system, along another
    segment; each failed slot takes an endpoint of that run that the first run did not reach (the
    same solution has the same coordinates in both: one patch)."""
    homotopy = info.homotopy
    assert homotopy is not None
    alternative = homotopy.alternative
    paths = alternative.shape[0]
    rows = np.unique(np.nonzero(ended.status == PATH_FAILED)[0] // paths)
    # every path, as the generated C driver's retry does (failures are rare; the two agree)
    system = family_system(
        _path_table(m, info, theta[rows], START_ALTERNATIVE), homotopy.exponents, homotopy.equation, paths
    )
    second = track(system, np.tile(alternative, (rows.size, 1)), tolerance)
    z, status = ended.z.copy(), ended.status.copy()
    for j, i in enumerate(rows):
        mine, theirs = slice(i * paths, (i + 1) * paths), slice(j * paths, (j + 1) * paths)
        known = z[mine][status[mine] == PATH_REACHED]
        fresh = second.z[theirs][second.status[theirs] == PATH_REACHED]
        for slot in np.nonzero(status[mine] == PATH_FAILED)[0]:
            for candidate in fresh:
                if not is_known(known, candidate):
                    z[i * paths + slot], status[i * paths + slot] = candidate, PATH_REACHED
                    known = np.vstack([known, candidate])
                    break
    return Paths(z, status, ended.steps, ended.update)


def _polynomial_candidates(m: Mechanism, theta: Array, info: Forward) -> dict[str, np.ndarray]:
    """Every real root of the generated univariate polynomial x every branch, back substituted."""
    codes = _codes(m)
    settings = _settings(m)
    n = theta.shape[0]
    degree, combos = info.degree, np.array(info.combinations, dtype=float).reshape(len(info.combinations), -1)
    n_b = combos.shape[0]
    with np.errstate(all="ignore"):
        poly = m.backend.call("forward_polynomial", theta, m.params)
    coefficients = poly["coefficients"]
    degeneracies = poly.get("degeneracies", np.zeros((n, 0)))
    usable = np.asarray(np.isfinite(coefficients).all(-1))
    degenerate = ~(np.abs(degeneracies) >= settings["degenerate"]).all(-1) | ~usable
    roots = isolate_real_roots(
        np.where(usable[:, None], coefficients, 0.0), settings["leading_tolerance"], settings["near_tolerance"]
    )
    found = np.where(usable & ~roots.vanishing, roots.count, 0)
    at_infinity = np.where(usable & ~roots.vanishing, roots.at_infinity, 0)
    total = np.minimum(found + at_infinity, degree)
    index = np.arange(degree)
    infinite = (index >= found[:, None]) & (index < total[:, None])
    has_root = index < total[:, None]
    finite_roots = np.where(index < found[:, None], np.nan_to_num(roots.roots[:, :degree]), 0.0)
    evaluate = np.where(infinite, m.tolerances["at_infinity"], finite_roots)
    kind = np.where(index < found[:, None], roots.kind[:, :degree], np.where(infinite, 0, -1))

    # slots: root r, branch b at r * n_b + b
    slot_has = np.repeat(has_root, n_b, axis=1)
    t = np.repeat(evaluate, n_b, axis=1)[..., None]
    branch = np.tile(combos, (degree, 1))
    outcome = np.where(slot_has, -1, codes["no_root"]).astype(np.int32)
    with np.errstate(all="ignore"):
        pose = m.backend.call("forward_back_substitution", theta[:, None, :], t, branch, m.params)["pose"]
    defined = np.asarray(np.isfinite(pose).all(axis=(-2, -1)))
    outcome = np.where((outcome < 0) & ~defined, codes["back_substitution_undefined"], outcome)
    pose = np.where(defined[..., None, None] & slot_has[..., None, None], pose, np.eye(4))
    theta_slots = np.broadcast_to(theta[:, None, :], (n, degree * n_b, theta.shape[-1]))
    near = np.where(index < found[:, None], kind == 2, False).sum(-1)
    return {
        "pose": pose,
        "q": _passive_from_pose(m, theta_slots, pose, settings["validity"]),
        "outcome": outcome,
        "root": np.repeat(np.where(infinite, np.inf, np.where(has_root, finite_roots, np.nan)), n_b, axis=1),
        "kind": np.repeat(kind, n_b, axis=1).astype(np.int32),
        "has_root": slot_has,
        "degenerate": degenerate | roots.vanishing,
        "real_roots": found - near,
        "near_roots": near,
        "at_infinity": at_infinity,
    }


def _check_candidates(m: Mechanism, theta: Array, q: Array, pose: Array, outcome: np.ndarray) -> tuple[np.ndarray, ...]:
    """Candidates (k,) with actuated values ``theta`` (k, n_a), passive values ``q`` (k, n_p) and
    poses (k, 4, 4) where ``outcome`` is -1 (others pass through): closure and alignment, Newton
    polish, wrapping, joint limits and input independence. Returns q, pose, outcome (-1 still
    for a mode), the closure residual and the conditioning."""
    codes = _codes(m)
    settings = _settings(m)
    q, pose, outcome = q.copy(), pose.copy(), outcome.copy()
    located = np.asarray(np.isfinite(q).all(-1))
    outcome = np.where((outcome < 0) & ~located, codes["not_closed"], outcome)
    q = np.where(located[..., None], q, 0.0)
    with np.errstate(all="ignore"):
        closure = m.backend.call("loop_closure", theta, q, m.params)
    # a NaN entry makes the whole closure undefined (np.fmax would drop it)
    norm = np.abs(closure["residual"]).max(-1, initial=0.0)
    norm = np.where(np.isnan(norm), np.inf, norm)
    aligned = (closure["alignment"] > 0).all(-1)
    residual = np.where(outcome < 0, norm, np.nan)
    outcome = np.where((outcome < 0) & ~(norm < settings["candidate"]), codes["not_closed"], outcome)
    outcome = np.where((outcome < 0) & ~aligned, codes["false_closure"], outcome)
    conditioning = np.full(outcome.shape, np.nan)
    pending = outcome < 0
    if pending.any():
        where = np.nonzero(pending)
        polished_q, polished_pose, polished_norm, _, status, ratio, _, _ = m._newton_python(
            theta[where], q[where], settings["tolerance"], int(settings["polish_iterations"]), 0.5, keep_last=True
        )
        conditioning[where] = ratio
        # near a double root Newton converges only linearly: a last iterate that closes to the
        # closure tolerance (and is aligned) is the mode, polished as far as its conditioning allows
        slow = (status == NEWTON_NO_CONVERGENCE) & (polished_norm < settings["closure"])
        if slow.any():
            with np.errstate(all="ignore"):
                check = m.backend.call("loop_closure", theta[where][slow], polished_q[slow], m.params)
            status[np.nonzero(slow)[0][(check["alignment"] > 0).all(-1)]] = NEWTON_OK
        ok = status == NEWTON_OK
        keep = (status == NEWTON_SINGULAR) & (norm[where] < settings["closure"])
        result = np.full(status.shape, -1, dtype=np.int32)
        result[status == NEWTON_WRONG_BASIN] = codes["false_closure"]
        result[~ok & ~keep & (status != NEWTON_WRONG_BASIN)] = codes["not_converged"]
        outcome[where] = result
        residual[where] = np.where(ok, polished_norm, residual[where])
        q[where] = np.where(ok[:, None], polished_q, q[where])
        pose[where] = np.where(ok[:, None, None], polished_pose, pose[where])
    q = np.where(m._angular_passive, wrap_angle(q), q)
    lower, upper = _limits(m)
    inside = ((q > lower) & (q < upper)).all(-1)
    outcome = np.where((outcome < 0) & ~inside, codes["outside_limits"], outcome)
    folded = m.capabilities.rates.input_independent if m.capabilities.rates else ()
    if folded and (outcome < 0).any():
        with np.errstate(all="ignore"):
            factors = m.backend.call("singularity_factors", theta, q, m.params)["factors"]
        names = list(m.manifest.singularity_factors)
        picked = np.array([names.index(name) for name in folded])
        independent = (np.abs(factors[..., picked]) < settings["factor_zero"]).all(-1)
        outcome = np.where((outcome < 0) & independent, codes["input_independent"], outcome)
    return q, pose, outcome, residual, conditioning


def _settle(
    m: Mechanism, theta: Array, finite_input: np.ndarray, found: dict[str, np.ndarray]
) -> dict[str, np.ndarray]:
    """Candidates to modes: closure and alignment, Newton polish, wrapping, joint limits, input
    independence (``_check_candidates``) and repeats; every slot ends with an outcome."""
    codes = _codes(m)
    settings = _settings(m)
    slot_has = found["has_root"] & finite_input[:, None]
    outcome = np.where(slot_has, found["outcome"], codes["no_root"]).astype(np.int32)
    n, slots = outcome.shape
    theta_slots = np.broadcast_to(theta[:, None, :], (n, slots, theta.shape[-1]))
    checked = _check_candidates(
        m, theta_slots.reshape(n * slots, -1), found["q"].reshape(n * slots, -1),
        found["pose"].reshape(n * slots, 4, 4), outcome.reshape(-1),
    )  # fmt: skip
    q, pose, outcome, residual, conditioning = (v.reshape((n, slots) + v.shape[1:]) for v in checked)
    # repeats: slot by slot, so that the first of two equal modes is the one kept (as in C)
    for s in range(slots):
        pending_s = outcome[:, s] < 0
        if not pending_s.any():
            continue
        earlier = outcome[:, :s] == codes["mode"]
        distance = np.abs(pose[:, :s] - pose[:, s, None]).max(axis=(-2, -1)) if s else np.zeros((n, 0))
        repeat = (earlier & (distance < settings["duplicate"])).any(-1)
        outcome[:, s] = np.where(pending_s, np.where(repeat, codes["duplicate"], codes["mode"]), outcome[:, s])
    count = (outcome == codes["mode"]).sum(-1).astype(np.int32)
    status_codes = m.manifest.abi.input_status
    status = np.where(
        ~finite_input,
        status_codes.index("nonfinite"),
        np.where(found["degenerate"] & (count == 0), status_codes.index("degenerate"), 0),
    ).astype(np.int32)

    def per_input(key: str) -> np.ndarray:
        return np.where(finite_input, found[key], 0).astype(np.int32)

    return {
        "poses": pose,
        "passive": np.where(slot_has[..., None], np.nan_to_num(q), 0.0),
        "residual": residual,
        "conditioning": conditioning,
        "roots": np.where(finite_input[:, None], found["root"], np.nan),
        "outcome": outcome,
        "root_kind": np.where(finite_input[:, None], found["kind"], -1).astype(np.int32),
        "count": count,
        "real_roots": per_input("real_roots"),
        "near_roots": per_input("near_roots"),
        "at_infinity": per_input("at_infinity"),
        "status": status,
        **(
            {"endpoints": np.where(finite_input[:, None, None, None], found["endpoints"], np.nan)}
            if "endpoints" in found
            else {}
        ),
        **({"end_size": np.where(finite_input[:, None], found["end_size"], 0.0)} if "end_size" in found else {}),
    }


def _passive_from_pose(m: Mechanism, theta: Array, pose: Array, validity_floor: float) -> Array:
    """The passive values of the inverse branch whose actuated values match ``theta`` and how far
    they miss it; the same rule as the C driver's ``passive_from_pose``: every sign pattern in one
    ``inverse_pose_patterns`` call, each independent branch group choosing its own pattern (ranked
    by actuated mismatch, +1e3 per invalid validity measure; NaN where no pattern is finite)."""
    inverse = m.capabilities.inverse
    assert inverse is not None
    n_groups = len(inverse.groups)

    def group_of(groups: tuple[int, ...]) -> np.ndarray:
        # outputs that no branch symbol changes form one more group, the last
        return np.where(np.array(groups, dtype=np.intp) < 0, n_groups, np.array(groups, dtype=np.intp))

    with np.errstate(all="ignore"):
        out = m.backend.call("inverse_pose_patterns", pose_vector(pose), m.params)
    batch, count = pose.shape[:-2], len(inverse.patterns)
    sizes = {"actuated": len(m.manifest.actuated), "passive": len(m.passive_names), "validity": len(inverse.validity)}
    # (..., patterns, size); a single pattern's outputs arrive as vectors
    actuated, passive, validity = (np.moveaxis(out[k].reshape(batch + (n, count)), -1, -2) for k, n in sizes.items())
    members = np.arange(n_groups + 1)[:, None]
    difference = actuated - theta[..., None, :]
    difference = np.abs(np.where(m._angular_actuated, wrap_angle(difference), difference))
    in_group = group_of(inverse.actuated_groups) == members  # (groups, NA)
    missed = np.fmax.reduce(np.where(in_group, difference[..., None, :], 0.0), axis=-1, initial=0.0)
    invalid = ~(validity > validity_floor)
    penalty = (invalid[..., None, :] & (group_of(inverse.validity_groups) == members)).sum(-1)
    passive_group = group_of(inverse.passive_groups)
    unusable = (~np.isfinite(passive)[..., None, :] & (passive_group == members)).any(-1)
    ranked = np.where(unusable, np.inf, missed + 1e3 * penalty)  # (..., patterns, groups)
    best = np.argmin(ranked, axis=-2)  # (..., groups): first best pattern, as in C
    chosen = np.take_along_axis(ranked, best[..., None, :], axis=-2)[..., 0, :]
    pattern = np.take_along_axis(best, np.broadcast_to(passive_group, best.shape[:-1] + passive_group.shape), axis=-1)
    q = np.take_along_axis(passive, pattern[..., None, :], axis=-2)[..., 0, :]
    q = np.where(m._angular_passive, wrap_angle(q), q)
    return np.where(np.isfinite(chosen).all(-1)[..., None], q, np.nan)


def quaternion_blocks(m: Mechanism) -> tuple[int, ...]:
    """The first index of each unit quaternion among the passive values: four consecutive
    dimensionless variables (``parakin.packages.manifest.Variable``: dimensionless means a
    quaternion component)."""
    return _fixed("quaternion_blocks", m.manifest, lambda: _quaternion_starts([v.kind for v in m.manifest.passive]))


def _quaternion_starts(kinds: list[str]) -> tuple[int, ...]:
    starts, k = [], 0
    while k + 4 <= len(kinds):
        if all(kind == "dimensionless" for kind in kinds[k : k + 4]):
            starts.append(k)
            k += 4
        else:
            k += 1
    return tuple(starts)


#: a unit quaternion's component this small is zero for its sign (a half-turn's q0 is rounding
#: noise of either sign; the components are unit-free and at most 1)
QUATERNION_ZERO = 1e-9


def canonical_quaternions(passive: np.ndarray, blocks: tuple[int, ...]) -> np.ndarray:
    """``passive`` (..., n_p) with each quaternion q of ``blocks`` replaced by -q where its first
    component larger than ``QUATERNION_ZERO`` in size is negative (q0 > 0, the inverse's
    convention, and for a half-turn (q0 = 0) the next component): q and -q are one rotation, and
    which of the two a root or a backend's settling lands on is an accident of the path, so a
    mode's passive values would otherwise differ between backends and between a mode and the
    home it is. NaN stays NaN."""
    if not blocks:
        return passive
    out = passive.copy()
    for k in blocks:
        q = out[..., k : k + 4]
        nonzero = np.abs(q) > QUATERNION_ZERO
        # the first component larger than QUATERNION_ZERO (q0 where none is), picked last to first
        first = q[..., 0]
        for j in (3, 2, 1, 0):
            first = np.where(nonzero[..., j], q[..., j], first)
        np.negative(q, out=q, where=(first < 0.0)[..., None])
    return out


def closure_tolerance(m: Mechanism) -> float:
    """What a mode's loop closure must reach in the caller's units, max-norm over the rows (m and
    rad): the package's closure tolerance times the size of the geometry (``length_scale``)."""
    return float(m.tolerances["closure"]) * length_scale(m)


def _closed_modes(
    m: Mechanism, outcome: np.ndarray, residual: np.ndarray, codes: dict[str, int]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The last check of every mode (..., M), whatever produced it: its closure ``residual`` in
    the caller's units (the rescaled solver's modes are measured again in the caller's geometry,
    ``Mechanism._every_mode``) below ``closure_tolerance``; a mode that does not close is "not
    closed", never a mode. Returns the outcomes (``outcome`` itself where every mode closes, the
    rule), the modes taken away per input (...) and the modes left (..., M)."""
    valid = outcome == codes["mode"]
    opened = valid & ~(residual <= closure_tolerance(m))
    if not opened.any():
        return outcome, opened.sum(-1), valid
    outcome = np.where(opened, codes["not_closed"], outcome).astype(outcome.dtype)
    return outcome, opened.sum(-1), outcome == codes["mode"]


#: per mechanism object: (its parameter values, method -> whether its root count bounds the roots)
_BOUNDS: weakref.WeakKeyDictionary[Any, tuple[bytes, dict[str, bool]]] = weakref.WeakKeyDictionary()


def root_count_bounds(m: Mechanism, info: Forward) -> bool:
    """Whether the homotopy's root count is proven and bounds the roots at ``m``'s parameters.
    A count proven on a subfamily (parameters sharing a value: a Hexaglide's sliders on shared
    rails, ``parakin.solvers.subfamily_membership``) does not where these parameters break its relations: the
    family's other roots are back, and no input may be certified complete (one warning names the
    relation). The relations hold for every input or none; cached per mechanism and parameters."""
    homotopy = info.homotopy
    if homotopy is None or homotopy.root_count is None or not homotopy.root_count.proven:
        return False
    if not homotopy.subfamily_identical:
        return True
    key = np.ascontiguousarray(m.params, dtype=float).tobytes()
    known = _BOUNDS.get(m)
    if known is None or known[0] != key:
        known = (key, {})
        _BOUNDS[m] = known
    if info.method not in known[1]:
        free, angles = _family(m, info, np.asarray(m.home_actuated, dtype=float)[None])
        outside = bool(outside_subfamily(homotopy.subfamily_identical, free, angles, homotopy.subfamily_tolerance)[0])
        if outside:
            logger.warning(
                "%s: the %s root count was proven where %s; these parameters break that, so its "
                "certificates cannot say complete (to prove a count that holds for them, generate the "
                "mechanism with these values as its defaults)",
                m.name,
                info.method,
                homotopy.subfamily_relations or "the generation's parameter values hold",
            )
        known[1][info.method] = not outside
    return known[1][info.method]


def assemble(m: Mechanism, theta: Array, out: dict[str, np.ndarray], info: Forward) -> AssemblyModes:
    """The result object over the caller's batch shape."""
    shape = theta.shape[:-1]
    codes = _codes(m)

    def shaped(key: str) -> np.ndarray:
        value = out[key]
        if one and value.ndim > 1:  # the input's row: the same view, indexed (a reshape costs 10x)
            return value[0]
        return value.reshape(shape + value.shape[1:])

    one = shape == ()  # one input, no batch axis

    # a mode that does not close is none (counted undecided: the input is then not complete)
    outcome, dropped, valid = _closed_modes(m, shaped("outcome"), shaped("residual"), codes)
    count = (shaped("count") - dropped).astype(np.int32)
    undecided = shaped("undecided") + dropped if "undecided" in out else None
    kind, kinds = shaped("root_kind"), m.manifest.abi.root_kinds
    return AssemblyModes(
        actuated=theta,
        poses=shaped("poses"),
        passive=canonical_quaternions(shaped("passive"), quaternion_blocks(m)),
        residual=shaped("residual"),
        root=shaped("roots"),
        # real: a root kind that is real (a simple root or a cluster of real roots), or a slot
        # polished into a mode; near-real pairs, complex endpoints and failed paths are not
        real=(kind == kinds.index("simple")) | (kind == kinds.index("cluster")) | valid,
        valid=valid,
        count=count,
        input_independent=outcome == codes["input_independent"],
        outcome=outcome,
        root_kind=kind,
        # measured at every mode (``Mechanism._measured``); none in a slot that is no mode (a
        # deferred measure is NaN until read: the caller puts it in its place)
        conditioning=shaped("conditioning")
        if "conditioning_jacobians" in out
        else np.where(valid, shaped("conditioning"), np.nan),
        real_roots=shaped("real_roots"),
        near_roots=shaped("near_roots"),
        at_infinity=shaped("at_infinity"),
        status=shaped("status"),
        outcomes=m.manifest.abi.mode_outcomes,
        branch_count=len(info.combinations),
        method=info.method,
        root_count=info.homotopy.root_count.count if info.homotopy and info.homotopy.root_count else None,
        root_count_proven=root_count_bounds(m, info),
        certified_roots=shaped("certified") if "certified" in out else None,
        path_certified=shaped("path_certified") if "path_certified" in out else None,
        retracked=shaped("retracked") if "retracked" in out else None,
        undecided_roots=undecided,
        pose_kind=m.manifest.pose_kind,
    )
