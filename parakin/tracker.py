"""A forward-pose tracker for control loops: Newton from the previous solution, with every
buffer allocated once, so a solve costs one foreign call on the compiled backend."""

from __future__ import annotations

import ctypes

import numpy as np
from numpy.typing import ArrayLike

from parakin.errors import BadInputError, raise_for_newton_status
from parakin.results import Array, Configuration


class ForwardPoseTracker:
    """Tracks the forward pose of a batch of n mechanisms (n = 1 for one robot).

    ``solve(actuated)`` runs Newton from the previous solution and returns the passive values
    (n, n_p) and poses (n, 4, 4) as views of internal buffers (copy them to keep them); the
    last ``residual``, ``iterations`` and ``status`` stay readable. Raises ConvergenceError or
    SingularConfigurationError like ``Mechanism.forward_pose``.
    """

    def __init__(self, mechanism, start: Configuration, tolerance: float = 1e-12, max_iterations: int = 30) -> None:
        passive = np.array(start.passive, dtype=float).reshape(-1, len(mechanism.passive_names))
        self.mechanism = mechanism
        self.count = passive.shape[0]
        shape = (self.count, len(mechanism.actuated_names))
        self.actuated = np.array(np.broadcast_to(np.atleast_2d(start.actuated), shape), dtype=float, order="C")
        self.passive = np.ascontiguousarray(passive)
        self.pose = np.zeros((self.count, 4, 4))
        self.residual = np.zeros(self.count)
        self.iterations = np.zeros(self.count, dtype=np.int32)
        self.status = np.zeros(self.count, dtype=np.int32)
        self._params = np.ascontiguousarray(mechanism.params)
        self._tolerance, self._max_iterations = tolerance, max_iterations
        backend = mechanism.backend
        self._compiled = backend.name == "compiled"
        self.conditioning = np.zeros(self.count)
        if self._compiled:
            n_a, n_p = self.actuated.shape[1], self.passive.shape[1]
            self._job = backend.job(
                backend.NewtonJob,
                {
                    "n": self.count, "actuated": self.actuated, "actuated_stride": n_a, "guess": self.passive,
                    "guess_stride": n_p, "params": self._params, "max_iterations": max_iterations,
                    "tolerance": tolerance, "max_step": 0.5,
                    "singular_ratio": mechanism.tolerances["singular_ratio"], "passive": self.passive,
                    "pose": self.pose, "residual": self.residual, "conditioning": self.conditioning,
                    "iterations": self.iterations, "status": self.status,
                },
            )  # fmt: skip
            self._solve = backend.newton
            self._job_address = ctypes.addressof(self._job)

    def configure(self, tolerance: float, max_iterations: int, max_step: float) -> None:
        """Change the Newton settings (used by ``Mechanism.forward_pose``'s single-input path)."""
        self._tolerance, self._max_iterations = tolerance, max_iterations
        if self._compiled:
            self._job.tolerance, self._job.max_iterations, self._job.max_step = tolerance, max_iterations, max_step

    def call(self) -> None:
        """One compiled Newton solve on the buffers as they are (no checks)."""
        self._solve(self._job_address)

    @property
    def tolerance(self) -> float:
        """Newton tolerance (max-norm of the residual), fixed at construction."""
        return self._tolerance

    @property
    def max_iterations(self) -> int:
        """Newton iteration limit, fixed at construction."""
        return self._max_iterations

    def solve(self, actuated: ArrayLike) -> tuple[Array, Array]:
        """Newton from the previous solution for new actuated values (n, n_a) or (n_a,)."""
        try:
            self.actuated[...] = actuated
        except ValueError as error:
            raise BadInputError(f"actuated must broadcast to {self.actuated.shape}: {error}") from error
        if self._compiled:
            self._solve(self._job_address)
        else:
            passive, pose, residual, iterations, status, conditioning = self.mechanism._newton_python(
                self.actuated, self.passive, self._tolerance, self._max_iterations, 0.5
            )
            self.passive[...], self.pose[...] = passive, pose
            self.residual[...], self.iterations[...], self.status[...] = residual, iterations, status
            self.conditioning[...] = conditioning
        if self.status.any():  # failed entries kept their previous (good) solution
            raise_for_newton_status(
                self.status, self.residual, self.iterations, "tracker", self._tolerance, self._max_iterations
            )
        return self.passive, self.pose
