"""The runtime mechanism: thin wrappers that validate input, call generated kernels through a
backend, and return named results. Conventions are those of the mechanism's generated manifest
(``m.manifest``, its ``conventions`` text is the mechanism file's docstring): SI units, radians, poses as
^B_P T (..., 4, 4), twists as (v of the origin of {P}, w), both in {B}.
"""

from __future__ import annotations

import ctypes
import functools
import inspect
import threading
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from parakin.errors import (
    NEWTON_NO_CONVERGENCE,
    NEWTON_NONFINITE,
    NEWTON_OK,
    NEWTON_SINGULAR,
    NEWTON_WRONG_BASIN,
    BadInputError,
    FixedModelError,
    InconsistentInputError,
    SelfMotionError,
    SingularConfigurationError,
    UnreachablePoseError,
    UnsupportedOperationError,
    at_index,
    first_index,
    raise_for_newton_status,
)
from parakin.log import progress
from parakin.packages.backends import Backend
from parakin.packages.manifest import Capabilities, Forward, Manifest, Variable
from parakin.packages.package import GeneratedPackage
from parakin.pose import (
    LEG_TWIST,
    POSE_KINDS,
    RIGID_TOLERANCE,
    as_array,
    pose_vector,
    rigid_or_nan,
    rigidity_error,
    transform_from_pose,
    wrap_angle,
)
from parakin.results import (
    Array,
    AssemblyModes,
    Configuration,
    DeferredConditioning,
    ForwardPose,
    InversePose,
    Mask,
    NewtonOutcome,
    Rates,
)
from parakin.solvers import tracker as tracking
from parakin.solvers.continuation import LeastSquares, SelfMotion, least_squares_configuration, trace_self_motion
from parakin.solvers.linalg import inverse_condition, pivoted_solve
from parakin.solvers.modes import (
    SCALED_UNITS,
    assemble,
    certified_modes,
    compiled_modes,
    length_scale,
    length_unit,
    numpy_modes,
)
from parakin.solvers.tracker import ForwardPoseTracker
from parakin.validation import (
    MAX_MAGNITUDE,
    bounded_vector,
    broadcast_shapes,
    integer_in_range,
    keywords_checked,
    newton_tolerance,
    positive_number,
    within_ranges,
)

STATUS_OK, STATUS_NO_CONVERGENCE, STATUS_SINGULAR, STATUS_WRONG_BASIN = (
    NEWTON_OK,
    NEWTON_NO_CONVERGENCE,
    NEWTON_SINGULAR,
    NEWTON_WRONG_BASIN,
)
#: a lower-mobility platform's twist must satisfy constraints @ twist = 0 to this relative
#: measure, |C_i . twist| / (|C_i| |twist|) per constraint wrench C_i (``inverse_rate``)
CONSTRAINT_TOLERANCE = 1e-6
#: the fewest inputs per step of a batch of ``forward_pose_all`` that shows a progress bar
BAR_STEP = 256
#: ``forward_pose_all`` of at most this many inputs measures its modes' conditioning when it is
#: first read (``results.DeferredConditioning``: the closure Jacobians are kept until then); a
#: larger batch measures it at once
DEFER_CONDITIONING = 64
#: the continuation step ``self_motion`` takes by default (m or rad): a traced curve that moves by
#: half of it is a self-motion, not an isolated configuration found again and again
SELF_MOTION_STEP = 0.02


def _home(variable: Variable) -> float:
    return 0.0 if variable.home is None else variable.home


class FixedMapping(dict):  # type: ignore[type-arg]
    """A loaded mechanism's parameters, limits or actuator ranges: read like a dict (and written
    to JSON as one); any assignment raises FixedModelError, since every solver and cached value
    was set up from them (an assignment that changed nothing would be an ignored option)."""

    def __init__(self, what: str, values: Mapping[str, Any]) -> None:
        super().__init__(values)
        self._what = what

    def __reduce__(self) -> tuple[type, tuple[str, dict[str, Any]]]:  # copies and pickles: built anew
        return (FixedMapping, (self._what, dict(self)))

    def _refuse(self, *args: object, **kwargs: object) -> None:
        raise FixedModelError(
            f"a loaded mechanism's {self._what} are fixed (every solver was set up with them); load another "
            "with other values: parakin.load(name, <parameter>=value, limits={...}, actuated_ranges={...})"
        )

    __setitem__ = __delitem__ = update = pop = popitem = clear = setdefault = __ior__ = _refuse  # type: ignore[assignment]


