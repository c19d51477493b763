"""The runtime mechanism: thin wrappers that validate input, call generated kernels through a
backend, and return named results. Conventions are those of the mechanism's generated manifest
(``m.manifest``, its ``conventions`` text is the mechanism file's docstring): SI units, radians, poses as
^B_P T (..., 4, 4), twists as (v of the origin of {P}, w), both in {B}.
"""

from __future__ import annotations

import ctypes
import functools
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
    RIGID_TOLERANCE,
    as_array,
    pose_vector,
    rigid_or_nan,
    rigidity_error,
    transform_from_pose,
    wrap_angle,
)
from parakin.results import Array, AssemblyModes, Configuration, ForwardPose, InversePose, NewtonOutcome, Rates
from parakin.solvers import tracker as tracking
from parakin.solvers.continuation import LeastSquares, SelfMotion, least_squares_configuration, trace_self_motion
from parakin.solvers.linalg import pivoted_solve
from parakin.solvers.modes import (
    RETRACKS,
    Retrack,
    assemble,
    certify,
    compiled_modes,
    length_scale,
    numpy_modes,
    reconcile,
    suspect_paths,
)
from parakin.solvers.tracker import ForwardPoseTracker
from parakin.validation import (
    MAX_MAGNITUDE,
    bounded_vector,
    broadcast_shapes,
    integer_in_range,
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


def _home(variable: Variable) -> float:
    return 0.0 if variable.home is None else variable.home


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
        self.parameters = dict(parameters)
        self.params = np.array([parameters[p.name] for p in manifest.parameters], dtype=float)
        self.actuated_names: list[str] = manifest.actuated_names
        self.passive_names: list[str] = manifest.passive_names
        self.tolerances = manifest.tolerances
        self.limits = limits
        self._limit_index = np.array([self.passive_names.index(name) for name in limits], dtype=np.intp)
        self._limit_low = np.array([low for low, _ in limits.values()], dtype=float)
        self._limit_high = np.array([high for _, high in limits.values()], dtype=float)
        #: per actuated variable (low, high): the manifest's declared range (actuator strokes, leg
        #: lengths >= 0) unless ``load(limits=...)`` overrides it; every solver checks these
        self.actuated_ranges: dict[str, tuple[float, float]] = {
            v.name: (actuated_ranges or {}).get(v.name, v.limits) for v in manifest.actuated
        }
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
        """Whether passive values (..., n_p) lie inside ``limits`` (open interval), over the batch;
        a NaN or infinite entry is never within them."""
        checked = as_array(passive, "passive", (len(self.passive_names),), finite=False)
        values = checked[..., self._limit_index]
        finite = np.isfinite(checked).all(-1)
        return np.asarray(((values > self._limit_low) & (values < self._limit_high)).all(-1) & finite)

    # ------------------------------------------------------------------ pose kernels
    def platform_pose(self, actuated: ArrayLike, passive: ArrayLike) -> Array:
        """^B_P T from joint values through the mechanism's pose kernel (e.g. the first leg's
        forward chain, eq 2-3): always a rigid transform (rotation orthonormal to rounding).
        A kernel that reads the platform from several legs gives a rigid pose only where the
        joint values close the loop: elsewhere (rotation off orthonormal by more than 1e-6, the
        tolerance of a pose input) InconsistentInputError names the batch index and the
        loop-closure residual."""
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
        """Loop-closure residual and its passive Jacobian (see ``parakin inspect``)."""
        return self._finite("loop_closure", self._actuated(actuated), self._passive(passive))

    def _as_transform(self, pose: ArrayLike, name: str = "pose") -> Array:
        """^B_P T (..., 4, 4), or the short form of the pose kind (``parakin.pose.POSE_KINDS``);
        positions of magnitude above MAX_MAGNITUDE are refused, like every other input."""
        transform = transform_from_pose(pose, self.manifest.pose_kind, name)
        bound = np.full(3, MAX_MAGNITUDE)
        within_ranges(transform[..., :3, 3], ["x", "y", "z"], -bound, bound, f"{name} position")
        return transform

    def inverse_pose(self, pose: ArrayLike, strict: bool = True) -> InversePose:
        """Every closed-form inverse branch for ^B_P T (..., 4, 4) (or R (..., 3, 3) for an
        orienting platform).

        With ``strict``, a pose with no valid branch raises UnreachablePoseError (limits) or
        SingularConfigurationError (every branch at a serial singularity), naming the pose index.
        """
        info = self.capabilities.inverse
        self._require(info, "inverse_pose", "closed-form inverse")
        assert info is not None
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
        valid = ~np.logical_or.reduce(list(failures.values()))
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
                    raise UnreachablePoseError(
                        f"pose{at} is unreachable on every branch: {', '.join(failed)} (joint limits {self.limits})"
                    )
                raise SingularConfigurationError(
                    f"pose{at} has no valid inverse branch: {', '.join(failed) or 'mixed failures'} "
                    "(serial singularity: the leg joints cannot be resolved)"
                )
        return result

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
        """The passive values of the inverse branch whose actuated values match ``actuated``."""
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

        ``guess``: a previous result (tracking), passive values (..., n_p), a pose (..., 4, 4), or
        None: then the valid assembly mode nearest the home configuration (eq 15 for SAM) seeds
        Newton, or the home configuration itself when there is no closed form or no mode. The
        residual is the position difference and rotation error between the legs (max-norm,
        metres and radians). With ``strict``, non-convergence raises ConvergenceError (with the
        residual reached), a singular Newton matrix SingularConfigurationError, and a loop
        closure that is not defined at the guess (e.g. a zero quaternion) BadInputError naming
        it, the same on every backend. Poses are rigid: a converged entry whose pose kernel is
        not rigid at the tolerance asked for gets the nearest rotation; an entry that did not
        converge (``strict=False``) keeps its guess as ``passive``, and its ``pose`` is NaN
        unless that guess gives a rigid pose.
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
        """A ForwardPoseTracker from ``start`` (a solved configuration, batch allowed): Newton from
        the previous solution with preallocated buffers; the fast path of a control loop. It
        reports every change of assembly mode (a crossed type II singularity, a jump to another
        branch) in ``mode_change``, and with ``strict`` raises AssemblyModeChangeError."""
        return ForwardPoseTracker(self, start, tolerance, max_iterations, strict, jump_ratio, trust_step)

    # ------------------------------------------------------------------ forward pose, all modes
    def forward_pose_all(
        self, actuated: ArrayLike, strict: bool = True, method: str | None = None, certify: str = "exact"
    ) -> AssemblyModes:
        """Every real assembly mode, by ``method`` (``capabilities.forward_methods``; None: the
        default, the fastest complete one): "elimination", the generated univariate polynomial of
        a closed form written with the mechanism; "homotopy", the mechanism's own polynomial
        system; "automatic", the polynomial form the generator derives from the loop closure,
        whose generic root count is proven at generation time (total-degree bound or trace test). A homotopy
        follows one path per solution of its generated start system (``root_count`` paths).

        Every real root of the polynomial is isolated (none is lost: roots are separated by the
        roots of the derivative; near-double roots and roots at infinity are reported), back
        substituted for every branch, completed with the passive joints, polished by Newton to
        1e-13 and checked (closure, alignment, joint limits, input independence, repeats).
        Slots: M = degree x branch combinations; ``valid`` marks modes, ``outcome`` says what
        became of every other slot and ``certificate()`` accounts for every root. A mode at a
        type II singularity is kept with its ``conditioning`` near 0 (``ill_conditioned()``).
        With ``strict``, a degenerate elimination with no isolated mode (e.g. SAM with parallel
        U-joint axes: a self-motion) raises SelfMotionError or SingularConfigurationError.

        ``certify`` (homotopy methods): "exact" (default) tests every endpoint that the
        double-precision Krawczyk test cannot certify again in exact dyadic arithmetic
        (``parakin.solvers.exact_certify``: milliseconds per such root; ill-conditioned roots near
        infinity need it), "double" only in double precision (faster; such roots stay
        uncertified and the input incomplete).
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
            single = self.forward_pose(theta)  # a serial chain has exactly one forward pose
            one = np.ones(theta.shape[:-1] + (1,), dtype=bool)
            zero = np.zeros(theta.shape[:-1], dtype=np.int32)
            return AssemblyModes(
                theta, single.pose[..., None, :, :], single.passive[..., None, :], single.residual[..., None],
                np.full(one.shape, np.nan), one, one, one.sum(-1), ~one,
                outcome=np.zeros(one.shape, dtype=np.int32), root_kind=np.full(one.shape, -1, dtype=np.int32),
                conditioning=np.ones(one.shape), real_roots=zero, near_roots=zero, at_infinity=zero, status=zero,
                outcomes=self.manifest.abi.mode_outcomes, pose_kind=self.manifest.pose_kind,
            )  # fmt: skip
        flat = theta.reshape(-1, theta.shape[-1])
        count = flat.shape[0]
        with progress(count, f"{self.name}: every assembly mode") as bar:
            # with a bar, in about a hundred steps so that it moves (each input is solved on its
            # own: the same answers); without one, in one step
            step = max(BAR_STEP, -(-count // 100)) if bar.active else max(count, 1)
            parts = []
            for start in range(0, max(count, 1), step):
                parts.append(self._every_mode(info, flat[start : start + step], certify == "exact"))
                bar.update(parts[-1]["count"].shape[0])
        out = parts[0] if len(parts) == 1 else {key: np.concatenate([p[key] for p in parts]) for key in parts[0]}
        modes = assemble(self, theta, out, info)
        degenerate = modes.status == self.manifest.abi.code("input_status", "degenerate")
        if strict and np.any(degenerate):
            index = first_index(degenerate)
            cause = (
                "homotopy paths that end nowhere (no isolated solution to reach)"
                if info.homotopy is not None
                else f"degenerate elimination ({', '.join(info.degeneracies) or 'the polynomial vanishes'})"
            )
            message = (
                f"forward pose at batch index {index}: {cause} and no isolated mode; "
                "the platform is not determined by the actuators here"
            )
            # a positive-dimensional solution set (a self-motion): report it, not a random point
            motion = self.self_motion(theta[index])
            if motion.count:
                raise SelfMotionError(f"{message}; the solution set is attached (.solution_set)", motion)
            raise SingularConfigurationError(f"{message}; no closed configuration was found near the home pose")
        return modes

    def _every_mode(self, info: Forward, flat: Array, exact: bool) -> dict[str, np.ndarray]:
        """The all-modes pipeline's arrays for a flat batch. A homotopy solves the geometry in its
        own size (``_unit_free``): the paths, the certificate and every threshold then see the same
        numbers in millimetres, metres or kilometres, and the modes are scaled back."""
        if info.homotopy is None:
            return self._every_mode_here(info, flat, exact)
        unit_free = self._unit_free
        if unit_free is None:
            return self._every_mode_here(info, flat, exact)
        scaled, unit = unit_free
        length_actuated = np.array([v.unit == "m" for v in self.manifest.actuated], dtype=bool)
        length_passive = np.array([v.unit == "m" for v in self.manifest.passive], dtype=bool)
        out = scaled._every_mode_here(info, np.where(length_actuated, flat / unit, flat), exact)
        out["passive"] = np.where(length_passive, out["passive"] * unit, out["passive"])
        out["poses"][..., :3, 3] *= unit
        # the closure residual in the caller's units, at the modes' own values
        where = np.isfinite(out["residual"]) & np.isfinite(out["passive"]).all(-1)
        if where.any():
            rows, slots = np.nonzero(where)
            residual = self.backend.call("loop_closure", flat[rows], out["passive"][rows, slots], self.params)
            out["residual"][rows, slots] = np.abs(residual["residual"]).max(-1, initial=0.0)
        return out

    @functools.cached_property
    def _unit_free(self) -> tuple[Mechanism, float] | None:
        """This mechanism with every length divided by a power of two near its size, and that
        power (an exact scaling in floating point); None where no rescaling is needed or where a
        parameter's unit is not a length, an angle or a pure number (its scaling is not known)."""
        known = all(p.unit in ("m", "rad", "") for p in self.manifest.parameters)
        unit = float(np.exp2(np.round(np.log2(length_scale(self)))))
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
        """Certify every input's endpoints (``exact``: what double precision cannot certify or
        decide is tested in exact arithmetic); an input whose certified roots fall short of the
        root count is tracked again in projective space (its suspect paths, then ``RETRACKS``:
        every path from the second start instance, then the first) and keeps the run with the
        most certified roots; then the modes are the certified real roots (``modes.reconcile``):
        never a silent loss, the certificate says what remains."""
        if flat.shape[0] == 0:  # an empty batch: nothing to certify
            paths = out["endpoints"].shape[1]
            empty = {"certified": np.zeros(0, np.int64), "path_certified": np.zeros((0, paths), bool)}
            return out | empty | {"retracked": np.zeros(0, bool), "undecided": np.zeros(0, np.int64)}
        found = certify(self, info, flat, out["endpoints"], exact)
        assert info.homotopy is not None and info.homotopy.root_count is not None
        count = info.homotopy.root_count.count
        retracked = np.zeros(flat.shape[0], dtype=bool)
        for instance in (None, *RETRACKS):
            short = np.nonzero((found.certified < count) & np.isfinite(flat).all(-1))[0]
            if not short.size:
                break
            retracked[short] = True
            if instance is None:  # the first run's suspect paths only, projectively, from the same start
                ends = out["endpoints"][short]
                plan = Retrack(0, suspect_paths(ends, found.unique[short]), ends[..., 0] + 1j * ends[..., 1])
            else:
                plan = Retrack(instance)
            again = numpy_modes(self, flat[short], info, retrack=plan)
            second = certify(self, info, flat[short], again["endpoints"], exact)
            better = second.certified > found.certified[short]
            rows = short[better]
            for key, value in again.items():
                out[key][rows] = value[better]
            for mine, theirs in zip(found, second, strict=True):
                mine[rows] = theirs[better]
        out = reconcile(self, info, flat, out, found)
        return out | {"certified": found.certified, "path_certified": found.unique, "retracked": retracked}

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
        """``forward_pose_all`` over a flat batch (N, n_a), one ``(start, AssemblyModes)`` per
        chunk of at most ``chunk`` inputs: memory bounded by the chunk whatever N."""
        theta = self._actuated(actuated).reshape(-1, len(self.actuated_names))
        if not (isinstance(chunk, int | np.integer) and chunk > 0):
            raise BadInputError(f"chunk must be a positive integer, got {chunk!r}")
        for start in range(0, theta.shape[0], chunk):
            yield start, self.forward_pose_all(theta[start : start + chunk], strict=strict)

    def count_modes(self, actuated: ArrayLike, chunk: int = 65536) -> dict[str, Array]:
        """Per input (batch shape of ``actuated``): ``count`` of assembly modes, ``real_roots``,
        ``near_roots``, ``at_infinity``, ``status`` and ``min_conditioning`` over the modes,
        computed chunk by chunk (peak memory set by ``chunk``, not by the batch)."""
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

    def self_motion(self, actuated: ArrayLike, starts: ArrayLike | None = None, step: float = 0.02) -> SelfMotion:
        """The solution set of the loop closure for one locked input where it is a curve (a
        self-motion), traced by continuation from ``starts`` (k, n_p) or from the home
        configuration and random perturbations of it (see ``parakin.solvers.continuation``)."""
        theta = self._actuated(actuated)
        step = positive_number(step, "step")
        if theta.ndim != 1:
            raise BadInputError(f"self_motion takes one input (n_a,), got shape {theta.shape}")
        start = None if starts is None else np.atleast_2d(self._passive(starts))
        return trace_self_motion(self, theta, start, step)

    def least_squares(self, actuated: ArrayLike, start: Configuration | ArrayLike) -> LeastSquares:
        """For locked inputs that no configuration satisfies exactly: the passive values that
        minimise the loop-closure residual (Levenberg-Marquardt from ``start``); its ``norm`` is
        the distance from compatible inputs (0 where they are compatible)."""
        theta = self._actuated(actuated)
        if theta.ndim != 1:
            raise BadInputError(f"least_squares takes one input (n_a,), got shape {theta.shape}")
        guess = start.passive if isinstance(start, Configuration) else start
        return least_squares_configuration(self, theta, self._passive(guess))

    # ------------------------------------------------------------------ rates
    def rate_jacobians(self, state: Configuration) -> dict[str, Array]:
        """A and B of A twist = B actuated_rates (mechanisms with a rate model, e.g. the SPM)."""
        self._require(self.capabilities.rates, "rate_jacobians", "A/B rate model")
        theta, passive = self._state(state)
        return self._finite("rate_jacobians", theta, passive)

    def passive_rates(self, state: Configuration, actuated_rates: ArrayLike) -> Array:
        """Passive joint rates from the loop closure: J_q qdot = -J_theta theta_dot."""
        theta, passive = self._state(state)
        rates = bounded_vector(actuated_rates, "actuated_rates", self.actuated_names)
        out = self.backend.call("loop_closure", theta, passive, self.params)
        actuated_jacobian = self.backend.call("loop_closure_actuated", theta, passive, self.params)["jacobian_actuated"]
        right = -(actuated_jacobian @ rates[..., None])[..., 0]
        return self._solve(out["jacobian"], right, "loop-closure Jacobian", "a type II (parallel) singularity")

    def leg_jacobians(self, state: Configuration) -> dict[str, Array]:
        """Each leg's 6x6 Jacobian (eq 9): twist (v of the origin of {P}, w; in {B}) per joint
        rate, columns in the leg's joint order (``m.capabilities.legs``)."""
        self._require(self.capabilities.legs, "leg_jacobians", "serial legs")
        theta, passive = self._state(state)
        return self._finite("leg_jacobians", theta, passive)

    def inverse_rate(self, state: Configuration, twist: ArrayLike, damping: float | None = None) -> Rates:
        """Joint rates for a platform twist (..., 6) = (v, w) in {B} (eq 10), leg by leg.

        ``damping``: None solves exactly and raises SingularConfigurationError at a singular
        Jacobian; a value lambda > 0 uses the damped pseudo-inverse J^T (J J^T + lambda^2 I)^-1 of
        the matrix that maps joint rates to the twist (each leg's J, or B of A twist = B rates),
        the paper's recommendation near a serial singularity (the motion is then not exactly as
        commanded). A single state broadcasts against a batch of twists and the reverse. A
        lower-mobility platform (a rate model with constraint wrenches C) takes only twists it can
        make, |C_i . twist| <= CONSTRAINT_TOLERANCE |C_i| |twist|, and raises BadInputError otherwise.
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
        """M of eq (11): actuated rates = M @ twist; rows of each leg's inverse Jacobian that
        belong to actuated joints, in actuated order."""
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
        """Platform twist (v, w) in {B} from actuator rates: twist = M^-1 theta_dot (eq 12), or
        A twist = B theta_dot with a rate model (and constraints twist = 0 for a lower-mobility
        platform: its parasitic components come out with the rest)."""
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
        """Actuator efforts that move the platform with the given actuated rates and accelerations
        (``parakin.dynamics.inverse_dynamics``: the platform's Newton-Euler wrench through the rate
        model; massless legs). Returns ``parakin.dynamics.InverseDynamics``."""
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
        """Y (..., n_a, 10) with efforts tau = Y theta over the platform's ten inertial parameters
        (``parakin.dynamics.dynamics_regressor``)."""
        from parakin import dynamics

        g = dynamics.STANDARD_GRAVITY if gravity is None else gravity
        return dynamics.dynamics_regressor(self, state, rates, accelerations, gravity=g, leg_inertias=leg_inertias)

    def to_mjcf(self, actuated: ArrayLike | None = None, **options: Any) -> str:
        """The MJCF text of this mechanism for MuJoCo: its legs as bodies, its loops cut by site
        connects, the home as qpos0 and every assembly mode of ``actuated`` (default: the home's)
        a keyframe (``parakin.mjcf.to_mjcf``, which lists the ``options``: modes, accuracy,
        timestep, masses, payload, actuators)."""
        from parakin.mjcf import to_mjcf

        return to_mjcf(self, actuated, **options)

    def actuator_forces(self, state: Configuration, wrench: ArrayLike) -> Array:
        """Actuator efforts that hold the platform against an external wrench (virtual work; see
        ``parakin.solvers.statics.actuator_forces`` for the wrench convention)."""
        from parakin.solvers.statics import actuator_forces

        return actuator_forces(self, state, wrench)

    def constraint_forces(self, state: Configuration, wrench: ArrayLike) -> Array:
        """Intensities of the constraint wrenches a lower-mobility platform's legs apply while its
        actuators hold ``wrench`` (``parakin.solvers.statics.constraint_forces``)."""
        from parakin.solvers.statics import constraint_forces

        return constraint_forces(self, state, wrench)

    def stiffness(self, state: Configuration, actuator_stiffness: ArrayLike | None = None) -> Array:
        """Platform stiffness K = G^T K_q G from actuator stiffnesses (default: the ones the
        mechanism declares as parameters, ``m.capabilities.statics``)."""
        from parakin.solvers.statics import stiffness

        if actuator_stiffness is None:
            statics = self.capabilities.statics
            self._require(statics, "stiffness without actuator stiffnesses", "declared actuator stiffness")
            assert statics is not None
            actuator_stiffness = [self.parameters[name] for name in statics.stiffness]
        return stiffness(self, state, actuator_stiffness)

    # ------------------------------------------------------------------ drawing
    def drawing(self, state: Configuration) -> dict[str, Array]:
        """The named point sets (..., 3, n) in {B} (metres) of the drawing kernel."""
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
        """Draw the mechanism (metres; 2-D for a planar drawing, on its sphere for a spherical
        one) in a configuration, mode ``mode`` of an AssemblyModes, or all its modes as a grid;
        a PNG is written to ``path`` when given (``parakin.interfaces.plot.plot``). Needs matplotlib."""
        from parakin.interfaces.plot import plot

        return plot(self, state, path, ax, title, mode=mode, all_modes=all_modes)

    # ------------------------------------------------------------------ singularities
    def is_architecturally_singular(self) -> bool:
        """Whether this geometry is singular at every pose (a useless design): one of the
        mechanism's normalised architecture measures (``architecture()``) is below its declared
        tolerance. False for mechanisms without such conditions."""
        info = self.capabilities.architecture
        if info is None:
            return False
        return any(abs(value) < info.tolerance for value in self.architecture().values())

    def architecture(self) -> dict[str, float]:
        """The mechanism's architecture-singularity measures at its parameters (``parakin inspect``
        shows them symbolically; zero means singular at every pose); empty for mechanisms
        without such conditions."""
        info = self.capabilities.architecture
        if info is None:
            return {}
        values = self.backend.call("architecture", self.params)["measures"]
        return {name: float(values[k]) for k, name in enumerate(info.measures)}

    def singularities(self, state: Configuration) -> dict[str, Array]:
        """Every named singularity factor (serial: leg determinants, eq 13-14; parallel: the
        closed-loop matrix), then the determinants themselves; zero means singular."""
        theta, passive = self._state(state)
        out = self._finite("singularity_factors", theta, passive)
        names = self.manifest.singularity_factors + self.manifest.determinants
        values = np.concatenate([out["factors"], out["determinants"]], axis=-1)
        return {name: values[..., k] for k, name in enumerate(names)}


__all__ = ["Mechanism"]
