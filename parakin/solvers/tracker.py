"""A forward-pose tracker for control loops: Newton from the previous solution, with every
buffer allocated once, so a solve costs one foreign call on the compiled backend.

Tracking never changes assembly mode silently. After each solve, every entry is checked for
- a crossing: the sign of det(d closure / d passive) at the new solution differs from the previous
  one, so a type II singularity lies between them (the mode on the far side is another one), and
- a suspect step: the solution moved more than ``jump_ratio`` times the first Newton step (the
  change the linearisation at the previous solution predicts), or that first step exceeds
  ``trust_step`` (beyond the linearisation's reach Newton finds *a* solution, not necessarily the
  one on this branch: 8 of 10 such coarse SPM steps landed on another branch). A suspect entry is
  re-solved by continuation in ``SUBSTEPS`` steps from its previous solution, which keeps the
  branch; what even that cannot follow (a crossing, a fold where the branch ends, a step still
  too coarse) is flagged.
``mode_change`` says what happened (``MODE_CHANGES``); with ``strict`` a flagged step raises
``AssemblyModeChangeError`` and the entries keep their previous solution.
"""

from __future__ import annotations

import ctypes

import numpy as np
from numpy.typing import ArrayLike

from parakin.errors import (
    AssemblyModeChangeError,
    BadInputError,
    ConvergenceError,
    UnsupportedOperationError,
    at_index,
    raise_for_newton_status,
)
from parakin.pose import rigid_or_nan, wrap_angle
from parakin.results import NEAR_SINGULAR, Array, Configuration
from parakin.solvers.linalg import inverse_condition, pivoted_solve
from parakin.validation import integer_in_range, newton_tolerance, positive_number

#: ``ForwardPoseTracker.mode_change`` codes
MODE_CHANGES = ("none", "crossed_singularity", "left_branch", "step_too_coarse")
#: substeps of the continuation that re-solves a suspect step
SUBSTEPS = 32
#: the defaults of ``ForwardPoseTracker`` and ``Mechanism.tracker`` (one set for both)
TOLERANCE, MAX_ITERATIONS, JUMP_RATIO, TRUST_STEP = 1e-12, 30, 4.0, 0.25