class Mechanism:
    """A loaded mechanism. Build with ``parakin.load(name, **parameters)``.

    Every method accepts a leading batch shape. Branch numbering of ``inverse_pose``: branch k
    has the signs ``InversePose.branches[k]`` of ``m.capabilities.inverse.branches`` (branch 0:
    all +1, then binary counting with -1 as the set bit, most significant first).
    """

    def __init__(
        self,
        package: GeneratedPackage,
        backend: Backend,
        parameters: dict[str, float],
        limits: dict[str, tuple[float, float]],
        actuated_ranges: Mapping[str, tuple[float, float]] | None = None,
    ) -> None:
        self.package = package
        self.manifest: Manifest = package.manifest
        manifest = self.manifest
        self.name: str = manifest.name
        self.backend = backend
        self.parameters: dict[str, float] = FixedMapping("parameters", parameters)
        self.params = np.array([parameters[p.name] for p in manifest.parameters], dtype=float)
        self.params.flags.writeable = False  # the model is fixed: load another for other values
        self.actuated_names: list[str] = manifest.actuated_names
        self.passive_names: list[str] = manifest.passive_names
        self.tolerances = manifest.tolerances
        self.limits: dict[str, tuple[float, float]] = FixedMapping("limits", limits)
        self._limit_index = np.array([self.passive_names.index(name) for name in limits], dtype=np.intp)
        self._limit_low = np.array([low for low, _ in limits.values()], dtype=float)
        self._limit_high = np.array([high for _, high in limits.values()], dtype=float)
        #: per actuated variable (low, high): the manifest's declared range (actuator strokes, leg
        #: lengths >= 0) unless ``load(limits=...)`` overrides it; every solver checks these
        self.actuated_ranges: dict[str, tuple[float, float]] = FixedMapping(
            "actuated_ranges", {v.name: (actuated_ranges or {}).get(v.name, v.limits) for v in manifest.actuated}
        )
        bounds = np.array(list(self.actuated_ranges.values()), dtype=float).reshape(-1, 2)
        self._actuated_low = np.maximum(bounds[:, 0], -MAX_MAGNITUDE)
        self._actuated_high = np.minimum(bounds[:, 1], MAX_MAGNITUDE)
        self._single_input = threading.local()  # forward_pose_all's reusable one-input job
        # the compiled Newton call for one input, built on first use, one per thread: ctypes
        # releases the GIL during the call, so threads must not share its buffers
        self._single_jobs = threading.local()
        self._angular_passive = np.array([v.revolute for v in manifest.passive], dtype=bool)
        self._angular_actuated = np.array([v.revolute for v in manifest.actuated], dtype=bool)
        self.home_actuated = np.array([_home(v) for v in manifest.actuated], dtype=float)
        self.home_passive = np.array([_home(v) for v in manifest.passive], dtype=float)
        # each leg's joints as (is_actuated, index into actuated or passive)
        self._leg_columns = {
            leg.name: [
                (True, self.actuated_names.index(j))
                if j in self.actuated_names
                else (False, self.passive_names.index(j))
                for j in leg.joints
            ]
            for leg in manifest.capabilities.legs or ()
        }
        self._sealed = True

    #: the model's values: fixed (FixedModelError), as every solver and cached value was set up with them
    _FIXED = frozenset({"parameters", "params", "limits", "actuated_ranges"})

    def __setattr__(self, name: str, value: Any) -> None:
        if name in self._FIXED and getattr(self, "_sealed", False):
            raise FixedModelError(
                f"{self.name}.{name} is fixed (every solver was set up with it); load another with other values: "
                f"parakin.load({self.name!r}, <parameter>=value, limits={{...}}, actuated_ranges={{...}})"
            )
        super().__setattr__(name, value)

    @property
    def capabilities(self) -> Capabilities:
        """What this mechanism supports (closed-form inverse, forward elimination, rates, ...)."""
        return self.manifest.capabilities

    def _require(self, capability: object, operation: str, what: str) -> None:
        if capability is None:
            raise UnsupportedOperationError(f"{self.name} has no {what}: {operation} is not available")

    def __repr__(self) -> str:
        values = ", ".join(f"{k}={v:g}" for k, v in self.parameters.items())
        return f"parakin.load({self.name!r}, {values})  # backend {self.backend.name}"

    def __str__(self) -> str:
        """Tables of the parameters (values, units), variables (kinds, units, home, limits),
        capabilities and named examples, under the title and citation."""
        from parakin.interfaces.display import mechanism_text

        return mechanism_text(self)

    def _repr_html_(self) -> str:
        from parakin.interfaces.display import mechanism_html

        return mechanism_html(self)

    # ------------------------------------------------------------------ input checks
    def _actuated(self, value: ArrayLike) -> Array:
        """Actuated values (..., n_a): finite reals inside each actuator's declared range."""
        theta = as_array(value, "actuated", (len(self.actuated_names),))
        within_ranges(theta, self.actuated_names, self._actuated_low, self._actuated_high, "actuated")
        return theta

    def _passive(self, value: ArrayLike) -> Array:
        """Passive values (..., n_p): finite reals of magnitude at most MAX_MAGNITUDE (m or rad)."""
        return bounded_vector(value, "passive", self.passive_names)

    def _state(self, state: Configuration) -> tuple[Array, Array]:
        if not isinstance(state, Configuration):
            raise BadInputError(f"state must be a Configuration (from a solver), got {type(state).__name__}")
        return self._actuated(state.actuated), self._passive(state.passive)

    def _finite(self, kernel: str, theta: Array, passive: Array) -> dict[str, Array]:
        """A kernel of the state whose every output is finite, or BadInputError at the first batch
        index where it is not (values too large for doubles, or a model undefined there)."""
        with np.errstate(all="ignore"):
            out = self.backend.call(kernel, theta, passive, self.params)
        shapes = {output.name: output.shape for output in self.manifest.kernels[kernel].outputs}
        for name, value in out.items():
            bad = ~np.isfinite(value)
            if bad.any():
                where = first_index(bad)[: value.ndim - len(shapes[name])]
                raise BadInputError(
                    f"{kernel}: {name} is not finite at batch index {where} (the state is too large for "
                    "double precision, or the model is undefined there)"
                )
        return out

    @property
    def actuated_bounds(self) -> tuple[Array, Array]:
        """(low, high), each (n_a,): the actuated ranges every solver checks (``actuated_ranges``,
        within the largest accepted magnitude)."""
        return self._actuated_low, self._actuated_high

    def within_limits(self, passive: ArrayLike) -> np.ndarray:
        """Whether passive values lie inside the passive joint limits ``limits`` (open intervals).

        Parameters
        ----------
        passive : array_like, shape (..., n_p)
            Passive joint values (m or rad, in ``passive_names`` order), any leading batch shape.
            NaN and infinite entries are accepted and are never within the limits.

        Returns
        -------
        numpy.ndarray of bool, shape (...)
            True where every limited passive value lies strictly inside its limits.

        Raises
        ------
        BadInputError
            ``passive`` is not numeric or its last axis is not n_p long.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> m.within_limits([[0.0, 0.33], [float("nan"), 0.33]]).tolist()
        [True, False]
        """
        checked = as_array(passive, "passive", (len(self.passive_names),), finite=False)
        values = checked[..., self._limit_index]
        finite = np.isfinite(checked).all(-1)
        return np.asarray(((values > self._limit_low) & (values < self._limit_high)).all(-1) & finite)

    # ------------------------------------------------------------------ pose kernels
    def platform_pose(self, actuated: ArrayLike, passive: ArrayLike) -> Array:
        """The platform pose ^B_P T from joint values, through the mechanism's pose kernel.

        The kernel is e.g. the first leg's forward chain (eq 2-3); the result is always a rigid
        transform (rotation orthonormal to rounding). A kernel that reads the platform from several
        legs gives a rigid pose only where the joint values close the loop.

        Parameters
        ----------
        actuated : array_like, shape (..., n_a)
            Actuated values (m or rad), inside ``actuated_ranges``.
        passive : array_like, shape (..., n_p)
            Passive values (m or rad); batch axes broadcast against ``actuated``.

        Returns
        -------
        numpy.ndarray, shape (..., 4, 4)
            ^B_P T: the platform frame {P} in the base frame {B} (metres).

        Raises
        ------
        BadInputError
            A value outside its range, non-finite, or a kernel output that is not finite.
        InconsistentInputError
            The joint values do not close the loop and give no rigid pose (rotation off orthonormal
            by more than 1e-6): the message names the batch index and the loop-closure residual.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> m.platform_pose(m.home_actuated, m.home_passive)[:3, 3].round(3).tolist()
        [0.0, 0.33, 0.0]
        """
        theta, q = self._actuated(actuated), self._passive(passive)
        kernel = self._finite("platform_pose", theta, q)["pose"]
        pose, rigid = rigid_or_nan(kernel)
        if not rigid.all():
            index = first_index(~rigid)
            with np.errstate(all="ignore"):
                closure = self.backend.call("loop_closure", theta, q, self.params)["residual"]
            shape = np.broadcast_shapes(theta.shape[:-1], q.shape[:-1])
            residual = np.abs(np.broadcast_to(closure, shape + closure.shape[-1:])[index]).max(initial=0.0)
            rotation = np.broadcast_to(kernel, shape + (4, 4))[index][:3, :3]
            raise InconsistentInputError(
                f"platform_pose{at_index(index)}: the joint values do not close the loop (closure residual "
                f"{residual:.3g}, tolerance {self.tolerances['closure']:g}) and give no rigid pose "
                f"(|R^T R - I| = {float(rigidity_error(kernel[index])):.3g}, det R = {np.linalg.det(rotation):.4g}); "
                "pass joint values that close (from forward_pose, forward_pose_all or inverse_pose)"
            )
        return pose

    def loop_closure(self, actuated: ArrayLike, passive: ArrayLike) -> dict[str, Array]:
        """The loop-closure residual and its passive Jacobian (``parakin inspect`` shows them symbolically).

        Parameters
        ----------
        actuated : array_like, shape (..., n_a)
            Actuated values (m or rad), inside ``actuated_ranges``.
        passive : array_like, shape (..., n_p)
            Passive values (m or rad); batch axes broadcast.

        Returns
        -------
        dict of str to numpy.ndarray
            ``residual`` (..., n_p): position difference (m) and rotation error (rad) between the
            legs, zero where the loop closes; ``jacobian`` (..., n_p, n_p): its derivative in the
            passive values; ``alignment`` (..., k): measures that are positive on a true closure
            (not a half-turn or mirror).

        Raises
        ------
        BadInputError
            An input out of range or non-finite, or an output that is not finite.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> out = m.loop_closure(m.home_actuated, m.home_passive)
        >>> sorted(out), bool(abs(out["residual"]).max() < 1e-12)
        (['alignment', 'jacobian', 'residual'], True)
        """
        return self._finite("loop_closure", self._actuated(actuated), self._passive(passive))

    def _as_transform(self, pose: ArrayLike, name: str = "pose") -> Array:
        """^B_P T (..., 4, 4), or the short form of the pose kind (``parakin.pose.POSE_KINDS``);
        positions of magnitude above MAX_MAGNITUDE are refused, like every other input."""
        transform = transform_from_pose(pose, self.manifest.pose_kind, name)
        bound = np.full(3, MAX_MAGNITUDE)
        within_ranges(transform[..., :3, 3], ["x", "y", "z"], -bound, bound, f"{name} position")
        return transform

    def inverse_pose(self, pose: ArrayLike, strict: bool = True, onto_reachable: bool = False) -> InversePose:
        """Every closed-form inverse branch for a platform pose.

        Branch k has the signs ``InversePose.branches[k]`` (branch 0: all +1, then binary counting
        with -1 as the set bit, most significant first).

        Parameters
        ----------
        pose : array_like, shape (..., 4, 4)
            ^B_P T in metres, or the short form of the pose kind (``m.manifest.pose_kind``, e.g.
            R (..., 3, 3) for an orienting platform, see ``parakin.pose.POSE_KINDS``).
        strict : bool
            Raise when a pose has no valid branch (default); with False such poses come back with
            every ``valid`` entry False and the reasons in ``failures``.
        onto_reachable : bool
            For a lower-mobility platform whose inverse reads a pose onto its reachable set
            (``m.manifest.capabilities.inverse.reading``: the controlled coordinates, e.g. a
            3-RPS's height p . k and tilt R^T k, kept and the parasitic ones as the platform
            reaches them): True answers with the configurations of the reached pose, valid
            where they are (their pose in ``InversePose.pose``), instead of marking a pose off
            the reachable set invalid (default False: the asked pose must be reachable as given).
            A mechanism declared ``unreachable="read"`` (prs3) already answers so: True changes
            nothing there.

        Returns
        -------
        InversePose
            ``actuated`` (..., K, n_a), ``passive`` (..., K, n_p), ``valid`` (..., K) for the K
            branches; ``branch(k)`` is one branch as a Configuration; ``pose`` the pose the
            configurations reach (a lower-mobility platform's reading of the asked pose).

        Raises
        ------
        UnsupportedOperationError
            The mechanism has no closed-form inverse; or ``onto_reachable`` where its inverse
            reads no pose onto a reachable set (full mobility: every pose is taken as given; or
            a lower-mobility platform with no derived reading).
        BadInputError
            A pose that is not rigid, not finite, or too far away; ``onto_reachable`` not a bool.
        UnreachablePoseError
            With ``strict``: joint limits, actuator ranges or reach conditions fail on every branch
            (the message names the pose index).
        SingularConfigurationError
            With ``strict``: every branch is at a serial singularity.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> branches = m.inverse_pose(m.platform_pose(m.home_actuated, m.home_passive))
        >>> branches.valid.tolist()
        [True, True, True, True]
        >>> branches.actuated[0].round(3).tolist()  # branch 0 is the home input
        [1.865, 1.276]

        A 3-RPS asked for a height and a tilt (x = y = 0 is off its reachable set when tilted):

        >>> rps3 = parakin.load("rps3", backend="numpy")
        >>> tilted = parakin.pose_from_xyz_euler([0.0, 0.0, 1.0, 0.0, 0.2, 0.0])
        >>> rps3.inverse_pose(tilted, strict=False).valid.tolist()
        [False]
        >>> reached = rps3.inverse_pose(tilted, onto_reachable=True)
        >>> reached.valid.tolist(), round(float(reached.pose[1, 3]), 4)  # the parasitic y
        ([True], 0.005)
        """
        info = self.capabilities.inverse
        self._require(info, "inverse_pose", "closed-form inverse")
        assert info is not None
        if not isinstance(onto_reachable, (bool, np.bool_)):
            raise BadInputError(f"onto_reachable must be True or False, got {onto_reachable!r}")
        ignored = self._reading_conditions(info) if onto_reachable else ()
        transform = self._as_transform(pose)
        combinations = np.array(info.combinations, dtype=np.int8)
        with np.errstate(all="ignore"):  # singular or unreachable branches: masked below
            out = self.backend.call(
                "inverse_pose", pose_vector(transform)[..., None, :], combinations.astype(float), self.params
            )
        actuated = np.where(self._angular_actuated, wrap_angle(out["actuated"]), out["actuated"])
        passive = np.where(self._angular_passive, wrap_angle(out["passive"]), out["passive"])
        failures: dict[str, np.ndarray] = {
            name: np.asarray(~(out["validity"][..., k] > self.tolerances["validity"]))
            for k, name in enumerate(info.validity)
        }
        failures["limits"] = np.asarray(~self.within_limits(passive))
        with np.errstate(invalid="ignore"):
            failures["actuator_range"] = np.asarray(
                ~((actuated >= self._actuated_low) & (actuated <= self._actuated_high)).all(-1)
            )
        failures["finite"] = np.asarray(~(np.isfinite(actuated).all(-1) & np.isfinite(passive).all(-1)))
        for name in ignored:  # the asked pose off the set: the reached pose's values answer
            del failures[name]
        valid = ~np.logical_or.reduce(list(failures.values()))
        if self._freedoms[0] < self._freedoms[1]:  # lower mobility: the inverse reads the pose
            transform = self._reached_pose(actuated, passive, valid, transform)
        result = InversePose(actuated, passive, valid, combinations, info.branches, failures, transform)
        if strict:
            none = ~valid.any(-1)
            if none.any():
                index = first_index(none)
                failed = [name for name, mask in failures.items() if mask[index].all()]
                at = at_index(index)
                # joint limits, actuator ranges and reach conditions bound the workspace; anything
                # else failing on every branch is a leg that cannot be resolved
                if failed and all(
                    name in ("limits", "actuator_range") or name.endswith("reachable") for name in failed
                ):
                    detail = f" (joint limits {dict(self.limits)})" if "limits" in failed else ""
                    reading = info.reading
                    if reading is not None and set(reading.reachable) & set(failed) and not onto_reachable:
                        detail += (
                            f"; the pose is off the set {self.name}'s platform reaches: "
                            "inverse_pose(pose, onto_reachable=True) (--onto-reachable) answers with the pose it reaches"
                        )
                    raise UnreachablePoseError(f"pose{at} is unreachable on every branch: {', '.join(failed)}{detail}")
                raise SingularConfigurationError(
                    f"pose{at} has no valid inverse branch: {', '.join(failed) or 'mixed failures'} "
                    "(serial singularity: the leg joints cannot be resolved)"
                )
        return result

    @functools.cached_property
    def _freedoms(self) -> tuple[int, int]:
        """(actuated variables, coordinates of the pose kind): fewer of the first, a lower-mobility
        platform, whose inverse reads a pose onto the set it reaches."""
        return len(self.actuated_names), len(POSE_KINDS[self.manifest.pose_kind].coordinates)

    def _reading_conditions(self, info: Any) -> tuple[str, ...]:
        """The validity conditions ``inverse_pose(onto_reachable=True)`` leaves out: those the
        manifest names as testing the asked pose against the reachable set its inverse reads
        onto; UnsupportedOperationError where the inverse reads no pose onto a reachable set."""
        if info.reading is not None:
            return tuple(info.reading.reachable)
        freedoms, coordinates = self._freedoms
        if freedoms >= coordinates:
            raise UnsupportedOperationError(
                f"{self.name}: onto_reachable=True (--onto-reachable) reads a pose onto a lower-mobility platform's reachable set, and "
                f"{self.name}'s platform has full mobility ({freedoms} actuated variables for the {coordinates} "
                f"coordinates of pose kind {self.manifest.pose_kind!r}): every pose it reaches is taken as given; "
                "leave the option out"
            )
        raise UnsupportedOperationError(
            f"{self.name}: onto_reachable=True (--onto-reachable) needs an inverse that reads a pose onto the reachable set, and "
            f"{self.name}'s inverse ({freedoms} actuated variables for the {coordinates} coordinates of pose kind "
            f"{self.manifest.pose_kind!r}) takes the pose as given: ask for a reachable pose (inverse_pose's "
            "failures name the conditions it breaks)"
        )

    def _reached_pose(self, actuated: Array, passive: Array, valid: Mask, pose: Array) -> Array:
        """The pose a lower-mobility platform reaches for ``pose``: its inverse reads the
        coordinates the actuators control and returns the configuration on the reachable set
        (prs3's parasitic motion, a pointing chain's roll), whose pose the configurations must
        carry. The same for every valid branch; the given pose where no branch is valid (only
        valid values are evaluated: an invalid branch's may leave a range, which platform_pose
        refuses)."""
        first = np.argmax(valid, axis=-1)[..., None, None]
        chosen_actuated = np.take_along_axis(actuated, first, axis=-2)[..., 0, :]
        chosen_passive = np.take_along_axis(passive, first, axis=-2)[..., 0, :]
        some = np.asarray(valid.any(-1))
        reached = np.array(np.broadcast_to(pose, some.shape + (4, 4)), dtype=float)
        if some.any():
            with np.errstate(all="ignore"):
                reached[some] = self.platform_pose(chosen_actuated[some], chosen_passive[some])
        return reached

    # ------------------------------------------------------------------ forward pose (Newton)
    def _passive_guess(self, actuated: Array, guess: Any) -> Array:
        if guess is None and self.capabilities.forward is not None:
            return self._closest_mode_to_home(actuated)
        if guess is None:
            return np.broadcast_to(self.home_passive, actuated.shape[:-1] + self.home_passive.shape)
        if isinstance(guess, Configuration):
            return self._passive(guess.passive)
        array = as_array(guess, "guess", ())
        # (..., 4, 4) is a pose (^B_P T); anything else is passive values (..., n_p): a (3, 3)
        # array is three passive vectors, never a rotation (pass a 4x4 or a Configuration). With
        # four passive values (a quaternion), four guesses are also (4, 4): a pose has the last
        # row (0, 0, 0, 1) and a rotation block; anything else is the passive values
        four = len(self.passive_names) == 4
        if array.shape[-2:] == (4, 4) and (not four or bool((rigidity_error(array) <= RIGID_TOLERANCE).all())):
            return self.passive_from_pose(actuated, array)
        return self._passive(array)

    def _closest_mode_to_home(self, actuated: Array) -> Array:
        """Without a guess: the assembly mode nearest the home configuration, or home itself
        where the input has no mode. Only valid modes seed Newton: a slot that is not a mode
        (a complex endpoint, a candidate that did not close) can hold any value."""
        modes = self.forward_pose_all(actuated, strict=False)
        # nearest by pose, not by passive values: a quaternion and its negative, or two Euler
        # readings, are one pose far apart in the passive values
        home = np.asarray(self.platform_pose(self.home_actuated, self.home_passive))
        turn = np.abs(modes.poses[..., :3, :3] - home[:3, :3]).max((-2, -1))
        move = np.abs(modes.poses[..., :3, 3] - home[:3, 3]).max(-1) / length_scale(self)
        distance = np.where(modes.valid, np.maximum(turn, move), np.inf)
        distance = np.where(np.isfinite(distance), distance, np.inf)  # argmin would pick a NaN
        best = np.argmin(distance, axis=-1)
        fallback = np.broadcast_to(self.home_passive, modes.passive.shape[:-2] + self.home_passive.shape)
        chosen = np.take_along_axis(modes.passive, best[..., None, None], axis=-2)[..., 0, :]
        return np.where(np.asarray(modes.valid.any(-1))[..., None], chosen, fallback)

    def passive_from_pose(self, actuated: ArrayLike, pose: ArrayLike) -> Array:
        """The passive values of the inverse branch whose actuated values match ``actuated``.

        Parameters
        ----------
        actuated : array_like, shape (..., n_a)
            Actuated values (m or rad).
        pose : array_like, shape (..., 4, 4)
            ^B_P T (metres) or the pose kind's short form; batch axes broadcast.

        Returns
        -------
        numpy.ndarray, shape (..., n_p)
            Passive values (m or rad) of the best-matching valid branch.

        Raises
        ------
        UnsupportedOperationError
            The mechanism has no closed-form inverse.
        BadInputError
            An input out of range, non-finite or not rigid.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> pose = m.platform_pose(m.home_actuated, m.home_passive)
        >>> m.passive_from_pose(m.home_actuated, pose).round(3).tolist()
        [0.0, 0.33]
        """
        theta = self._actuated(actuated)
        branches = self.inverse_pose(pose, strict=False)
        difference = np.where(
            self._angular_actuated,
            wrap_angle(branches.actuated - theta[..., None, :]),
            branches.actuated - theta[..., None, :],
        )
        mismatch = np.abs(difference).max(-1) + np.where(branches.valid, 0.0, 1e3)
        mismatch = np.where(np.isfinite(mismatch), mismatch, np.inf)  # argmin would pick a NaN
        best = np.argmin(mismatch, axis=-1)
        # one pose for a batch of inputs (or the reverse) broadcasts like every other argument
        passive = np.broadcast_to(branches.passive, mismatch.shape + branches.passive.shape[-1:])
        return np.take_along_axis(passive, best[..., None, None], axis=-2)[..., 0, :]

    def forward_pose(
        self,
        actuated: ArrayLike,
        guess: Configuration | ArrayLike | None = None,
        tolerance: float = 1e-12,
        max_iterations: int = 30,
        max_step: float = 0.5,
        strict: bool = True,
    ) -> ForwardPose:
        """Forward pose by Newton on the loop closure in the passive variables.

        The residual is the position difference and rotation error between the legs (max-norm,
        metres and radians). Poses are rigid: a converged entry whose pose kernel is not rigid at
        the tolerance asked for gets the nearest rotation; an entry that did not converge
        (``strict=False``) keeps its guess as ``passive``, and its ``pose`` is NaN unless that guess
        gives a rigid pose.

        Parameters
        ----------
        actuated : array_like, shape (..., n_a)
            Actuated values (m or rad), inside ``actuated_ranges``.
        guess : Configuration or array_like or None
            A previous result (tracking), passive values (..., n_p), a pose ^B_P T (..., 4, 4), or
            None: the valid assembly mode nearest the home configuration (eq 15 for SAM) seeds
            Newton, or the home configuration itself when there is no closed form or no mode.
        tolerance : float
            Newton stops when the residual's max-norm is below this (m and rad).
        max_iterations : int
            The most Newton steps.
        max_step : float
            The largest step in any passive value (m or rad).
        strict : bool
            Raise on any entry that did not converge (default); with False, read ``converged``.

        Returns
        -------
        ForwardPose
            A Configuration (``actuated``, ``passive`` (..., n_p), ``pose`` (..., 4, 4)) with
            ``residual``, ``iterations``, ``converged`` and ``within_limits`` per entry.

        Raises
        ------
        BadInputError
            An input out of range or non-finite, or a loop closure undefined at the guess (e.g. a
            zero quaternion).
        ConvergenceError
            With ``strict``: Newton did not converge (the residual reached is in the message).
        SingularConfigurationError
            With ``strict``: the Newton matrix is singular (a type II singularity).

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> solved = m.forward_pose(m.home_actuated)
        >>> bool(solved.converged), solved.passive.round(3).tolist()
        (True, [0.0, 0.33])
        """
        theta = self._actuated(actuated)
        tolerance = newton_tolerance(tolerance)
        max_iterations = integer_in_range(max_iterations, "max_iterations")
        max_step = positive_number(max_step, "max_step")
        if not self.passive_names and guess is not None and not isinstance(guess, Configuration):
            # a serial chain: only an empty guess (..., 0) is consistent; its batch broadcasts
            empty = self._passive(guess)
            theta = np.broadcast_to(theta, broadcast_shapes(theta.shape[:-1], empty.shape[:-1]) + theta.shape[-1:])
        if not self.passive_names:  # a serial chain: the forward pose is the chain itself
            pose = self.platform_pose(theta, np.zeros(theta.shape[:-1] + (0,)))
            batch = theta.shape[:-1]
            done = np.ones(batch, dtype=bool)
            return ForwardPose(
                theta, np.zeros(batch + (0,)), pose, np.zeros(batch), np.zeros(batch, np.int32), done, done
            )
        guess_passive = self._passive_guess(theta, guess)
        batch = broadcast_shapes(theta.shape[:-1], guess_passive.shape[:-1])
        start = np.broadcast_to(guess_passive, batch + guess_passive.shape[-1:])
        theta = np.broadcast_to(theta, batch + theta.shape[-1:])
        if self.backend.name == "compiled":
            solved = self._newton_compiled(theta, start, tolerance, max_iterations, max_step)
        else:
            solved = self._newton_python(theta, start, tolerance, max_iterations, max_step)
        passive, pose, residual, iterations, status = solved[:5]
        passive = np.where(self._angular_passive, wrap_angle(passive), passive)
        converged = status == STATUS_OK
        # poses are rigid: a converged entry that closes only to a loose tolerance gets the
        # nearest rotation; one that did not converge keeps its guess, whose pose is NaN where
        # the guess gives no rigid pose (a kernel reading several legs)
        pose = rigid_or_nan(pose, keep=converged)[0]
        if strict:
            raise_for_newton_status(status, residual, iterations, "forward pose", tolerance, max_iterations, start)
        return ForwardPose(np.array(theta), passive, pose, residual, iterations, converged, self.within_limits(passive))

    def _newton_python(
        self,
        theta: Array,
        start: Array,
        tolerance: float,
        max_iterations: int,
        max_step: float,
        keep_last: bool = False,
    ) -> NewtonOutcome:
        """The NumPy Newton loop (same steps and statuses as the C driver's ``newton``); a failed
        entry returns its guess, or with ``keep_last`` its last iterate."""
        q = np.array(start, dtype=float)
        batch = q.shape[:-1]
        status = np.full(batch, STATUS_NO_CONVERGENCE, dtype=np.int32)
        iterations = np.zeros(batch, dtype=np.int32)
        residual_norm = np.full(batch, np.nan)
        conditioning = np.full(batch, np.nan)
        orientation = np.zeros(batch, dtype=np.int32)
        first_step = np.full(batch, np.nan)
        # as in the C driver: non-finite inputs are reported, not iterated
        finite_input = np.isfinite(np.broadcast_to(theta, batch + theta.shape[-1:])).all(-1) & np.isfinite(q).all(-1)
        status[~finite_input] = NEWTON_NONFINITE
        active = finite_input.copy()
        q = np.where(finite_input[..., None], q, 0.0)
        for iteration in range(max_iterations + 1):
            with np.errstate(all="ignore"):  # entries where the closure is undefined: flagged below
                out = self.backend.call("loop_closure", theta, q, self.params)
            norm = np.abs(out["residual"]).max(-1)
            residual_norm = np.where(active, norm, residual_norm)
            iterations = np.where(active, iteration, iterations)
            active &= np.isfinite(norm)
            # a half-turn between legs zeroes the rotation error too: a wrong basin, not a closure
            done = active & (norm < tolerance)
            wrong = done & ~(out["alignment"] > 0.0).all(-1)
            status[wrong] = STATUS_WRONG_BASIN
            active &= ~wrong
            done &= active
            if iteration == max_iterations:
                active &= done
            # checked at convergence too: a zero residual does not reveal a type II singularity
            # a Jacobian that is not finite (e.g. a zero-length leg) is a singularity of the closure
            defined = np.asarray(np.isfinite(out["jacobian"]).all(axis=(-2, -1)))
            jacobian = np.where(defined[..., None, None], out["jacobian"], 0.0)
            step, ratio, sign = pivoted_solve(jacobian, np.where(np.isfinite(out["residual"]), out["residual"], 0.0))
            conditioning = np.where(active, ratio, conditioning)
            orientation = np.where(active, sign, orientation)
            if iteration == 0:
                first_step = np.where(active, np.abs(step).max(-1, initial=0.0), first_step)
            singular = active & ~(ratio > self.tolerances["singular_ratio"])
            status[singular] = STATUS_SINGULAR
            status[done & ~singular] = STATUS_OK
            active &= ~singular & ~done
            if not active.any():
                break
            step = np.where(active[..., None], step, 0.0)
            size = np.abs(step).max(-1, keepdims=True)
            scale = np.where(size > max_step, max_step / np.maximum(size, 1e-300), 1.0)
            q = np.where(active[..., None], q - scale * step, q)
        # as in the C driver: a failed entry keeps its guess, never a diverged iterate
        q = np.where(((status == STATUS_OK) | keep_last)[..., None], q, start)
        status = np.where((status == STATUS_NO_CONVERGENCE) & ~np.isfinite(residual_norm), NEWTON_NONFINITE, status)
        with np.errstate(all="ignore"):  # a guess where the model is undefined: NaN, flagged by status
            pose = self.backend.call("platform_pose", theta, q, self.params)["pose"]
        return NewtonOutcome(q, pose, residual_norm, iterations, status, conditioning, orientation, first_step)

    def _newton_compiled(
        self, theta: Array, start: Array, tolerance: float, max_iterations: int, max_step: float
    ) -> NewtonOutcome:
        batch = theta.shape[:-1]
        if batch == ():
            return self._newton_compiled_single(theta, start, tolerance, max_iterations, max_step)
        count = int(np.prod(batch, dtype=np.int64))
        theta_c = np.ascontiguousarray(theta, dtype=float)
        start_c = np.ascontiguousarray(start, dtype=float)
        out: dict[str, Any] = {
            "passive": np.empty(batch + start.shape[-1:]),
            "pose": np.empty(batch + (4, 4)),
            "residual": np.empty(batch),
            "conditioning": np.empty(batch),
            "orientation": np.empty(batch, dtype=np.int32),
            "first_step": np.empty(batch),
            "iterations": np.empty(batch, dtype=np.int32),
            "status": np.empty(batch, dtype=np.int32),
        }
        backend = self.backend
        job = backend.job(  # type: ignore[attr-defined]
            backend.NewtonJob,  # type: ignore[attr-defined]
            {
                "n": count, "actuated": theta_c, "actuated_stride": theta.shape[-1], "guess": start_c,
                "guess_stride": start.shape[-1], "params": self.params, "max_iterations": max_iterations,
                "tolerance": tolerance, "max_step": max_step, "singular_ratio": self.tolerances["singular_ratio"],
                **out,
            },
        )  # fmt: skip
        backend.newton(ctypes.byref(job))  # type: ignore[attr-defined]
        return NewtonOutcome(
            out["passive"], out["pose"], out["residual"], out["iterations"], out["status"],
            out["conditioning"], out["orientation"], out["first_step"],
        )  # fmt: skip

    def _newton_compiled_single(
        self, theta: Array, start: Array, tolerance: float, max_iterations: int, max_step: float
    ) -> NewtonOutcome:
        """One input: a preallocated job, so the foreign call takes one argument (the tracker's
        path), then copies of the outputs."""
        job = getattr(self._single_jobs, "job", None)
        if job is None:
            job = ForwardPoseTracker(
                self, Configuration(self.home_actuated, self.home_passive, np.eye(4)), tolerance, max_iterations
            )
            self._single_jobs.job = job
        job.configure(tolerance, max_iterations, max_step)
        job.actuated[0] = theta
        job.passive[0] = start
        job.call()
        # 0-d arrays, as the NumPy loop returns for one input
        return NewtonOutcome(
            job.passive[0].copy(), job.pose[0].copy(), np.array(job.residual[0]), np.array(job.iterations[0]),
            np.array(job.status[0]), np.array(job.conditioning[0]), np.array(job.orientation[0]),
            np.array(job.first_step[0]),
        )  # fmt: skip

    def tracker(
        self,
        start: Configuration,
        tolerance: float = tracking.TOLERANCE,
        max_iterations: int = tracking.MAX_ITERATIONS,
        strict: bool = True,
        jump_ratio: float = tracking.JUMP_RATIO,
        trust_step: float = tracking.TRUST_STEP,
    ) -> ForwardPoseTracker:
        """A ForwardPoseTracker from ``start``: the fast path of a control loop.

        Newton runs from the previous solution with preallocated buffers. The tracker reports every
        change of assembly mode (a crossed type II singularity, a jump to another branch) in
        ``mode_change``.

        Parameters
        ----------
        start : Configuration
            A solved configuration (from ``forward_pose``, ``forward_pose_all(...).mode(k)`` or
            ``inverse_pose(...).branch(k)``); a batch tracks every entry.
        tolerance : float
            Newton tolerance on the residual's max-norm (m and rad).
        max_iterations : int
            The most Newton steps per call.
        strict : bool
            Raise AssemblyModeChangeError on a change of assembly mode (default).
        jump_ratio : float
            A solution that moved more than this times the first Newton step is suspect.
        trust_step : float
            The largest Newton step trusted without a check (m or rad).

        Returns
        -------
        ForwardPoseTracker
            Call ``solve(actuated)`` for each new input.

        Raises
        ------
        BadInputError
            ``start`` is not a Configuration, or a setting is out of range.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> tracker = m.tracker(m.forward_pose(m.home_actuated))
        >>> passive, pose = tracker.solve(m.home_actuated + 0.01)
        >>> passive.round(4).tolist(), tracker.mode_change.tolist()
        ([-0.0023, 0.33], [0])
        """
        return ForwardPoseTracker(self, start, tolerance, max_iterations, strict, jump_ratio, trust_step)

    # ------------------------------------------------------------------ forward pose, all modes
    def forward_pose_all(
        self, actuated: ArrayLike, strict: bool = True, method: str | None = None, certify: str = "exact"
    ) -> AssemblyModes:
        """Every real assembly mode for each input.

        Methods (``capabilities.forward_methods``): "elimination", the generated univariate
        polynomial of a closed form written with the mechanism; "homotopy", the mechanism's own
        polynomial system; "automatic", the polynomial form the generator derives from the loop
        closure, whose generic root count is proven at generation time (total-degree bound or trace
        test). A homotopy follows one path per solution of its generated start system
        (``root_count`` paths).

        Every real root of the polynomial is isolated (none is lost: roots are separated by the
        roots of the derivative; near-double roots and roots at infinity are reported), back
        substituted for every branch, completed with the passive joints, polished by Newton to
        1e-13 and checked (closure, alignment, joint limits, input independence, repeats).
        Slots: M = degree x branch combinations; ``valid`` marks modes, ``outcome`` says what
        became of every other slot and ``certificate()`` accounts for every root. A mode at a
        type II singularity is kept with its ``conditioning`` near 0 (``ill_conditioned()``).

        Parameters
        ----------
        actuated : array_like, shape (..., n_a)
            Actuated values (m or rad), inside ``actuated_ranges``; any leading batch shape. A
            batch of at least ``parakin.log.LARGE_BATCH`` inputs shows a progress bar
            (``parakin.log.progress``).
        strict : bool
            Raise when an input's elimination is degenerate with no isolated mode (default).
        method : str or None
            One of ``capabilities.forward_methods``; None: the default, the fastest complete one.
        certify : {"exact", "double"}
            Homotopy methods: "exact" (default) tests every endpoint that the double-precision
            Krawczyk test cannot certify again in exact dyadic arithmetic
            (``parakin.solvers.exact_certify``: milliseconds per such root; ill-conditioned roots
            near infinity need it); "double" only in double precision (faster; such roots stay
            uncertified and the input incomplete).

        Returns
        -------
        AssemblyModes
            ``poses`` (..., M, 4, 4), ``passive`` (..., M, n_p), ``valid`` (..., M), ``count``
            (...), ``conditioning`` (..., M: each mode's distance to a type II singularity,
            ``parakin.singularity.type_ii_distance``, NaN in a slot that is no mode; for at most
            ``DEFER_CONDITIONING`` inputs measured when first read) and the
            accounting of every slot; ``mode(k)`` is the k-th mode of each input as a Configuration.

        Raises
        ------
        BadInputError
            An input out of range or non-finite, or ``certify`` not "exact" or "double".
        UnsupportedOperationError
            No forward method (use ``forward_pose``), or an unknown ``method``.
        SelfMotionError
            With ``strict``: the platform moves with the actuators locked (e.g. SAM with parallel
            U-joint axes); the solution set is attached (``.solution_set``).
        SingularConfigurationError
            With ``strict``: a degenerate elimination with no closed configuration near home.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> modes = m.forward_pose_all(m.home_actuated)
        >>> int(modes.count), modes.passive[modes.valid].round(4).tolist()
        (2, [[0.0, 0.0528], [0.0, 0.33]])
        >>> m.forward_pose_all([[1.8, 1.3], [1.9, 1.2]]).count.tolist()  # a batch of two inputs
        [2, 2]
        """
        if certify not in ("exact", "double"):
            raise BadInputError(f"certify must be 'exact' or 'double', got {certify!r}")
        theta = self._actuated(actuated)
        info = self._forward_method(method)
        if info is None:
            if self.passive_names:
                raise UnsupportedOperationError(
                    f"{self.name} has no closed-form forward elimination: forward_pose_all is not available; "
                    "use forward_pose (Newton from a guess)"
                )
            # a serial chain (no passive joint) has exactly one forward pose, a function of its
            # joints: complete by construction, so its certificate says so
            single = self.forward_pose(theta)
            one = np.ones(theta.shape[:-1] + (1,), dtype=bool)
            zero = np.zeros(theta.shape[:-1], dtype=np.int32)
            return AssemblyModes(
                theta, single.pose[..., None, :, :], single.passive[..., None, :], single.residual[..., None],
                np.full(one.shape, np.nan), one, one, one.sum(-1), ~one,
                outcome=np.zeros(one.shape, dtype=np.int32), root_kind=np.full(one.shape, -1, dtype=np.int32),
                conditioning=np.ones(one.shape), real_roots=zero, near_roots=zero, at_infinity=zero, status=zero,
                outcomes=self.manifest.abi.mode_outcomes, pose_kind=self.manifest.pose_kind,
                method="serial chain", root_count=1, root_count_proven=True,
                certified_roots=np.ones(theta.shape[:-1], dtype=np.int64), path_certified=one,
                undecided_roots=np.zeros(theta.shape[:-1], dtype=np.int64),
            )  # fmt: skip
        flat = theta.reshape(-1, theta.shape[-1])
        count = flat.shape[0]
        with progress(count, f"{self.name}: every assembly mode") as bar:
            # with a bar, in about a hundred steps so that it moves (each input is solved on its
            # own: the same answers); without one, in one step
            step = max(BAR_STEP, -(-count // 100)) if bar.active else max(count, 1)
            # a few inputs in one step: their conditioning is measured when first read (most
            # callers of one input never read it: a control loop picking its mode)
            defer = step >= count and count <= DEFER_CONDITIONING
            parts = []
            for start in range(0, max(count, 1), step):
                parts.append(self._every_mode(info, flat[start : start + step], certify == "exact", defer))
                bar.update(parts[-1]["count"].shape[0])
        out = parts[0] if len(parts) == 1 else {key: np.concatenate([p[key] for p in parts]) for key in parts[0]}
        modes = assemble(self, theta, out, info)
        if "conditioning_jacobians" in out:
            modes._defer(
                "conditioning",
                DeferredConditioning(
                    out["conditioning_measured"], out["conditioning_jacobians"], modes.valid, inverse_condition
                ),
            )
        degenerate = modes.status == self.manifest.abi.code("input_status", "degenerate") if strict else None
        if degenerate is not None and degenerate.any():
            index = first_index(degenerate)
            cause = (
                "homotopy paths that end nowhere (no isolated solution to reach)"
                if info.homotopy is not None
                else f"degenerate elimination ({', '.join(info.degeneracies) or 'the polynomial vanishes'})"
            )
            where = f" at batch index {index}" if index else ""  # one input has no batch index
            message = (
                f"forward pose{where}: {cause} and no isolated mode; "
                "the platform is not determined by the actuators here"
            )
            # a positive-dimensional solution set (a self-motion): report it, not a random point
            motion = self.self_motion(theta[index])
            # a self-motion is a curve that moves; continuation at an isolated configuration
            # returns that point over and over (a step is SELF_MOTION_STEP in every variable)
            curves = [motion.passive[motion.curve == c] for c in np.unique(motion.curve)] if motion.count else []
            if any(np.ptp(points, axis=0).max() >= SELF_MOTION_STEP / 2 for points in curves):
                raise SelfMotionError(f"{message}; the solution set is attached (.solution_set)", motion)
            distinct: list[np.ndarray] = []  # the curves' points, each isolated configuration once
            for points in curves:
                if all(np.abs(points[0] - other).max() >= SELF_MOTION_STEP / 2 for other in distinct):
                    distinct.append(points[0])
            found = (
                f"{len(distinct)} isolated configuration(s) near the home pose that continuation "
                "(self_motion) closes to its tolerance"
                if distinct
                else "no closed configuration near the home pose"
            )
            if info.homotopy is not None and modes.certified_roots is not None:
                # failed paths and no mode: what is proven is said, not a self-motion (a user's
                # Hexaglide on shared rails: 72 roots certified non-real, 8 paths failed)
                certified = int(np.asarray(modes.certified_roots)[index])
                failed_code = self.manifest.abi.code("mode_outcomes", "path_failed")
                failed = int(np.sum(np.asarray(modes.outcome)[index] == failed_code))
                raise SingularConfigurationError(
                    f"forward pose{where}: no real assembly mode found, and the search is not complete: "
                    f"{failed} homotopy path(s) failed, {certified} of {modes.root_count} roots certified "
                    f"(none real); {found}. The input may be at or near a singularity; strict=False returns "
                    "the modes with their certificate"
                )
            raise SingularConfigurationError(f"{message}; {found}")
        return modes

    def _every_mode(self, info: Forward, flat: Array, exact: bool, defer: bool = False) -> dict[str, np.ndarray]:
        """The all-modes pipeline's arrays for a flat batch. A homotopy solves the geometry in its
        own size (``_unit_free``): the paths, the certificate and every threshold then see the same
        numbers in millimetres, metres or kilometres, and the modes are scaled back. ``defer``:
        the modes' conditioning is left to its first reading (``_measured``)."""
        unit_free = self._unit_free if info.homotopy is not None else None
        if unit_free is None:
            return self._measured(flat, self._every_mode_here(info, flat, exact), rescaled=False, defer=defer)
        scaled, unit = unit_free
        down, up = self._length_factors
        # the unit is a power of two: x * (1 / unit) is x / unit exactly, and x * 1.0 is x
        out = scaled._every_mode_here(info, flat * down, exact)
        out["passive"] = out["passive"] * up
        out["poses"][..., :3, 3] *= unit
        return self._measured(flat, out, rescaled=True, defer=defer)

    def _measured(
        self, flat: Array, out: dict[str, np.ndarray], rescaled: bool, defer: bool = False
    ) -> dict[str, np.ndarray]:
        """``out`` with each mode's ``conditioning`` measured in the caller's units: the type II
        distance of ``parakin.singularity`` (sigma_min / sigma_max of d closure / d passive at the
        mode, from one call of the closure kernel and one batched SVD), the same measure whatever
        backend or pipeline found the mode; NaN in a slot that is no mode. ``rescaled``: the modes
        were solved in the unit-free geometry (``_unit_free``), so the closure residual of every
        slot with a configuration is measured again in the caller's units from the same call."""
        mode = self.manifest.abi.code("mode_outcomes", "mode")
        located = np.isfinite(out["passive"]).all(-1)
        modes = (out["outcome"] == mode) & located
        where = (np.isfinite(out["residual"]) & located) | modes if rescaled else modes
        conditioning = np.empty(modes.shape)
        conditioning.fill(np.nan)
        if not self.passive_names:  # no loop to close: no type II singularity
            conditioning[modes] = 1.0
        elif where.any():
            # the slots in row-major order (a mask's order); one input's actuated values are
            # shared by its slots (the kernel reads the one row for each)
            actuated = flat[0] if flat.shape[0] == 1 else flat[np.nonzero(where)[0]]
            with np.errstate(all="ignore"):
                closure = self.backend.call("loop_closure", actuated, out["passive"][where], self.params)
            if rescaled:  # the closure residual in the caller's units, at the modes' own values
                out["residual"][where] = np.abs(closure["residual"]).max(-1, initial=0.0)
            jacobian = closure["jacobian"] if where is modes else closure["jacobian"][modes[where]]
            if defer:  # measured when first read: the modes and their Jacobians (DeferredConditioning)
                out["conditioning_measured"], out["conditioning_jacobians"] = modes, jacobian
            else:
                conditioning[modes] = inverse_condition(jacobian)  # the modes, in the same order
        out["conditioning"] = conditioning
        return out

    @functools.cached_property
    def _length_variables(self) -> tuple[Array, Array]:
        """Masks of the actuated (n_a,) and passive (n_p,) variables that are lengths (unit m)."""
        return (
            np.array([v.unit == "m" for v in self.manifest.actuated], dtype=bool),
            np.array([v.unit == "m" for v in self.manifest.passive], dtype=bool),
        )

    @functools.cached_property
    def _length_factors(self) -> tuple[Array, Array]:
        """Per actuated (n_a,) and passive (n_p,) variable, the factor into the unit-free
        geometry's numbers and the factor back (``_unit_free``): 1 / unit and unit for a length,
        1 for any other (read only); none without a rescaling."""
        unit_free = self._unit_free
        unit = 1.0 if unit_free is None else unit_free[1]
        length_actuated, length_passive = self._length_variables
        down = np.where(length_actuated, 1.0 / unit, 1.0)
        up = np.where(length_passive, unit, 1.0)
        down.flags.writeable = up.flags.writeable = False
        return down, up

    @functools.cached_property
    def _unit_free(self) -> tuple[Mechanism, float] | None:
        """This mechanism with every length divided by a power of two near its size, and that
        power (an exact scaling in floating point); None where no rescaling is needed or where a
        parameter's unit is not a length, an angle or a pure number (its scaling is not known)."""
        known = all(p.unit in SCALED_UNITS for p in self.manifest.parameters)
        unit = length_unit(length_scale(self))
        if not known or unit == 1.0:
            return None

        def scaled(variables: Sequence[Variable], values: Mapping[str, tuple[float, float]]) -> dict:
            lengths = {v.name for v in variables if v.unit == "m"}
            return {k: (lo / unit, hi / unit) if k in lengths else (lo, hi) for k, (lo, hi) in values.items()}

        parameters = {
            p.name: value / unit if p.unit == "m" else value
            for p, value in zip(self.manifest.parameters, self.params, strict=True)
        }
        limits, ranges = (
            scaled(self.manifest.passive, self.limits),
            scaled(self.manifest.actuated, self.actuated_ranges),
        )
        return Mechanism(self.package, self.backend, parameters, limits, ranges), unit

    def _every_mode_here(self, info: Forward, flat: Array, exact: bool) -> dict[str, np.ndarray]:
        """The all-modes pipeline in this mechanism's own numbers: compiled C or NumPy, then certified."""
        if self.backend.name == "compiled" and info is self.capabilities.forward:
            out = compiled_modes(self, flat)
        else:  # the same pipeline in NumPy, over this backend's kernels
            out = numpy_modes(self, flat, info)
        if info.homotopy is not None:
            out = self._certified(info, flat, out, exact)
        return out

    def _certified(self, info: Forward, flat: Array, out: dict[str, np.ndarray], exact: bool) -> dict[str, np.ndarray]:
        """Certify and complete every input's roots (``exact``: what double precision cannot
        certify or decide is tested in exact arithmetic), re-tracking an input short of the root
        count, then the modes are the certified real roots: ``modes.certified_modes``."""
        return certified_modes(self, info, flat, out, exact)

    def _forward_method(self, method: str | None) -> Forward | None:
        if method is None:
            return self.capabilities.forward
        methods = self.capabilities.forward_methods
        if method not in methods:
            known = ", ".join(repr(name) for name in methods) or "none"
            raise UnsupportedOperationError(
                f"{self.name} has no forward_pose_all method {method!r}; its methods: {known}"
            )
        return methods[method]

    def forward_pose_all_chunks(self, actuated: ArrayLike, chunk: int = 65536, strict: bool = True):
        """``forward_pose_all`` over a flat batch, chunk by chunk: memory bounded by the chunk.

        Parameters
        ----------
        actuated : array_like, shape (..., n_a)
            Actuated values (m or rad); flattened to (N, n_a).
        chunk : int
            The most inputs per chunk, positive.
        strict : bool
            As in ``forward_pose_all``.

        Yields
        ------
        tuple of (int, AssemblyModes)
            The flat index of the chunk's first input and its modes, chunk by chunk in order.

        Raises
        ------
        BadInputError
            An input out of range, or ``chunk`` not a positive integer.

        Examples
        --------
        >>> import numpy as np, parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> inputs = np.stack([m.home_actuated] * 3)
        >>> [(start, modes.count.tolist()) for start, modes in m.forward_pose_all_chunks(inputs, chunk=2)]
        [(0, [2, 2]), (2, [2])]
        """
        theta = self._actuated(actuated).reshape(-1, len(self.actuated_names))
        if not (isinstance(chunk, int | np.integer) and chunk > 0):
            raise BadInputError(f"chunk must be a positive integer, got {chunk!r}")
        for start in range(0, theta.shape[0], chunk):
            yield start, self.forward_pose_all(theta[start : start + chunk], strict=strict)

    def count_modes(self, actuated: ArrayLike, chunk: int = 65536) -> dict[str, Array]:
        """The number of assembly modes per input, computed chunk by chunk.

        Peak memory is set by ``chunk``, not by the batch; one progress bar counts the inputs.

        Parameters
        ----------
        actuated : array_like, shape (..., n_a)
            Actuated values (m or rad).
        chunk : int
            The most inputs solved at once.

        Returns
        -------
        dict of str to numpy.ndarray, each shape (...)
            ``count`` of assembly modes, ``real_roots``, ``near_roots``, ``at_infinity``,
            ``status`` and ``min_conditioning``, the smallest type II distance
            (``parakin.singularity.type_ii_distance``) over the modes (NaN without a mode).

        Raises
        ------
        BadInputError
            An input out of range or non-finite, or ``chunk`` not a positive integer.
        UnsupportedOperationError
            The mechanism has no forward method.

        Examples
        --------
        >>> import numpy as np, parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> m.count_modes(np.stack([m.home_actuated, m.home_actuated]))["count"].tolist()
        [2, 2]
        """
        theta = self._actuated(actuated)
        shape = theta.shape[:-1]
        keys = ("count", "real_roots", "near_roots", "at_infinity", "status")
        total = int(np.prod(shape, dtype=np.int64))
        result: dict[str, Array] = {key: np.zeros(total, dtype=np.int32) for key in keys}
        result["min_conditioning"] = np.full(total, np.nan)
        with progress(total, f"{self.name}: counting assembly modes"):  # the chunks feed this one bar
            for start, modes in self.forward_pose_all_chunks(theta, chunk, strict=False):
                stop = start + modes.count.shape[0]
                for key in keys:
                    result[key][start:stop] = getattr(modes, key)
                conditioning = np.where(modes.valid, modes.conditioning, np.inf).min(-1)
                result["min_conditioning"][start:stop] = np.where(np.isfinite(conditioning), conditioning, np.nan)
        return {key: value.reshape(shape) for key, value in result.items()}

    def self_motion(
        self, actuated: ArrayLike, starts: ArrayLike | None = None, step: float = SELF_MOTION_STEP
    ) -> SelfMotion:
        """The solution set of the loop closure for one locked input, traced by continuation.

        Where the set is a curve (a self-motion), points are traced along it from ``starts`` or from
        the home configuration and random perturbations of it (``parakin.solvers.continuation``);
        where the modes are isolated the points found are those modes.

        Parameters
        ----------
        actuated : array_like, shape (n_a,)
            One locked input (m or rad).
        starts : array_like, shape (k, n_p), optional
            Passive values to start the continuation from.
        step : float
            The continuation step (m or rad), positive.

        Returns
        -------
        SelfMotion
            ``passive`` (k, n_p), ``poses`` (k, 4, 4), ``residual`` (k,), ``curve`` (k,) and
            ``closed`` per traced curve.

        Raises
        ------
        BadInputError
            A batch of inputs, an input out of range, or ``step`` not positive.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> motion = m.self_motion(m.home_actuated)
        >>> bool(motion.count > 0 and (motion.residual < 1e-9).all())
        True
        """
        theta = self._actuated(actuated)
        step = positive_number(step, "step")
        if theta.ndim != 1:
            raise BadInputError(f"self_motion takes one input (n_a,), got shape {theta.shape}")
        start = None if starts is None else np.atleast_2d(self._passive(starts))
        return trace_self_motion(self, theta, start, step)

    def least_squares(self, actuated: ArrayLike, start: Configuration | ArrayLike) -> LeastSquares:
        """For locked inputs that no configuration satisfies exactly: the passive values that minimise
        the loop-closure residual (Levenberg-Marquardt from ``start``).

        Parameters
        ----------
        actuated : array_like, shape (n_a,)
            One input (m or rad).
        start : Configuration or array_like, shape (n_p,)
            Where Levenberg-Marquardt starts.

        Returns
        -------
        LeastSquares
            ``passive`` (n_p,), ``pose`` (4, 4), ``residual`` (n_p,), ``norm`` (the distance from
            compatible inputs: 0 where they are compatible) and ``iterations``.

        Raises
        ------
        BadInputError
            A batch of inputs, or an input out of range or non-finite.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> fit = m.least_squares(m.home_actuated, m.home_passive)
        >>> bool(fit.norm < 1e-12), fit.passive.round(3).tolist()
        (True, [0.0, 0.33])
        """
        theta = self._actuated(actuated)
        if theta.ndim != 1:
            raise BadInputError(f"least_squares takes one input (n_a,), got shape {theta.shape}")
        guess = start.passive if isinstance(start, Configuration) else start
        return least_squares_configuration(self, theta, self._passive(guess))

    # ------------------------------------------------------------------ rates
    def rate_jacobians(self, state: Configuration) -> dict[str, Array]:
        """A and B of A twist = B actuated_rates (mechanisms with a rate model, e.g. the SPM).

        Parameters
        ----------
        state : Configuration
            A closed configuration (from a solver); batch allowed.

        Returns
        -------
        dict of str to numpy.ndarray
            ``a`` (..., n_t, n_t) and ``b`` (..., n_t, n_a) over the twist components
            ``capabilities.rates.twist`` (v of the origin of {P}, w; in {B}); a lower-mobility
            platform adds ``constraints`` (..., n_c, 6), its constraint wrenches.

        Raises
        ------
        UnsupportedOperationError
            The mechanism has no A/B rate model.
        BadInputError
            ``state`` is not a Configuration, or an output is not finite.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> jacobians = m.rate_jacobians(m.forward_pose(m.home_actuated))
        >>> {name: value.shape for name, value in jacobians.items()}
        {'a': (2, 2), 'b': (2, 2)}
        """
        self._require(self.capabilities.rates, "rate_jacobians", "A/B rate model")
        theta, passive = self._state(state)
        return self._finite("rate_jacobians", theta, passive)

    def passive_rates(self, state: Configuration, actuated_rates: ArrayLike) -> Array:
        """Passive joint rates from the loop closure: J_q qdot = -J_theta theta_dot.

        Parameters
        ----------
        state : Configuration
            A closed configuration.
        actuated_rates : array_like, shape (..., n_a)
            Actuated rates (m/s or rad/s).

        Returns
        -------
        numpy.ndarray, shape (..., n_p)
            Passive rates (m/s or rad/s).

        Raises
        ------
        BadInputError
            ``state`` is not a Configuration, or a rate is not finite.
        SingularConfigurationError
            The loop-closure Jacobian is singular (a type II singularity).

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> m.passive_rates(m.forward_pose(m.home_actuated), [0.1, 0.0]).round(4).tolist()
        [-0.0115, -0.0173]
        """
        theta, passive = self._state(state)
        rates = bounded_vector(actuated_rates, "actuated_rates", self.actuated_names)
        out = self.backend.call("loop_closure", theta, passive, self.params)
        actuated_jacobian = self.backend.call("loop_closure_actuated", theta, passive, self.params)["jacobian_actuated"]
        right = -(actuated_jacobian @ rates[..., None])[..., 0]
        return self._solve(out["jacobian"], right, "loop-closure Jacobian", "a type II (parallel) singularity")

    def leg_jacobians(self, state: Configuration) -> dict[str, Array]:
        """Each leg's 6x6 Jacobian (eq 9): twist per joint rate, columns in the leg's joint order.

        Parameters
        ----------
        state : Configuration
            A closed configuration.

        Returns
        -------
        dict of str to numpy.ndarray, each shape (..., 6, 6)
            Per leg (``capabilities.legs``): the twist (v of the origin of {P}, w; in {B}) per
            joint rate.

        Raises
        ------
        UnsupportedOperationError
            The mechanism has no serial legs.
        BadInputError
            ``state`` is not a Configuration, or an output is not finite.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("sam", backend="numpy")
        >>> jacobians = m.leg_jacobians(m.forward_pose(m.home_actuated))
        >>> {leg: value.shape for leg, value in jacobians.items()}
        {'left': (6, 6), 'right': (6, 6)}
        """
        self._require(self.capabilities.legs, "leg_jacobians", "serial legs")
        theta, passive = self._state(state)
        return self._finite("leg_jacobians", theta, passive)

    def inverse_rate(self, state: Configuration, twist: ArrayLike, damping: float | None = None) -> Rates:
        """Joint rates for a platform twist (eq 10), leg by leg or through the rate model.

        A single state broadcasts against a batch of twists and the reverse. A lower-mobility
        platform (a rate model with constraint wrenches C) takes only twists it can make,
        |C_i . twist| <= CONSTRAINT_TOLERANCE |C_i| |twist|.

        Parameters
        ----------
        state : Configuration
            A closed configuration.
        twist : array_like, shape (..., n_t)
            The platform twist over ``capabilities.rates.twist`` (or the six (v, w) of a leg
            model): v of the origin of {P} (m/s) and w (rad/s), both in {B}.
        damping : float or None
            None solves exactly; lambda > 0 uses the damped pseudo-inverse
            J^T (J J^T + lambda^2 I)^-1, the paper's recommendation near a serial singularity (the
            motion is then not exactly as commanded).

        Returns
        -------
        Rates
            ``actuated`` (..., n_a) and ``passive`` (..., n_p) joint rates (m/s or rad/s).

        Raises
        ------
        SingularConfigurationError
            Without damping: a singular Jacobian (a serial, type I singularity).
        BadInputError
            A twist the platform cannot make, a non-finite twist, or ``damping`` not positive.
        UnsupportedOperationError
            The mechanism has neither a rate model nor serial legs.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> state = m.forward_pose(m.home_actuated)
        >>> twist = m.forward_rate(state, [0.1, 0.0])
        >>> m.inverse_rate(state, twist).actuated.round(6).tolist()  # the round trip
        [0.1, 0.0]
        """
        if damping is not None:
            damping = positive_number(damping, "damping")
        if self.capabilities.rates is not None:
            return self._inverse_rate_ab(state, twist, damping)
        self._require(self.capabilities.legs, "inverse_rate", "rate model (A/B Jacobians or serial legs)")
        xdot = bounded_vector(twist, "twist", LEG_TWIST)
        jacobians = self.leg_jacobians(state)
        batch = broadcast_shapes(xdot.shape[:-1], next(iter(jacobians.values())).shape[:-2])
        actuated_rates = np.zeros(batch + (len(self.actuated_names),))
        passive_rates = np.zeros(batch + (len(self.passive_names),))
        for leg, jacobian in jacobians.items():
            if damping is None:  # _solve broadcasts a single state against a batch of twists
                joint_rates = self._solve(
                    jacobian, xdot, f"{leg} leg Jacobian", "pass damping=... for the damped pseudo-inverse"
                )
            else:
                joint_rates = self._damped(jacobian, xdot, damping, f"{leg} leg Jacobian")
            for column, (is_actuated, index) in enumerate(self._leg_columns[leg]):
                target = actuated_rates if is_actuated else passive_rates
                target[..., index] = joint_rates[..., column]
        return Rates(actuated_rates, passive_rates)

    def _inverse_rate_ab(self, state: Configuration, twist: ArrayLike, damping: float | None) -> Rates:
        rates_model = self.capabilities.rates
        assert rates_model is not None
        omega = bounded_vector(twist, "twist", rates_model.twist)
        theta, passive = self._state(state)
        jacobians = self.rate_jacobians(state)
        if "constraints" in jacobians:
            self._check_feasible(jacobians["constraints"], omega)
        right = (jacobians["a"] @ omega[..., None])[..., 0]
        if damping is None:
            rates = self._solve(
                jacobians["b"], right, "B (inverse Jacobian)", "a serial (type I) singularity; pass damping=..."
            )
        else:
            rates = self._damped(jacobians["b"], right, damping, "B (inverse Jacobian)")
        state_b = Configuration(
            np.broadcast_to(theta, rates.shape),
            np.broadcast_to(passive, rates.shape[:-1] + passive.shape[-1:]),
            np.broadcast_to(np.eye(4), rates.shape[:-1] + (4, 4)),  # not read by passive_rates
        )
        return Rates(rates, self.passive_rates(state_b, rates))

    def _check_feasible(self, constraints: Array, twist: Array) -> None:
        """A lower-mobility platform moves only with constraints @ twist = 0: any other twist
        raises (its actuator rates would silently drop the motion the legs forbid)."""
        forbidden = np.abs((constraints @ twist[..., None])[..., 0])
        scale = np.linalg.norm(constraints, axis=-1) * np.linalg.norm(twist, axis=-1)[..., None]
        violation = np.max(forbidden / np.maximum(scale, 1e-300), axis=-1)
        bad = violation > CONSTRAINT_TOLERANCE
        if bad.any():
            index = first_index(bad)
            raise BadInputError(
                f"the twist{at_index(index)} is not a motion {self.name} can make: it works against the legs' "
                f"constraint wrenches (|C twist| / (|C| |twist|) = {float(violation[index]):.3g} > "
                f"{CONSTRAINT_TOLERANCE:g}, C = rate_jacobians(state)['constraints']); a feasible twist is "
                "forward_rate(state, actuated_rates)"
            )

    def rate_matrix(self, state: Configuration) -> Array:
        """M of eq (11): actuated rates = M @ twist, from the legs' inverse Jacobians.

        Parameters
        ----------
        state : Configuration
            A closed configuration.

        Returns
        -------
        numpy.ndarray, shape (..., n_a, 6)
            Rows of each leg's inverse Jacobian that belong to actuated joints, in actuated order;
            columns (v, w) in {B}.

        Raises
        ------
        UnsupportedOperationError
            The mechanism has no serial legs.
        SingularConfigurationError
            A leg Jacobian is singular.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("sam", backend="numpy")
        >>> m.rate_matrix(m.forward_pose(m.home_actuated)).shape
        (6, 6)
        """
        jacobians = self.leg_jacobians(state)
        rows: list[np.ndarray] = [np.zeros(0)] * len(self.actuated_names)
        for leg, jacobian in jacobians.items():
            identity = np.broadcast_to(np.eye(6), jacobian.shape)
            inverse = self._solve(
                jacobian, identity, f"{leg} leg Jacobian", "the rate matrix M needs every leg invertible", columns=True
            )
            for column, (is_actuated, index) in enumerate(self._leg_columns[leg]):
                if is_actuated:
                    rows[index] = inverse[..., column, :]
        return np.stack(rows, axis=-2)

    def forward_rate(self, state: Configuration, actuated_rates: ArrayLike) -> Array:
        """Platform twist from actuator rates: twist = M^-1 theta_dot (eq 12), or A twist = B theta_dot.

        With a rate model, a lower-mobility platform also satisfies constraints @ twist = 0: its
        parasitic components come out with the rest.

        Parameters
        ----------
        state : Configuration
            A closed configuration.
        actuated_rates : array_like, shape (..., n_a)
            Actuated rates (m/s or rad/s).

        Returns
        -------
        numpy.ndarray, shape (..., n_t)
            The twist over ``capabilities.rates.twist`` (six (v, w) for a leg model): v of the
            origin of {P} (m/s), w (rad/s), in {B}.

        Raises
        ------
        SingularConfigurationError
            A type II (parallel) singularity.
        BadInputError
            ``state`` is not a Configuration, or a rate is not finite.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> m.forward_rate(m.forward_pose(m.home_actuated), [0.1, 0.0]).round(4).tolist()  # vx, vy
        [-0.0115, -0.0173]
        """
        rates = bounded_vector(actuated_rates, "actuated_rates", self.actuated_names)
        if self.capabilities.rates is not None:
            from parakin.solvers.statics import overall_jacobian

            jacobians = self.rate_jacobians(state)
            overall, name = overall_jacobian(jacobians["a"], jacobians.get("constraints"))
            # and no motion against the constraint wrenches: C twist = 0
            right = (jacobians["b"] @ rates[..., None])[..., 0]
            right = np.concatenate([right, np.zeros(right.shape[:-1] + (overall.shape[-2] - right.shape[-1],))], -1)
            return self._solve(overall, right, name, "a type II (parallel) singularity")
        matrix = self.rate_matrix(state)
        return self._solve(matrix, rates, "rate matrix M (eq 12)", "a type II (parallel) singularity")

    def _solve(self, matrix: Array, rhs: Array, what: str, hint: str, columns: bool = False) -> Array:
        """matrix @ x = rhs by the one pivoted solve and singularity criterion of every backend
        (pivot ratio above the manifest's singular_ratio), or SingularConfigurationError. ``rhs``
        (..., n) vectors, or with ``columns`` (..., n, k) matrices; batch axes broadcast."""
        if columns:
            vectors = np.swapaxes(rhs, -1, -2)  # (..., k, n): one right-hand side per column
            shape = np.broadcast_shapes(matrix.shape[:-2], rhs.shape[:-2])
            solved = self._solve(
                matrix[..., None, :, :], np.broadcast_to(vectors, shape + vectors.shape[-2:]), what, hint
            )
            return np.swapaxes(solved, -1, -2)
        batch = np.broadcast_shapes(matrix.shape[:-2], rhs.shape[:-1])
        matrix = np.broadcast_to(matrix, batch + matrix.shape[-2:])
        x, ratio, _ = pivoted_solve(matrix, np.broadcast_to(rhs, batch + rhs.shape[-1:]))
        bad = ~(ratio > self.tolerances["singular_ratio"])
        if bad.any():
            index = first_index(bad)
            raise SingularConfigurationError(
                f"{what} is singular{at_index(index)} (pivot ratio {float(ratio[index]):.3g} <= "
                f"{self.tolerances['singular_ratio']:g}); {hint}"
            )
        return np.asarray(x, dtype=np.float64)

    def _damped(self, matrix: Array, rhs: Array, damping: float, what: str) -> Array:
        """x = J^T (J J^T + damping^2 I)^-1 rhs: finite for any J when damping > 0."""
        transposed = np.swapaxes(matrix, -1, -2)
        gram = matrix @ transposed + damping**2 * np.eye(matrix.shape[-1])
        y = self._solve(gram, rhs, f"damped {what}", "increase damping")
        return np.asarray((transposed @ y[..., None])[..., 0], dtype=np.float64)

    # ------------------------------------------------------------------ statics
    def inverse_dynamics(
        self,
        state: Configuration,
        rates: ArrayLike,
        accelerations: ArrayLike,
        *,
        platform_inertia: Any,
        gravity: ArrayLike | None = None,
        leg_inertias: object = None,
    ) -> Any:
        """Actuator efforts that move the platform with the given actuated rates and accelerations.

        ``parakin.dynamics.inverse_dynamics``: the platform's Newton-Euler wrench through the rate
        model, plus the legs' links by recursive Newton-Euler on their tree where ``leg_inertias``
        gives them mass (massless otherwise).

        Parameters
        ----------
        state : Configuration
            A closed configuration.
        rates, accelerations : array_like, shape (..., n_a)
            Actuated rates (m/s, rad/s) and accelerations (m/s^2, rad/s^2).
        platform_inertia : RigidInertia or array_like, shape (10,)
            The platform's mass, centre (in {P}) and inertia, or its ten inertial parameters.
        gravity : array_like, shape (3,), optional
            In {B} (m/s^2); default ``parakin.dynamics.STANDARD_GRAVITY`` (z up).
        leg_inertias : float or mapping, optional
            The legs' links: one link mass in kg (every link a thin rod), or body name -> mass or
            ``RigidInertia`` in that body's frame (the bodies ``to_mjcf`` writes); None: massless
            legs.

        Returns
        -------
        parakin.dynamics.InverseDynamics
            ``efforts`` (..., n_a) in N or N m, with the twist, its rate and the wrench.

        Raises
        ------
        UnsupportedOperationError
            Neither a rate model nor a joint graph (the legs' tree).
        SingularConfigurationError
            A type II singularity.
        BadInputError
            A non-physical inertia or a wrongly shaped input.

        Examples
        --------
        >>> import parakin
        >>> from parakin.dynamics import rigid_inertia
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> state = m.forward_pose(m.home_actuated)
        >>> held = m.inverse_dynamics(state, [0, 0], [0, 0], platform_inertia=rigid_inertia(0.5), gravity=[0, -9.81, 0])
        >>> held.efforts.round(3).tolist()  # at rest: the efforts that hold 0.5 kg
        [-0.847, 0.847]
        """
        from parakin import dynamics

        g = dynamics.STANDARD_GRAVITY if gravity is None else gravity
        return dynamics.inverse_dynamics(
            self, state, rates, accelerations, platform_inertia=platform_inertia, gravity=g, leg_inertias=leg_inertias
        )

    def dynamics_regressor(
        self,
        state: Configuration,
        rates: ArrayLike,
        accelerations: ArrayLike,
        *,
        gravity: ArrayLike | None = None,
        leg_inertias: object = None,
    ) -> Array:
        """Y with efforts tau = Y theta, linear in the platform's ten inertial parameters theta.

        ``parakin.dynamics.dynamics_regressor``; theta in ``parakin.dynamics.INERTIAL_PARAMETERS``
        order (inertia about the origin of {P}).

        Parameters
        ----------
        state : Configuration
            A closed configuration.
        rates, accelerations : array_like, shape (..., n_a)
            Actuated rates (m/s, rad/s) and accelerations (m/s^2, rad/s^2).
        gravity : array_like, shape (3,), optional
            In {B} (m/s^2); default ``parakin.dynamics.STANDARD_GRAVITY``.
        leg_inertias : float or mapping, optional
            The legs' links: one link mass in kg (every link a thin rod), or body name -> mass or
            ``RigidInertia`` in that body's frame (the bodies ``to_mjcf`` writes); None: massless
            legs.

        Returns
        -------
        numpy.ndarray, shape (..., n_a, 10) or (..., n_a, 10 (1 + n_links)) with ``leg_inertias``
            Y (the links' ten parameters after the platform's).

        Raises
        ------
        UnsupportedOperationError
            Neither a rate model nor a joint graph (the legs' tree).
        SingularConfigurationError
            A type II singularity.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> state = m.forward_pose(m.home_actuated)
        >>> m.dynamics_regressor(state, [0, 0], [0, 0], gravity=[0, -9.81, 0]).shape
        (2, 10)
        """
        from parakin import dynamics

        g = dynamics.STANDARD_GRAVITY if gravity is None else gravity
        return dynamics.dynamics_regressor(self, state, rates, accelerations, gravity=g, leg_inertias=leg_inertias)

    def to_mjcf(self, actuated: ArrayLike | None = None, **options: Any) -> str:
        """The MJCF text of this mechanism for MuJoCo.

        Its legs become bodies, its loops are cut by site connects, the home is qpos0 and every
        assembly mode of ``actuated`` a keyframe (``parakin.mjcf.to_mjcf``, which lists the
        ``options``: modes, accuracy, timestep, masses, payload, actuators).

        Parameters
        ----------
        actuated : array_like, shape (n_a,), optional
            The input whose modes become keyframes (default: the home's); m or rad.
        **options
            Passed to ``parakin.mjcf.to_mjcf``.

        Returns
        -------
        str
            The MJCF XML.

        Raises
        ------
        UnsupportedOperationError
            A joint or attachment the exporter does not handle (the message names it).
        BadInputError
            An input out of range or an unknown option.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> m.to_mjcf().lstrip().startswith("<!-- five_bar")
        True
        """
        from parakin.mjcf import to_mjcf

        return to_mjcf(self, actuated, **options)

    def actuator_forces(self, state: Configuration, wrench: ArrayLike) -> Array:
        """Actuator efforts that hold the platform against an external wrench (virtual work).

        See ``parakin.solvers.statics.actuator_forces`` for the convention: positive along
        increasing actuated values.

        Parameters
        ----------
        state : Configuration
            A closed configuration.
        wrench : array_like, shape (..., n_t)
            The external wrench on the platform over the twist components (force in N at the
            origin of {P}, moment in N m; in {B}).

        Returns
        -------
        numpy.ndarray, shape (..., n_a)
            Efforts (N for prismatic, N m for revolute actuators).

        Raises
        ------
        SingularConfigurationError
            A type II singularity: some wrench cannot be held.
        UnsupportedOperationError
            The mechanism has no rate model.
        BadInputError
            A wrench of the wrong length or not finite.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> m.actuator_forces(m.forward_pose(m.home_actuated), [0.0, -10.0]).round(3).tolist()
        [-1.727, 1.727]
        """
        from parakin.solvers.statics import actuator_forces

        return actuator_forces(self, state, wrench)

    def constraint_forces(self, state: Configuration, wrench: ArrayLike) -> Array:
        """Intensities of the constraint wrenches a lower-mobility platform's legs apply while its
        actuators hold ``wrench`` (``parakin.solvers.statics.constraint_forces``).

        Parameters
        ----------
        state : Configuration
            A closed configuration.
        wrench : array_like, shape (..., 6)
            The external wrench on the platform (N at the origin of {P}, N m; in {B}).

        Returns
        -------
        numpy.ndarray, shape (..., n_c)
            One intensity per row of ``rate_jacobians(state)["constraints"]``.

        Raises
        ------
        UnsupportedOperationError
            The platform has no constraint wrenches (its actuators alone hold every wrench).
        SingularConfigurationError
            A type II singularity.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("tricept", backend="numpy")
        >>> state = m.forward_pose(m.home_actuated)
        >>> (m.constraint_forces(state, [0, 0, -100, 0, 0, 0]).round(6) + 0.0).tolist()  # a centred load (+ 0.0: no -0.0)
        [0.0, 0.0, 0.0]
        """
        from parakin.solvers.statics import constraint_forces

        return constraint_forces(self, state, wrench)

    def stiffness(self, state: Configuration, actuator_stiffness: ArrayLike | None = None) -> Array:
        """Platform stiffness K = G^T K_q G from actuator stiffnesses.

        Parameters
        ----------
        state : Configuration
            A closed configuration.
        actuator_stiffness : array_like, shape (n_a,) or (n_a, n_a), optional
            K_q (N/m or N m/rad): a positive diagonal, or symmetric positive definite. Default: the
            stiffnesses the mechanism declares as parameters (``capabilities.statics``).

        Returns
        -------
        numpy.ndarray, shape (..., n_t, n_t)
            K over the twist components: the extra wrench dw = K (twist dt) that holds a small
            displacement.

        Raises
        ------
        UnsupportedOperationError
            No ``actuator_stiffness`` and none declared, or no rate model.
        BadInputError
            A stiffness that is not positive (definite).
        SingularConfigurationError
            A serial singularity (an actuator rate is not defined).

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> K = m.stiffness(m.forward_pose(m.home_actuated), [1000.0, 1000.0])
        >>> K.shape, bool(abs(K - K.T).max() < 1e-9)
        ((2, 2), True)
        """
        from parakin.solvers.statics import stiffness

        if actuator_stiffness is None:
            statics = self.capabilities.statics
            self._require(statics, "stiffness without actuator stiffnesses", "declared actuator stiffness")
            assert statics is not None
            actuator_stiffness = [self.parameters[name] for name in statics.stiffness]
        return stiffness(self, state, actuator_stiffness)

    # ------------------------------------------------------------------ drawing
    def drawing(self, state: Configuration) -> dict[str, Array]:
        """The named point sets of the drawing kernel, in {B} (metres).

        Parameters
        ----------
        state : Configuration
            A configuration (from a solver).

        Returns
        -------
        dict of str to numpy.ndarray, each shape (..., 3, n)
            Per named set (``capabilities.drawing.points``): n points as columns.

        Raises
        ------
        UnsupportedOperationError
            The mechanism has no drawing kernel.
        BadInputError
            ``state`` is not a Configuration.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> {name: points.shape for name, points in m.drawing(m.forward_pose(m.home_actuated)).items()}
        {'base': (3, 2), 'elbow': (3, 2), 'platform': (3, 2)}
        """
        self._require(self.capabilities.drawing, "drawing", "drawing kernel")
        theta, passive = self._state(state)
        points = self.backend.call("drawing", theta, passive, self.params)
        counts = self.capabilities.drawing.points  # type: ignore[union-attr]
        # a one-point set comes back as a vector (3,): restore its point axis
        return {
            name: value.reshape(value.shape[: value.ndim - (1 if counts[name] == 1 else 2)] + (3, counts[name]))
            for name, value in points.items()
        }

    def plot(
        self,
        state: Configuration | AssemblyModes,
        path: str | None = None,
        ax: Any = None,
        title: str | None = None,
        *,
        mode: int | None = None,
        all_modes: bool = False,
    ) -> Any:
        """Draw the mechanism (``parakin.interfaces.plot.plot``; needs matplotlib).

        Metres; 2-D for a planar drawing, on its sphere for a spherical one.

        Parameters
        ----------
        state : Configuration or AssemblyModes
            The configuration to draw, or the modes of one input.
        path : str, optional
            Write a PNG there.
        ax : matplotlib.axes.Axes, optional
            Draw into these axes (not with ``all_modes``).
        title : str, optional
            The heading (default: the mechanism's title).
        mode : int, optional
            Draw mode (or entry) ``mode`` alone.
        all_modes : bool
            Draw every mode in the grid. By default the modes of one input are drawn as a grid of
            the first 12 (``parakin.interfaces.plot.MAX_PANELS``), each titled "mode k" with its
            distances to singularity (in red, "near-singular", where type II is below
            ``parakin.singularity.NEAR_SINGULAR``), the others named in the figure's title;
            ``all_modes=True`` draws every one.

        Returns
        -------
        matplotlib.axes.Axes or numpy.ndarray of Axes
            The axes drawn on; for a grid a 1-D array, entry k the panel of mode k.

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
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> panels = m.plot(m.forward_pose_all(m.home_actuated), all_modes=True)
        >>> [ax.get_title().splitlines()[0] for ax in panels]
        ['mode 0', 'mode 1']
        """
        from parakin.interfaces.plot import plot

        return plot(self, state, path, ax, title, mode=mode, all_modes=all_modes)

    # ------------------------------------------------------------------ singularities
    def is_architecturally_singular(self) -> bool:
        """Whether this geometry is singular at every pose (a useless design).

        One of the mechanism's normalised architecture measures (``architecture()``) is below its
        declared tolerance; False for mechanisms without such conditions.

        Returns
        -------
        bool
            True when the design is architecturally singular.

        Examples
        --------
        >>> import parakin
        >>> parakin.load("gough", backend="numpy").is_architecturally_singular()
        False
        """
        info = self.capabilities.architecture
        if info is None:
            return False
        return any(abs(value) < info.tolerance for value in self.architecture().values())

    def architecture(self) -> dict[str, float]:
        """The mechanism's architecture-singularity measures at its parameters.

        ``parakin inspect`` shows them symbolically; zero means singular at every pose.

        Returns
        -------
        dict of str to float
            One normalised measure per declared condition; empty for mechanisms without such
            conditions.

        Examples
        --------
        >>> import parakin
        >>> parakin.load("five_bar", backend="numpy").architecture()
        {}
        >>> len(parakin.load("gough", backend="numpy").architecture()) > 0
        True
        """
        info = self.capabilities.architecture
        if info is None:
            return {}
        values = self.backend.call("architecture", self.params)["measures"]
        return {name: float(values[k]) for k, name in enumerate(info.measures)}

    def singularities(self, state: Configuration) -> dict[str, Array]:
        """Every named singularity factor, then the determinants themselves; zero means singular.

        Serial: leg determinants (eq 13-14); parallel: the closed-loop matrix.

        Parameters
        ----------
        state : Configuration
            A configuration (from a solver).

        Returns
        -------
        dict of str to numpy.ndarray, each shape (...)
            Per factor (``manifest.singularity_factors``) and determinant (``manifest.determinants``).

        Raises
        ------
        BadInputError
            ``state`` is not a Configuration, or a factor is not finite.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> factors = m.singularities(m.forward_pose(m.home_actuated))
        >>> list(factors)
        ['leg1_links_aligned', 'leg2_links_aligned', 'distal_links_aligned', 'det_A', 'det_B']
        >>> round(float(factors["det_A"]), 4)
        0.0577
        """
        theta, passive = self._state(state)
        out = self._finite("singularity_factors", theta, passive)
        names = self.manifest.singularity_factors + self.manifest.determinants
        values = np.concatenate([out["factors"], out["determinants"]], axis=-1)
        return {name: values[..., k] for k, name in enumerate(names)}


# every public method names a misspelt keyword (forward_pose(gues=...)) as the command line and
# parakin.load do, instead of Python's TypeError
for _name, _method in list(vars(Mechanism).items()):
    if not _name.startswith("_") and inspect.isfunction(_method):
        setattr(Mechanism, _name, keywords_checked(_method))

__all__ = ["Mechanism"]
