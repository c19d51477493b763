"""Named results: what the solvers return. Arrays carry the caller's leading batch shape."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]
Mask = NDArray[np.bool_]


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

    def branch(self, index: int) -> Configuration:
        """Branch ``index`` as a configuration (batch shape of the pose)."""
        return Configuration(self.actuated[..., index, :], self.passive[..., index, :], self.pose)


@dataclass(frozen=True)
class AssemblyModes:
    """Every forward-pose solution, padded to a fixed count M: arrays (..., M, ...).

    ``real``: the polynomial root was real; ``valid``: real, polished to tolerance, within joint
    limits, not a repeat of an earlier mode (double roots) and not input-independent;
    ``input_independent``: real modes at a factor that makes the pose independent of the inputs
    (e.g. the Agile Eye's folded poses), flagged and not counted; ``count`` = valid modes per input."""

    actuated: Array
    poses: Array
    passive: Array
    residual: Array
    root: Array
    real: Mask
    valid: Mask
    count: NDArray[np.int64]
    input_independent: Mask

    def mode(self, index: int) -> Configuration:
        """Mode ``index`` as a configuration."""
        return Configuration(self.actuated, self.passive[..., index, :], self.poses[..., index, :, :])


@dataclass(frozen=True)
class Rates:
    """Joint rates from a platform twist: actuated (..., n_a) and passive (..., n_p)."""

    actuated: Array
    passive: Array