class ForwardPoseTracker:
    """Tracks the forward pose of a batch of n mechanisms (n = 1 for one robot).

    ``solve(actuated)`` runs Newton from the previous solution and returns the passive values
    (n, n_p) and poses (n, 4, 4) as views of internal buffers (copy them to keep them); a
    tracker started from one configuration (no batch axis) given one input (n_a,) returns one
    result, (n_p,) and (4, 4), as ``Mechanism.forward_pose`` does. The
    last ``residual``, ``iterations``, ``status``, ``conditioning`` (the type II distance of
    ``parakin.singularity`` at the current solutions, measured when read), ``orientation`` (sign
    of the closure Jacobian's determinant) and ``mode_change`` stay readable.
    Raises ConvergenceError or SingularConfigurationError like ``Mechanism.forward_pose``, and
    with ``strict`` AssemblyModeChangeError (see the module docstring).
    """

    def __init__(
        self,
        mechanism,
        start: Configuration,
        tolerance: float = TOLERANCE,
        max_iterations: int = MAX_ITERATIONS,
        strict: bool = True,
        jump_ratio: float = JUMP_RATIO,
        trust_step: float = TRUST_STEP,
    ) -> None:
        if not isinstance(start, Configuration):
            raise BadInputError(f"start must be a Configuration (from a solver), got {type(start).__name__}")
        if not mechanism.passive_names:
            raise UnsupportedOperationError(
                f"{mechanism.name} is a serial chain: no passive joints to track (forward_pose is closed form)"
            )
        theta, passive = mechanism._state(start)
        #: started from one configuration: one input gives one result, not a batch of one
        self.single = theta.ndim == 1 and passive.ndim == 1
        #: the last answer was one result (no batch axis): ``conditioning`` has the same shape
        self._unbatched = self.single
        tolerance = newton_tolerance(tolerance)
        max_iterations = integer_in_range(max_iterations, "max_iterations")
        self._step_job: ctypes.Structure | None = None
        self.jump_ratio = positive_number(jump_ratio, "jump_ratio")
        self.trust_step = positive_number(trust_step, "trust_step")
        self.strict = bool(strict)
        passive = passive.reshape(-1, len(mechanism.passive_names))
        self.mechanism = mechanism
        self.count = passive.shape[0]
        shape = (self.count, len(mechanism.actuated_names))
        try:
            self.actuated = np.array(np.broadcast_to(np.atleast_2d(theta), shape), dtype=float, order="C")
        except ValueError as error:
            raise BadInputError(f"start: actuated {theta.shape} does not match passive {passive.shape}") from error
        self.passive = np.ascontiguousarray(passive)
        self.pose = np.zeros((self.count, 4, 4))
        self.residual = np.zeros(self.count)
        self.iterations = np.zeros(self.count, dtype=np.int32)
        self.status = np.zeros(self.count, dtype=np.int32)
        # the Newton's pivot ratio of the closure Jacobian (its singularity test); what a user
        # reads is ``conditioning``, the one measure of every solver
        self._pivot_ratio = np.zeros(self.count)
        self.orientation = np.zeros(self.count, dtype=np.int32)
        self.first_step = np.zeros(self.count)
        self.mode_change = np.zeros(self.count, dtype=np.int32)
        # the start's pose; NaN where its joint values give no rigid pose (a start that does not
        # close, e.g. the home configuration of the internal one-input job): never a non-rigid one
        with np.errstate(all="ignore"):
            kernel = mechanism.backend.call("platform_pose", self.actuated, self.passive, mechanism.params)["pose"]
        self.pose[...] = rigid_or_nan(kernel)[0]
        self._previous = self.passive.copy()
        self._previous_pose = self.pose.copy()
        # int32, updated in place: the compiled step writes it through a pointer
        self._previous_orientation = np.ascontiguousarray(self._orientation_at(self.actuated, self.passive), np.int32)
        self._previous_theta = self.actuated.copy()
        self._incoming = self.actuated.copy()  # the compiled step's new inputs
        self._angular = bool(mechanism._angular_passive.any())
        self._params = np.ascontiguousarray(mechanism.params)
        self._tolerance, self._max_iterations = tolerance, max_iterations
        backend = mechanism.backend
        self._compiled = backend.name == "compiled"
        self._step = None
        if self._compiled:
            n_a, n_p = self.actuated.shape[1], self.passive.shape[1]
            self._job = backend.job(
                backend.NewtonJob,
                {
                    "n": self.count, "actuated": self.actuated, "actuated_stride": n_a, "guess": self.passive,
                    "guess_stride": n_p, "params": self._params, "max_iterations": max_iterations,
                    "tolerance": tolerance, "max_step": 0.5,
                    "singular_ratio": mechanism.tolerances["singular_ratio"], "passive": self.passive,
                    "pose": self.pose, "residual": self.residual, "conditioning": self._pivot_ratio,
                    "orientation": self.orientation, "first_step": self.first_step,
                    "iterations": self.iterations, "status": self.status,
                },
            )  # fmt: skip
            self._solve = backend.newton
            self._job_address = ctypes.addressof(self._job)
            # the step with its checks in one foreign call (NAME_forward_pose_step), where the
            # library has it: it keeps the previous solutions and says whether anything needs
            # the checks below
            self._step = getattr(backend, "newton_step", None)
            if self._step is not None:
                self._ranges = (mechanism._actuated_low, mechanism._actuated_high)  # the job points at them
                self._step_job = backend.job(
                    backend.StepJob,
                    {
                        "actuated": self.actuated, "incoming": self._incoming,
                        "previous_actuated": self._previous_theta,
                        "previous": self._previous, "previous_pose": self._previous_pose,
                        "previous_orientation": self._previous_orientation, "mode_change": self.mode_change,
                        "low": np.ascontiguousarray(self._ranges[0], dtype=float),
                        "high": np.ascontiguousarray(self._ranges[1], dtype=float),
                        "jump_ratio": self.jump_ratio, "trust_step": self.trust_step,
                    },
                )  # fmt: skip
                self._step_address = ctypes.addressof(self._step_job)

    def _orientation_at(self, actuated: Array, passive: Array) -> Array:
        jacobian = self.mechanism.backend.call("loop_closure", actuated, passive, self.mechanism.params)["jacobian"]
        return pivoted_solve(jacobian, np.zeros(passive.shape))[2]

    def configure(self, tolerance: float, max_iterations: int, max_step: float) -> None:
        """Change the Newton settings (used by ``Mechanism.forward_pose``'s single-input path)."""
        self._tolerance, self._max_iterations = tolerance, max_iterations
        if self._compiled:
            self._job.tolerance, self._job.max_iterations, self._job.max_step = tolerance, max_iterations, max_step

    def call(self) -> None:
        """One compiled Newton solve on the buffers as they are (no checks); ``conditioning``
        then answers per buffer entry, (n,)."""
        self._unbatched = False
        self._solve(self._job_address)

    @property
    def conditioning(self) -> Array:
        """Distance to a type II singularity at the current solutions: ``parakin.singularity``'s
        sigma_min / sigma_max of the closure Jacobian d closure / d passive (1 far from, 0 at a
        singularity; NaN where the Jacobian is not finite), shaped as ``solve``'s answer: a 0-d
        array for one result (a tracker of one configuration given one input, or not yet
        solved), else (n,) (also after ``call``); the measure
        ``forward_pose_all`` reports per mode. Measured when read (one closure call and one
        batched SVD), so a control loop that does not read it does not pay for it.

        Examples
        --------
        >>> import parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> tracker = m.tracker(m.forward_pose(m.home_actuated))
        >>> _ = tracker.solve(m.home_actuated)
        >>> round(float(tracker.conditioning), 4)
        0.6662
        """
        m = self.mechanism
        with np.errstate(all="ignore"):
            jacobian = m.backend.call("loop_closure", self.actuated, self.passive, m.params)["jacobian"]
        measure = inverse_condition(jacobian)
        return measure[0] if self._unbatched else measure

    @property
    def tolerance(self) -> float:
        """Newton tolerance (max-norm of the residual), fixed at construction."""
        return self._tolerance

    @property
    def max_iterations(self) -> int:
        """Newton iteration limit, fixed at construction."""
        return self._max_iterations

    def solve(self, actuated: ArrayLike) -> tuple[Array, Array]:
        """Newton from the previous solution for new actuated values.

        Every entry is checked for a change of assembly mode (module docstring); ``mode_change``
        says what happened, and the last ``residual``, ``iterations``, ``status``,
        ``conditioning`` and ``orientation`` stay readable.

        Parameters
        ----------
        actuated : array_like, shape (n, n_a) or (n_a,)
            The new inputs (m or rad), inside the actuators' ranges; (n_a,) for a tracker of one
            configuration.

        Returns
        -------
        tuple of (numpy.ndarray, numpy.ndarray)
            Passive values and poses ^B_P T (metres, in {B}): (n_p,) and (4, 4) for one input to a
            tracker of one configuration (``single``), else (n, n_p) and (n, 4, 4). Views of the
            tracker's buffers: copy them to keep them.

        Raises
        ------
        BadInputError
            An input outside its range, non-finite, or of a shape that does not match the tracker.
        ConvergenceError
            Newton did not converge (as ``Mechanism.forward_pose``).
        SingularConfigurationError
            A singular Newton matrix.
        AssemblyModeChangeError
            With ``strict``: a crossed singularity, a left branch or a step too coarse; the entries
            keep their previous solution.

        Examples
        --------
        >>> import numpy as np, parakin
        >>> m = parakin.load("five_bar", backend="numpy")
        >>> tracker = m.tracker(m.forward_pose(m.home_actuated))
        >>> for inputs in m.home_actuated + np.linspace(0.0, 0.1, 5)[:, None] * [1.0, -1.0]:
        ...     passive, pose = tracker.solve(inputs)
        >>> passive.round(6).tolist(), tracker.mode_change.tolist()
        ([0.0, 0.289656], [0])
        >>> m.forward_pose(inputs).passive.round(6).tolist()  # the same mode, solved afresh
        [0.0, 0.289656]
        """
        previous_theta = self._previous_theta
        if self._step is not None and type(actuated) is np.ndarray and actuated.dtype == np.float64:
            # the control loop's case: the C checks the inputs' ranges (and finiteness), keeps the
            # previous inputs and solutions, solves and checks every entry; nothing unusual, done
            try:
                self._incoming[...] = actuated
            except ValueError:
                step = -1
            else:
                step = self._step(self._job_address, self._step_address)
            if not step:
                single = self._unbatched = self.single and actuated.ndim == 1
                return (self.passive[0], self.pose[0]) if single else (self.passive, self.pose)
            if step > 0:
                return self._checked(actuated, previous_theta, stepped=True)
            # -1: a bad input, nothing changed; named below
        return self._checked(self.mechanism._actuated(actuated), previous_theta, stepped=False)

    @property
    def jump_ratio(self) -> float:
        """A solution that moved more than this times the first Newton step is suspect."""
        return self._jump_ratio

    @jump_ratio.setter
    def jump_ratio(self, value: float) -> None:
        self._jump_ratio = positive_number(value, "jump_ratio")
        if self._step_job is not None:
            self._step_job.jump_ratio = self._jump_ratio

    @property
    def trust_step(self) -> float:
        """A first Newton step beyond this leaves the linearisation's reach: suspect."""
        return self._trust_step

    @trust_step.setter
    def trust_step(self, value: float) -> None:
        self._trust_step = positive_number(value, "trust_step")
        if self._step_job is not None:
            self._step_job.trust_step = self._trust_step

    def _checked(self, theta: Array, previous_theta: Array, stepped: bool) -> tuple[Array, Array]:
        """``solve`` from validated inputs, or after the compiled step (``stepped``) found an entry
        that failed or needs the mode checks."""
        if not stepped:
            previous_theta[...] = self.actuated
            try:
                self.actuated[...] = theta
            except ValueError as error:
                raise BadInputError(f"actuated must broadcast to {self.actuated.shape}: {error}") from error
            self._previous[...] = self.passive
            self._previous_pose[...] = self.pose
        if stepped:  # the compiled step has solved and kept the previous solutions
            pass
        elif self._compiled:
            self._solve(self._job_address)
        else:
            solved = self.mechanism._newton_python(
                self.actuated, self.passive, self._tolerance, self._max_iterations, 0.5
            )
            self.passive[...], self.pose[...] = solved.passive, solved.pose
            self.residual[...], self.iterations[...], self.status[...] = (
                solved.residual,
                solved.iterations,
                solved.status,
            )
            self._pivot_ratio[...], self.orientation[...] = solved.conditioning, solved.orientation
            self.first_step[...] = solved.first_step
        unbatched = self.single and theta.ndim == 1
        if self.status.any():  # the whole batch goes back to its previous, consistent state
            self._restore(np.ones(self.count, dtype=bool), previous_theta)
            self._raise_for_status(unbatched)
        self._check_mode(previous_theta, unbatched)
        self._unbatched = unbatched
        if unbatched:
            return self.passive[0], self.pose[0]
        return self.passive, self.pose

    def _raise_for_status(self, unbatched: bool) -> None:
        """The error of the first failed entry, the solutions already restored. Newton that does
        not converge from a solution near a type II singularity (conditioning below
        ``NEAR_SINGULAR``) is at a fold: the tracked mode ends there, and the message says so
        instead of advising a closer guess (a tracker's user gives none)."""
        pick = 0 if unbatched else slice(None)  # one result: no batch index in the message
        try:
            raise_for_newton_status(
                self.status[pick],
                self.residual[pick],
                self.iterations[pick],
                "tracker",
                self._tolerance,
                self._max_iterations,
                self._previous[pick],
            )
        except ConvergenceError as error:
            i = int(np.argmax(self.status != 0))
            with np.errstate(all="ignore"):
                m = self.mechanism
                jacobian = m.backend.call("loop_closure", self.actuated[i : i + 1], self.passive[i : i + 1], m.params)[
                    "jacobian"
                ]
            kept = float(inverse_condition(jacobian)[0])
            at = "" if unbatched else at_index((i,))
            reached = float(self.residual[i])
            if kept < NEAR_SINGULAR:
                message = (
                    f"tracker{at}: the assembly mode ends at a type II singularity near here: Newton did not "
                    f"converge (residual {reached:.3g}) past the kept solution, whose conditioning is {kept:.3g} "
                    "(type II distance: 1 far from, 0 at a singularity); beyond this fold the mode has no real "
                    "solution: reverse the path, or re-solve with forward_pose_all for the modes there"
                )
            else:
                message = (
                    f"tracker{at} did not converge in {self._max_iterations} iterations: residual {reached:.3g} > "
                    f"tolerance {self._tolerance:g}; the previous solution is kept (conditioning {kept:.3g}): "
                    "try a smaller step"
                )
            raise ConvergenceError(message, residual=error.residual) from error

    def _restore(self, entries: np.ndarray, previous_theta: Array) -> None:
        """Entries back to the state before this solve: inputs, solution and pose together."""
        self.actuated[entries] = previous_theta[entries]
        self.passive[entries] = self._previous[entries]
        self.pose[entries] = self._previous_pose[entries]

    def _moved(self, passive: Array, reference: Array) -> Array:
        change = passive - reference
        return np.abs(np.where(self.mechanism._angular_passive, wrap_angle(change), change)).max(-1, initial=0.0)

    def _check_mode(self, previous_theta: Array, unbatched: bool = False) -> None:
        crossed = self.orientation * self._previous_orientation < 0
        # the first step is the linearised prediction: a quadratically converging Newton moves
        # within a small multiple of it, a jump to another branch moves much further; a first
        # step beyond trust_step leaves the linearisation's reach, where Newton finds *a* solution
        moved = np.abs(self.passive - self._previous).max(-1, initial=0.0)
        if self._angular and moved.max(initial=0.0) > np.pi:  # a wrapped angle moved less
            moved = self._moved(self.passive, self._previous)
        jumped = moved > self.jump_ratio * self.first_step + 100 * self._tolerance
        coarse = ~(self.first_step <= self.trust_step)
        suspect = ~crossed & (jumped | coarse)
        if not (crossed | suspect).any():  # the control loop's case: nothing to follow or flag
            self.mode_change.fill(0)
            np.copyto(self._previous_orientation, self.orientation, where=self.orientation != 0)
            return
        self.mode_change[...] = np.where(crossed, 1, 0)
        if suspect.any():
            self._follow_branch(np.nonzero(suspect)[0], previous_theta)
        changed = self.mode_change != 0
        if self.strict and changed.any():
            self._restore(changed, previous_theta)
            i = int(np.argmax(changed))
            what = {
                1: "the closure Jacobian's determinant changed sign: a type II singularity was crossed",
                2: "the path leaves its branch (a fold or a crossing between the two inputs)",
                3: f"the step is too coarse to stay on the branch (first Newton step {self.first_step[i]:.3g} > "
                f"trust_step {self.trust_step:g} even in {SUBSTEPS} substeps)",
            }[int(self.mode_change[i])]
            raise AssemblyModeChangeError(
                f"tracker{'' if unbatched else at_index((i,))}: {what}; the previous solution is kept (a smaller step, or "
                "strict=False to accept the new mode)",
                index=i,
                change=MODE_CHANGES[int(self.mode_change[i])],
            )
        np.copyto(self._previous_orientation, self.orientation, where=self.orientation != 0)

    def _follow_branch(self, index: np.ndarray, previous_theta: Array) -> None:
        """Re-solve the suspect entries along the input segment in ``SUBSTEPS`` steps from their
        previous solution (continuation), keeping the branch; flag what even that cannot follow."""
        m = self.mechanism
        q = self._previous[index].copy()
        start, end = previous_theta[index], self.actuated[index]
        orientation = self._previous_orientation[index].copy()
        lost = np.zeros(index.size, dtype=np.int32)
        newton = m._newton_compiled if self._compiled else m._newton_python
        for fraction in np.linspace(0.0, 1.0, SUBSTEPS + 1)[1:]:
            solved = newton(start + fraction * (end - start), q, self._tolerance, self._max_iterations, 0.5)
            failed = solved.status != 0
            flipped = solved.orientation * orientation < 0
            lost = np.where(lost != 0, lost, np.where(flipped, 1, np.where(failed, 2, 0)))
            lost = np.where((lost == 0) & ~(solved.first_step <= self.trust_step), 3, lost)
            q = np.where((lost == 0)[:, None], solved.passive, q)
            orientation = np.where(solved.orientation != 0, solved.orientation, orientation)
        followed = lost == 0
        keep = index[followed]
        self.passive[keep] = q[followed]
        self.pose[keep] = m.platform_pose(self.actuated[keep], self.passive[keep])
        self.orientation[keep] = orientation[followed]
        self.mode_change[index] = lost
