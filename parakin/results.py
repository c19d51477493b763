"""Named results: what the solvers return. Arrays carry the caller's leading batch shape."""

from __future__ import annotations

import html
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from parakin.errors import NoSuchModeError, at_index, first_index
from parakin.tables import (
    POSE_HEADERS,
    ROWS_SHOWN,
    Rows,
    html_table,
    pose_convention,
    pose_headers,
    pose_values,
    text_table,
)

Array = NDArray[np.float64]
Mask = NDArray[np.bool_]
#: a distance to singularity (1/cond) below this is near a singularity: ``ill_conditioned()``
#: marks such modes, ``parakin plot``'s grid titles them in red, the MJCF export warns of such
#: keyframes and ``parakin sweep``'s maps draw this level as a contour (``parakin.singularity``
#: re-exports it: here because that module builds on this one)
NEAR_SINGULAR = 0.02


@dataclass(frozen=True)
class Configuration:
    """A closed configuration: actuated (..., n_a), passive (..., n_p) and pose ^B_P T (..., 4, 4)."""

    actuated: Array
    passive: Array
    pose: Array

    @property
    def rotation(self) -> Array:
        """The platform orientation ^B_P R (..., 3, 3)."""
        return self.pose[..., :3, :3]


@dataclass(frozen=True)
class ForwardPose(Configuration):
    """Newton forward pose: ``residual`` is the max-norm of the loop closure reached,
    ``iterations`` the Newton steps taken, ``converged`` whether the tolerance was met."""

    residual: Array
    iterations: NDArray[np.int32]
    converged: Mask
    within_limits: Mask


@dataclass(frozen=True)
class InversePose:
    """Every inverse-pose branch: arrays (..., n_branches, n). ``branches[k]`` are the sign
    values of the branch symbols ``branch_names`` for branch k; ``valid`` is the validity mask and
    ``failures`` maps each validity condition (and ``limits``) to where it failed."""

    actuated: Array
    passive: Array
    valid: Mask
    branches: NDArray[np.int8]
    branch_names: tuple[str, ...]
    failures: dict[str, Mask]
    pose: Array

    def __repr__(self) -> str:
        """A summary line and, for one pose, a table of its branches (signs, validity, actuated)."""
        return inverse_text(self)

    def _repr_html_(self) -> str:
        return inverse_html(self)

    def branch(self, index: int) -> Configuration:
        """One inverse branch as a configuration.

        Parameters
        ----------
        index : int
            The branch, 0 <= index < n_branches (its signs: ``branches[index]``).

        Returns
        -------
        Configuration
            actuated (..., n_a), passive (..., n_p) and the pose (..., 4, 4), over the batch
            shape of the pose; check ``valid[..., index]`` first (an invalid branch's values are
            no configuration).

        Raises
        ------
        NoSuchModeError
            ``index`` is not an integer in [0, n_branches).

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("delta", backend="numpy")
        >>> arms = m.inverse_pose([0.0, 0.0, -1.2]).branch(0).actuated   # by hand: every arm level
        >>> bool(abs(arms).max() < 1e-12)
        True
        """
        branches = self.valid.shape[-1]
        if isinstance(index, bool | np.bool_) or not isinstance(index, int | np.integer) or not 0 <= index < branches:
            raise NoSuchModeError(f"branch index must be an integer in [0, {branches}), got {index!r}")
        return Configuration(self.actuated[..., index, :], self.passive[..., index, :], self.pose)


@dataclass(frozen=True)
class DeferredConditioning:
    """An ``AssemblyModes.conditioning`` computed when first read (``Mechanism.forward_pose_all``
    of a few inputs): ``measure`` (the solvers' ``inverse_condition``, passed in: this module
    sits below them) of the closure Jacobians ``jacobians`` (k, n_c, n_p) of the measured modes
    ``measured`` (n, M) (flat batch, the Jacobians in row-major order of the mask), NaN in every
    other slot and where ``valid`` (..., M) is False, over the batch shape of ``valid``: the
    array the mechanism would have computed at once."""

    measured: Mask
    jacobians: Array
    valid: Mask
    measure: Callable[[Array], Array]

    def value(self) -> Array:
        """The conditioning (..., M)."""
        conditioning = np.full(self.measured.shape, np.nan)
        conditioning[self.measured] = self.measure(self.jacobians)
        return np.where(self.valid, conditioning.reshape(self.valid.shape), np.nan)


