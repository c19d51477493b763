"""What the solvers, the drawing and the tables read from a loaded mechanism: the interface that
``parakin.Mechanism`` implements and that the modules it delegates to (all modes, continuation,
statics, plot, display) take their mechanism argument as. They depend on this interface, not on
the class, so that ``Mechanism`` can call them without an import circle.

Members with a leading underscore are the mechanism's internals that its own solvers share
(joint-limit arrays, the one-input job cache, the NumPy Newton loop, the pivoted solve); users
call the public methods of ``parakin.Mechanism``.
"""

from __future__ import annotations

import threading
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from parakin.packages.backends import Backend
from parakin.packages.manifest import Capabilities, Manifest
from parakin.packages.package import GeneratedPackage
from parakin.results import Array, AssemblyModes, Configuration, ForwardPose, NewtonOutcome
from parakin.solvers.tracker import ForwardPoseTracker


class LoadedMechanism(Protocol):
    """A mechanism with its parameters bound and a backend chosen (``parakin.load``); the
    methods' conventions are those of ``parakin.Mechanism``."""

    name: str
    package: GeneratedPackage
    manifest: Manifest
    backend: Backend
    params: Array
    parameters: dict[str, float]
    tolerances: dict[str, float]
    limits: dict[str, tuple[float, float]]
    actuated_names: list[str]
    passive_names: list[str]
    home_actuated: Array
    home_passive: Array
    _limit_index: NDArray[np.intp]
    _limit_low: Array
    _limit_high: Array
    _angular_actuated: NDArray[np.bool_]
    _angular_passive: NDArray[np.bool_]
    _single_input: threading.local

    @property
    def capabilities(self) -> Capabilities: ...

    @property
    def actuated_bounds(self) -> tuple[Array, Array]: ...

    def within_limits(self, passive: ArrayLike) -> np.ndarray: ...

    def platform_pose(self, actuated: ArrayLike, passive: ArrayLike) -> Array: ...

    def loop_closure(self, actuated: ArrayLike, passive: ArrayLike) -> dict[str, Array]: ...

    def forward_pose(self, actuated: ArrayLike, guess: Configuration | ArrayLike | None = None) -> ForwardPose: ...

    def forward_pose_all(
        self, actuated: ArrayLike, strict: bool = True, method: str | None = None, certify: str = "exact"
    ) -> AssemblyModes: ...

    def passive_rates(self, state: Configuration, actuated_rates: ArrayLike) -> Array: ...

    def _actuated(self, value: ArrayLike) -> Array: ...

    def tracker(self, start: Configuration, *, strict: bool = True) -> ForwardPoseTracker: ...

    def rate_jacobians(self, state: Configuration) -> dict[str, Array]: ...

    def leg_jacobians(self, state: Configuration) -> dict[str, Array]: ...

    def rate_matrix(self, state: Configuration) -> Array: ...

    def drawing(self, state: Configuration) -> dict[str, Array]: ...

    def _solve(self, matrix: Array, rhs: Array, what: str, hint: str, columns: bool = False) -> Array: ...

    def _newton_python(
        self,
        theta: Array,
        start: Array,
        tolerance: float,
        max_iterations: int,
        max_step: float,
        keep_last: bool = False,
    ) -> NewtonOutcome: ...


__all__ = ["LoadedMechanism"]
