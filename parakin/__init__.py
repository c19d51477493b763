"""parakin: kinematics of parallel manipulators from generated symbolic models.

    >>> import parakin
    >>> parakin.available()                          # the generated packages found
    >>> m = parakin.load(parakin.available()[0])     # paper defaults, fastest available backend
    >>> modes = m.forward_pose_all(m.home_actuated)  # every assembly mode, closed form
    >>> ik = m.inverse_pose(modes.poses[0])          # every inverse branch

Units are SI and radians; poses are ^B_P T (..., 4, 4); ``m.manifest.conventions`` (the
mechanism file's docstring, also ``parakin inspect NAME``) gives frames and branch numbering.

Loading a package runs its code (its Python modules, and the C it compiles): load only
packages you trust.
"""

from __future__ import annotations

from parakin.errors import (
    ArchitectureSingularityWarning,
    AssemblyModeChangeError,
    BackendFallbackWarning,
    BadInputError,
    BrokenPackageError,
    BrokenPackageWarning,
    CacheUnavailableError,
    CalibrationDataError,
    CalibrationUnavailableError,
    CompiledUnavailableError,
    CompilerUnavailableError,
    ConvergenceError,
    FixedModelError,
    InconsistentInputError,
    NearSingularModeWarning,
    NoSuchModeError,
    ParakinError,
    SelfMotionError,
    ShadowedPackageWarning,
    SingularConfigurationError,
    StaleLibraryError,
    StoreInUseError,
    UnknownKeywordError,
    UnknownMechanismError,
    UnreachablePoseError,
    UnsupportedOperationError,
    UntrustedCacheError,
)
from parakin.loading import available, load, metadata, symbolic
from parakin.mechanism import Mechanism
from parakin.packages.manifest import Manifest
from parakin.pose import (
    euler_zyx_to_rotation,
    pose_from_xyz_euler,
    pose_from_xyz_euler_deg,
    xyz_euler_deg_from_pose,
    xyz_euler_from_pose,
)
from parakin.results import AssemblyModes, Configuration, ForwardPose, InversePose, Rates
from parakin.solvers.continuation import LeastSquares, SelfMotion
from parakin.solvers.tracker import ForwardPoseTracker
from parakin.studies.sweep import sweep

__version__ = "0.2.0"


#: the calibration's public names, imported from ``parakin.calibration`` on first use
_CALIBRATION = ("CalibrationData", "CalibrationResult", "PoseDesign", "calibrate", "design_poses")


def __getattr__(name: str) -> object:
    """``parakin.mujoco`` (the MuJoCo bridge; MuJoCo is optional: the ``sim`` extra) and the
    calibration's names, imported on first use."""
    import importlib

    if name == "mujoco":
        return importlib.import_module("parakin.mujoco_bridge")
    if name in _CALIBRATION:  # imported on first use: it costs most of a command's start-up
        return getattr(importlib.import_module("parakin.calibration"), name)
    raise AttributeError(f"module 'parakin' has no attribute {name!r}")


def __dir__() -> list[str]:
    """The public names (``__all__``) and the submodules, not this module's own imports."""
    import pkgutil

    return sorted({*__all__, *(m.name for m in pkgutil.iter_modules(__path__) if not m.name.startswith("_"))})


__all__ = [
    "ArchitectureSingularityWarning",
    "AssemblyModeChangeError",
    "AssemblyModes",
    "BackendFallbackWarning",
    "BadInputError",
    "BrokenPackageError",
    "BrokenPackageWarning",
    "ShadowedPackageWarning",
    "CacheUnavailableError",
    "CalibrationData",
    "CalibrationDataError",
    "CalibrationResult",
    "CalibrationUnavailableError",
    "CompiledUnavailableError",
    "CompilerUnavailableError",
    "Configuration",
    "ConvergenceError",
    "FixedModelError",
    "ForwardPose",
    "ForwardPoseTracker",
    "InconsistentInputError",
    "InversePose",
    "LeastSquares",
    "Manifest",
    "Mechanism",
    "NearSingularModeWarning",
    "NoSuchModeError",
    "ParakinError",
    "PoseDesign",
    "Rates",
    "SelfMotion",
    "SelfMotionError",
    "SingularConfigurationError",
    "StaleLibraryError",
    "StoreInUseError",
    "UnknownKeywordError",
    "UnknownMechanismError",
    "UnreachablePoseError",
    "UnsupportedOperationError",
    "UntrustedCacheError",
    "available",
    "calibrate",
    "design_poses",
    "euler_zyx_to_rotation",
    "load",
    "metadata",
    "pose_from_xyz_euler",
    "pose_from_xyz_euler_deg",
    "sweep",
    "symbolic",
    "xyz_euler_deg_from_pose",
    "xyz_euler_from_pose",
]