@dataclass(frozen=True)
class AssemblyModes:
    """Every forward-pose solution, in M = degree x branch-combination slots: arrays (..., M, ...).

    Slot r * B + b holds root r (ascending, then roots at infinity) with branch combination b.
    ``valid``: a mode (real root, closed and polished, within joint limits, not a repeat of an
    earlier mode, not input-independent); ``count`` = valid modes per input. ``real``: the slot's
    root is real (root kind simple or cluster) or its candidate was polished into a mode; complex,
    near-real pairs, failed paths and empty slots are not real.

    Modes are indexed as modes: ``mode(k)`` is the k-th valid slot (slot order), 0 <= k < count;
    for one input ``len(modes)`` is ``count`` and iterating gives each mode as a Configuration.
    For a batch, ``mode(k)`` is mode k of every input (each must have more than k modes, else
    NoSuchModeError naming the input), and ``len``/iteration refuse the batch (the counts differ:
    index ``valid`` or call ``mode``). ``slot(s)`` is slot s whatever it holds (its ``outcome``
    says whether it is a mode).
    ``outcome`` (..., M) says what became of every slot (codes: ``OUTCOMES``); ``root_kind`` is
    the kind of the slot's root (0 simple, 1 cluster of numerically multiple roots, 2 complex
    pair near the real axis, -1 no root). ``conditioning``: the type II distance
    (``parakin.singularity.type_ii_distance``: sigma_min / sigma_max of d closure / d passive), 1
    far from, 0 at a type II singularity; NaN in a slot that is no mode (for a call of a few inputs
    measured when first read: ``DeferredConditioning``). Per input: ``real_roots`` (distinct finite
    real roots), ``near_roots``, ``at_infinity`` (roots at infinity; at a degenerate input also
    the paths found heading there) and ``status`` (``INPUT_STATUS``)."""

    actuated: Array
    poses: Array
    passive: Array
    residual: Array
    root: Array
    real: Mask
    valid: Mask
    count: NDArray[np.integer]
    input_independent: Mask
    outcome: NDArray[np.int32]
    root_kind: NDArray[np.int32]
    conditioning: Array
    real_roots: NDArray[np.int32]
    near_roots: NDArray[np.int32]
    at_infinity: NDArray[np.int32]
    status: NDArray[np.int32]
    outcomes: tuple[str, ...] = ()
    branch_count: int = 1
    #: the method that found the modes (``Mechanism.forward_pose_all``)
    method: str = ""
    #: homotopy methods: the proven generic root count, and per input the distinct certified roots
    #: and per path whether its endpoint is certified (``certificate()``)
    root_count: int | None = None
    root_count_proven: bool = False
    certified_roots: NDArray[np.int64] | None = None
    path_certified: Mask | None = None
    #: per input: its paths were tracked a second time (first answer not certified complete)
    retracked: Mask | None = None
    #: per input: certified roots whose realness neither double nor exact arithmetic decided
    #: (listed as no mode; the input is then not complete)
    undecided_roots: NDArray[np.int64] | None = None
    #: the mechanism's pose kind (``parakin.pose.POSE_KINDS``): the tables show its coordinates
    #: only; "" (unknown) shows all six of a transform
    pose_kind: str = ""

    def __getstate__(self) -> dict[str, Any]:
        """A pickle holds values, not the Jacobians a deferred field waits on: such fields are
        computed first (the values their reading gives; ``_defer``)."""
        for name in list(self.__dict__.get("_deferred", {})):
            getattr(self, name)
        return self.__dict__

    def __copy__(self) -> AssemblyModes:
        """A shallow copy that keeps its deferred fields deferred (each copy computes its own at
        its first reading)."""
        copied = object.__new__(type(self))
        copied.__dict__.update(self.__dict__)
        return copied

    def _defer(self, name: str, deferred: DeferredConditioning) -> None:
        """Field ``name`` computed at its first reading (``deferred.value()``), not now: the
        value any reading gets is the one computing it now would give."""
        self.__dict__.pop(name)
        self.__dict__.setdefault("_deferred", {})[name] = deferred

    if not TYPE_CHECKING:  # (a static checker keeps seeing the fields alone)

        def __getattr__(self, name: str) -> Any:
            """A deferred field's value, computed at its first reading (``_defer``) and kept."""
            deferred = self.__dict__.get("_deferred", {}).get(name)
            if deferred is None:
                if name in self.__dict__:  # another thread computed it meanwhile
                    return self.__dict__[name]
                raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}", name=name, obj=self)
            value = deferred.value()
            self.__dict__[name] = value
            # a new dict, not this one emptied: a copy (copy.copy) shares this one until it reads
            self.__dict__["_deferred"] = {key: d for key, d in self.__dict__["_deferred"].items() if key != name}
            return value

    def complete(self) -> Mask:
        """Whether no assembly mode can be missing, per input.

        Returns
        -------
        ndarray of bool, shape (...)
            True where every root is certified and every real one decided, with a proven root
            count; False where no certificate applies (a method without one).

        Examples
        --------
        >>> import numpy as np, parakin
        >>> m = parakin.load("planar_3rrr", backend="numpy")
        >>> bool(m.forward_pose_all(np.deg2rad([-54.0, 174.0, -105.0])).complete())
        True
        """
        if self.certified_roots is None or self.root_count is None:
            return np.zeros(np.shape(self.count), dtype=bool)
        undecided = 0 if self.undecided_roots is None else self.undecided_roots
        return (self.certified_roots == self.root_count) & (undecided == 0) & self.root_count_proven

    def slot(self, index: int) -> Configuration:
        """A raw slot of the solver, whether or not it holds a mode.

        Parameters
        ----------
        index : int
            The slot, 0 <= index < M (``outcome[..., index]`` says what it holds).

        Returns
        -------
        Configuration
            The slot's actuated (..., n_a), passive (..., n_p) and pose (..., 4, 4); a slot that
            is not a mode need not close the loop.

        Raises
        ------
        NoSuchModeError
            ``index`` is not an integer in [0, M).

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> modes = m.forward_pose_all(m.home_actuated)
        >>> modes.outcomes[modes.outcome[1]], modes.slot(1).passive.round(3).tolist()
        ('mode', [0.0, 0.33])
        """
        slots = self.valid.shape[-1]
        if isinstance(index, bool | np.bool_) or not isinstance(index, int | np.integer) or not 0 <= index < slots:
            raise NoSuchModeError(f"slot index must be an integer in [0, {slots}), got {index!r}")
        return Configuration(self.actuated, self.passive[..., index, :], self.poses[..., index, :, :])

    def mode(self, index: int) -> Configuration:
        """Assembly mode ``index``: the index-th valid slot, in slot order (row ``index`` of
        ``print(modes)``).

        Parameters
        ----------
        index : int
            The mode, 0 <= index < count. For a batch, mode ``index`` of every input.

        Returns
        -------
        Configuration
            actuated (..., n_a), passive (..., n_p) and the pose ^B_P T (..., 4, 4) in {B}, metres.

        Raises
        ------
        NoSuchModeError
            An input has no mode ``index`` (the message names its count and the input), or
            ``index`` is not an integer.

        Examples
        --------
        >>> import numpy as np, parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> modes = m.forward_pose_all([np.pi / 2, np.pi / 2])   # by hand: P = (0, 0) or (0, 0.4)
        >>> sorted(round(float(c.pose[1, 3]), 6) + 0.0 for c in modes)
        [0.0, 0.4]
        """
        count = np.asarray(self.count)
        if isinstance(index, bool | np.bool_) or not isinstance(index, int | np.integer):
            raise NoSuchModeError(f"mode index must be an integer, got {type(index).__name__} {index!r}")
        short = ~(count > index) | (index < 0)
        if np.any(short):
            where = first_index(short)
            raise NoSuchModeError(
                f"no mode {index}{at_index(where)}: there are {int(count[where])} modes (count), "
                f"indexed 0 to {int(count[where]) - 1}; slots are reachable by slot(s)"
            )
        # position of the index-th True of valid along the slot axis
        rank = np.cumsum(self.valid, axis=-1) - 1
        slot = np.argmax(self.valid & (rank == index), axis=-1)
        passive = np.take_along_axis(self.passive, slot[..., None, None], axis=-2)[..., 0, :]
        poses = np.take_along_axis(self.poses, slot[..., None, None, None], axis=-3)[..., 0, :, :]
        return Configuration(self.actuated, passive, poses)

    def __len__(self) -> int:
        """The number of modes of a single input (``count``); a batch has one count per input."""
        count = np.asarray(self.count)
        if count.ndim:
            raise NoSuchModeError(
                f"len() needs a single input; this result holds a batch {count.shape} with counts per "
                "input in .count (use mode(k) for mode k of every input, or index .valid)"
            )
        return int(count)

    def __bool__(self) -> bool:
        """Always true, as a result object (not ``count > 0``: a batch has no single count)."""
        return True

    def __iter__(self) -> Iterator[Configuration]:
        """Each mode of a single input, in slot order (as ``mode(0)``, ``mode(1)``, ...)."""
        for k in range(len(self)):
            yield self.mode(k)

    def ill_conditioned(self, level: float | None = None) -> Mask:
        """Modes near a type II singularity: reported, but their pose is sensitive to the inputs.

        The same notion as ``parakin plot``'s red titles and the MJCF export's warnings: the
        type II distance ``conditioning`` (sigma_min / sigma_max of the closure Jacobian, 1 far
        from, 0 at a singularity) at or below ``level``.

        Parameters
        ----------
        level : float, optional
            The type II distance at or below which a mode counts as near a singularity;
            default ``parakin.singularity.NEAR_SINGULAR`` (0.02).

        Returns
        -------
        ndarray of bool, shape (..., M)
            Per slot: a valid mode whose conditioning is at most ``level``.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> m.forward_pose_all(m.home_actuated).ill_conditioned().tolist()  # two regular modes
        [False, False]
        """
        if level is None:
            level = NEAR_SINGULAR
        return self.valid & ~(self.conditioning > level)

    def __repr__(self) -> str:
        """A summary line and, for one input, a table of its modes (numbered 0 .. count - 1)."""
        return modes_text(self)

    def _repr_html_(self) -> str:
        return modes_html(self)

    def certificate(self) -> dict[str, NDArray[np.int64]]:
        """Per input: every isolated root accounted for.

        ``roots`` = real + near-real + at infinity; ``with_modes`` roots gave at least one mode;
        ``rejected[reason]`` counts the others by the furthest stage any of their branches
        reached. roots == with_modes + sum(rejected) holds for every input.

        A homotopy method adds ``root_count`` (the family's generic number of solutions, proven
        at generation time, by the total-degree bound or the trace test, where
        ``root_count_proven``), ``certified_roots`` (distinct roots of the system at the input,
        each in a Krawczyk box holding exactly one root: ``parakin.solvers.certify``),
        ``complete`` (the two are equal and the count is proven: no solution can be missing, so
        the modes returned are all of them), ``uncertified_paths`` (per input, the paths whose
        endpoint has no such box) and ``retracked`` (the first run was not complete: its suspect
        paths, then if need be every path from each start instance, tracked again in projective
        space, where roots near infinity stay bounded; each run's certified roots merged, and the
        complex conjugates of certified non-real roots added).

        Returns
        -------
        dict of str to ndarray, each shape (...)
            The counts above per input; ``rejected`` is itself a dict, reason to count.

        Examples
        --------
        >>> import numpy as np, parakin
        >>> m = parakin.load("planar_3rrr", backend="numpy")
        >>> found = m.forward_pose_all(np.deg2rad([-54.0, 174.0, -105.0])).certificate()
        >>> [int(found[key]) for key in ("roots", "with_modes", "root_count", "certified_roots")]
        [6, 6, 6, 6]
        >>> bool(found["complete"]), sum(int(n) for n in found["rejected"].values())
        (True, 0)
        """
        extra: dict[str, object] = {}
        if self.certified_roots is not None and self.root_count is not None and self.path_certified is not None:
            extra = {
                "root_count": np.full(self.certified_roots.shape, self.root_count),
                "certified_roots": self.certified_roots,
                "complete": self.complete(),
                "undecided_roots": self.undecided_roots
                if self.undecided_roots is not None
                else np.zeros(self.certified_roots.shape, np.int64),
                "root_count_proven": np.full(self.certified_roots.shape, self.root_count_proven),
                "uncertified_paths": (~self.path_certified).sum(-1),
                "retracked": self.retracked
                if self.retracked is not None
                else np.zeros(self.certified_roots.shape, bool),
            }
        slots = self.outcome.shape[-1]
        per_root = self.outcome.reshape(self.outcome.shape[:-1] + (slots // self.branch_count, self.branch_count))
        has_root = self.root_kind.reshape(per_root.shape)[..., 0] >= 0
        with_mode = has_root & (per_root == 0).any(-1)
        reason = np.where(has_root & ~with_mode, per_root.max(-1), -1)
        rejected = {name: (reason == code).sum(-1) for code, name in enumerate(self.outcomes) if code > 1}
        return {"roots": has_root.sum(-1), "with_modes": with_mode.sum(-1), "rejected": rejected, **extra}  # type: ignore[dict-item]


class NewtonOutcome(NamedTuple):
    """What a Newton loop returns per entry (both backends): the solution (or the guess where it
    failed), its pose, the residual reached, iterations, status (``errors.NEWTON_*``), pivot ratio
    and determinant sign of the closure Jacobian, and the size of the first step."""

    passive: Array
    pose: Array
    residual: Array
    iterations: NDArray[np.int32]
    status: NDArray[np.int32]
    conditioning: Array
    orientation: NDArray[np.int32]
    first_step: Array


@dataclass(frozen=True)
class Rates:
    """Joint rates from a platform twist: actuated (..., n_a) and passive (..., n_p)."""

    actuated: Array
    passive: Array


# ---------------------------------------------------------------- the modes as tables
def certified_complete(modes: AssemblyModes) -> bool | None:
    """Whether the certificate proves that no assembly mode is missing, for every input: True or
    False from a homotopy's certificate (``AssemblyModes.complete``); None where the method that
    found the modes has no certificate (an elimination), so that nothing is claimed either way.

    Parameters
    ----------
    modes : AssemblyModes
        The result of ``Mechanism.forward_pose_all``, any batch shape.

    Returns
    -------
    bool or None
        True: certified complete at every input; False: a certificate, not complete at some input;
        None: no certificate (``certificate_verdict`` says why in words).

    Examples
    --------
    >>> import parakin
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> certified_complete(m.forward_pose_all(m.home_actuated)) is None  # an elimination
    True
    """
    if modes.certified_roots is None or modes.root_count is None:
        return None
    return bool(np.all(modes.complete()))


def certificate_verdict(modes: AssemblyModes, api_hints: bool = True) -> str:
    """The certificate's verdict in words: "certified complete", what keeps it from being, or, for
    modes of a method without a certificate (an elimination), that nothing certifies them
    complete; ``api_hints`` names the result's field to look at. Never empty.

    Parameters
    ----------
    modes : AssemblyModes
        The result of ``Mechanism.forward_pose_all``, any batch shape.
    api_hints : bool
        Name the result's field that says more (the API's repr), or not (the command line).

    Returns
    -------
    str
        One clause, "certified complete" or starting "not certified complete: ".

    Examples
    --------
    >>> import parakin
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> certificate_verdict(m.forward_pose_all(m.home_actuated))
    'not certified complete: elimination (the real roots of a degree-2 univariate polynomial, in floating point) has no certificate'
    """
    if modes.certified_roots is None or modes.root_count is None:
        slots = int(np.shape(modes.outcome)[-1]) if np.ndim(modes.outcome) else 0
        degree = slots // max(modes.branch_count, 1)
        method = modes.method or "a method without a certificate"
        how = (
            f" (the real roots of a degree-{degree} univariate polynomial, in floating point)"
            if modes.method == "elimination"
            else ""
        )
        return f"not certified complete: {method}{how} has no certificate"
    count = np.asarray(modes.count)
    complete = modes.complete()
    undecided = int(np.sum(modes.undecided_roots)) if modes.undecided_roots is not None else 0
    if complete.all():
        return "certified complete"
    if count.ndim == 0 and not modes.root_count_proven:
        return "not certified complete: the root count is not proven"
    if count.ndim == 0 and int(modes.certified_roots) < modes.root_count:  # type: ignore[call-overload]
        missing = int(modes.root_count) - int(modes.certified_roots)  # type: ignore[call-overload]
        hint = " (modes.path_certified says which paths)" if api_hints else ""
        certified = f"{int(modes.certified_roots)} of {modes.root_count} roots certified"  # type: ignore[call-overload]
        if int(modes.at_infinity) >= missing:  # type: ignore[call-overload]
            # their paths end at 1e6 times the mechanism's size or beyond, or head there (``modes.FAR_ROOT``)
            return (
                f"not certified complete: {certified}, the other {missing} paths head to infinity "
                "(roots at infinity: the input is degenerate; "
                f"no finite root beyond the certified ones is proven absent){hint}"
            )
        return f"not certified complete: {certified}, {missing} not{hint}"
    if count.ndim == 0:  # every root certified, the realness of some undecided
        return (
            f"not certified complete: {undecided} certified root{'s' if undecided != 1 else ''} "
            "of undecided realness (outcome 'uncertified')"
        )
    return f"certified complete for {int(complete.sum())} of {complete.size} inputs"


def modes_summary(modes: AssemblyModes) -> str:
    """One line: input batch, modes found, method, certificate."""
    count = np.asarray(modes.count)
    method = f" by {modes.method}" if modes.method else ""
    if count.ndim == 0:
        found = f"{int(count)} assembly mode{'s' if int(count) != 1 else ''}"
    elif count.size == 0:
        found = f"an empty batch, shape {count.shape}: no inputs"
    else:
        found = f"a batch of {count.size} inputs, shape {count.shape}: {int(count.min())} to {int(count.max())} modes"
    return f"AssemblyModes: {found}{method}; {certificate_verdict(modes)}"


def modes_rows(
    modes: AssemblyModes, residual: bool = False, pose_kind: str | None = None, degrees: bool = True
) -> Rows:
    """One row per mode of a single input: mode k (as ``modes.mode(k)``), the pose coordinates of
    its pose kind (``pose_kind``, default ``modes.pose_kind``: ``parakin.tables.pose_headers``;
    angles in degrees with ``degrees``, else radians, as ``mode_headers`` labels them), the
    closure residual (with ``residual``) and the conditioning."""
    kind = modes.pose_kind if pose_kind is None else pose_kind
    valid = np.flatnonzero(np.asarray(modes.valid))
    width = len(pose_headers(kind))
    poses = pose_values(kind, modes.poses[valid], degrees) if valid.size else np.zeros((0, width))
    conditioning = np.asarray(modes.conditioning)[valid]
    residuals = np.asarray(modes.residual)[valid]
    return [
        [str(k), *(f"{v:.6g}" for v in pose), *([f"{r:.1e}"] if residual else []), f"{c:.3g}"]
        for k, (pose, r, c) in enumerate(zip(poses, residuals, conditioning, strict=True))
    ]


#: the headers of a table of modes of a transform (``mode_headers`` for any pose kind)
MODE_HEADERS = ["mode", *POSE_HEADERS, "conditioning"]


def mode_headers(pose_kind: str, residual: bool = False, degrees: bool = True) -> list[str]:
    """The headers of ``modes_rows`` for pose kind ``pose_kind`` (angles labelled deg with
    ``degrees``, else rad)."""
    return ["mode", *pose_headers(pose_kind, degrees), *(["residual"] if residual else []), "conditioning"]


def modes_convention(pose_kind: str) -> str:
    """The line above a table of modes: the pose convention and what conditioning means."""
    return f"{pose_convention(pose_kind)}; conditioning (type II distance): 1 far from, 0 at a singularity"


def modes_table(
    modes: AssemblyModes,
    residual: bool = False,
    rows_shown: int = ROWS_SHOWN,
    pose_kind: str | None = None,
    degrees: bool = True,
) -> str:
    """The convention line and the table of the modes of a single input (``modes_rows``; angles
    in degrees with ``degrees``, else radians, the headers saying which)."""
    kind = modes.pose_kind if pose_kind is None else pose_kind
    headers = mode_headers(kind, residual, degrees)
    return f"  {modes_convention(kind)}\n" + text_table(
        headers, modes_rows(modes, residual, kind, degrees), rows_shown=rows_shown
    )


def modes_text(modes: AssemblyModes) -> str:
    """``repr(modes)``: the summary line and, for one input, the table of its modes, angles in
    radians as everywhere in the API and on the command line (without a ``-deg`` flag)."""
    lines = [modes_summary(modes)]
    if np.ndim(modes.count) == 0 and int(modes.count):
        lines.append(modes_table(modes, degrees=False))
    elif np.ndim(modes.count):
        lines.append("  modes per input (count): " + np.array2string(np.asarray(modes.count), threshold=20))
    return "\n".join(lines)


def modes_html(modes: AssemblyModes) -> str:
    out = [f"<p><b>{html.escape(modes_summary(modes))}</b></p>"]
    if np.ndim(modes.count) == 0 and int(modes.count):
        kind = modes.pose_kind
        out += [
            f"<p>{html.escape(modes_convention(kind))}</p>",
            html_table(mode_headers(kind, degrees=False), modes_rows(modes, degrees=False)),
        ]
    return "<div class='parakin'>" + "".join(out) + "</div>"


# ---------------------------------------------------------------- the inverse branches as tables
#: failure names that leave a branch's values real (only out of a range): its values are shown
RANGE_FAILURES = ("limits", "actuator_range")


def inverse_summary(result: InversePose) -> str:
    """One line: the branches, their sign symbols and how many are valid (per pose in a batch)."""
    valid = np.asarray(result.valid)
    count = valid.shape[-1]
    signs = f" over the signs of ({', '.join(result.branch_names)})" if result.branch_names else ""
    if valid.ndim == 1:
        return f"InversePose: {count} branch{'es' if count != 1 else ''}{signs}, {int(valid.sum())} valid"
    per = valid.sum(-1)
    return (
        f"InversePose: a batch of poses, shape {per.shape}, {count} branches each{signs}; "
        f"{int(per.min())} to {int(per.max())} valid per pose"
    )


def inverse_rows(result: InversePose) -> Rows:
    """One row per branch of a single pose: number, signs, actuated values (SI: m, rad; "-" where
    the branch is not reachable, its numbers being no configuration) and validity (or the
    conditions that failed)."""
    rows = []
    for k in range(np.asarray(result.valid).shape[-1]):
        failed = [name for name, mask in result.failures.items() if np.asarray(mask)[k]]
        real = bool(result.valid[k]) or all(name in RANGE_FAILURES for name in failed)
        values = ", ".join(f"{round(float(v), 12) + 0.0:.6g}" for v in result.actuated[k]) if real else "-"
        signs = " ".join("+" if s > 0 else "-" for s in result.branches[k]) or "(none)"
        rows.append([str(k), signs, values, "yes" if result.valid[k] else "no: " + ", ".join(failed)])
    return rows


INVERSE_HEADERS = ["branch", "signs", "actuated (m, rad)", "valid"]


def inverse_text(result: InversePose) -> str:
    lines = [inverse_summary(result)]
    if np.ndim(result.valid) == 1:
        lines.append(text_table(INVERSE_HEADERS, inverse_rows(result)))
    return "\n".join(lines)


def inverse_html(result: InversePose) -> str:
    out = [f"<p><b>{html.escape(inverse_summary(result))}</b></p>"]
    if np.ndim(result.valid) == 1:
        out.append(html_table(INVERSE_HEADERS, inverse_rows(result)))
    return "<div class='parakin'>" + "".join(out) + "</div>"
