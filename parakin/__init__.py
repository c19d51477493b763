"""parakin: kinematics of parallel manipulators from generated symbolic models.

    >>> import parakin
    >>> m = parakin.load("sam")                      # paper defaults, fastest available backend
    >>> ik = m.inverse_pose(parakin.pose_from_xyz_euler([0, 0, 0.664, 0, 0, 0]))
    >>> fk = m.forward_pose(ik.actuated[0], guess=ik.branch(0))

Units are SI and radians; poses are ^B_P T (..., 4, 4); see each mechanism's docstring in
``mechanisms/`` (also ``parakin inspect NAME``) for frames and branch numbering.
"""

from __future__ import annotations

import importlib
import pkgutil
from typing import Any

import generated
from parakin.backends import make_backend
from parakin.errors import (
    BadInputError,
    ConvergenceError,
    InconsistentInputError,
    ParakinError,
    SelfMotionError,
    SingularConfigurationError,
    UnknownMechanismError,
    UnreachablePoseError,
)
from parakin.extensions import extension
from parakin.mechanism import Mechanism
from parakin.pose import (
    euler_zyx_to_rotation,
    pose_from_xyz_euler,
    pose_from_xyz_euler_deg,
    xyz_euler_deg_from_pose,
    xyz_euler_from_pose,
)
from parakin.results import AssemblyModes, Configuration, ForwardPose, InversePose, Rates

__version__ = "0.1.0"


def available() -> list[str]:
    """Names of the mechanisms present in ``generated/``."""
    return sorted(
        info.name.removesuffix("_numpy")
        for info in pkgutil.iter_modules(generated.__path__)
        if info.name.endswith("_numpy")
    )


def metadata(name: str) -> dict[str, Any]:
    """The generated metadata of ``name`` (variables, parameters, branches, factor names)."""
    if name not in available():
        raise UnknownMechanismError(f"unknown mechanism {name!r}; available: {available()}")
    return importlib.import_module(f"generated.{name}_numpy").MECHANISM


def load(
    name: str,
    backend: str = "auto",
    limits: dict[str, tuple[float, float]] | None = None,
    **parameters: float,
) -> Mechanism:
    """Load a mechanism with its paper's default parameters, overridden by ``parameters``.

    ``backend``: 'auto' (compiled C if a compiler works, else NumPy), 'compiled', 'numpy' or
    'casadi'. ``limits`` overrides the passive joint ranges (name -> (low, high)).
    """
    info = metadata(name)
    unknown = sorted(set(parameters) - set(info["parameters"]))
    if unknown:
        raise UnknownMechanismError(f"unknown parameter(s) {unknown} for {name!r}; valid: {sorted(info['parameters'])}")
    values = {**info["parameters"], **{k: float(v) for k, v in parameters.items()}}
    bounds = {
        k: (-float("inf") if lo is None else lo, float("inf") if hi is None else hi)
        for k, (lo, hi) in info["limits"].items()
    }
    for key, bound in (limits or {}).items():
        if key not in info["passive"]:
            raise UnknownMechanismError(f"unknown limit {key!r} for {name!r}; valid: {info['passive']}")
        bounds[key] = (float(bound[0]), float(bound[1]))
    mechanism = Mechanism(info, make_backend(name, backend), values, bounds)
    module = extension(name)
    if module is not None and hasattr(module, "on_load"):
        module.on_load(mechanism)  # e.g. warn about an architecturally singular geometry
    return mechanism


def symbolic(name: str) -> dict[str, Any]:
    """The derived SymPy objects of ``name`` (needs SymPy): loop closure, leg Jacobians,
    determinants, named singularity factors, inverse steps, forward polynomial."""
    metadata(name)
    return importlib.import_module(f"generated.{name}_symbolic").load()


__all__ = [
    "AssemblyModes",
    "BadInputError",
    "Configuration",
    "ConvergenceError",
    "ForwardPose",
    "InconsistentInputError",
    "InversePose",
    "Mechanism",
    "ParakinError",
    "Rates",
    "SelfMotionError",
    "SingularConfigurationError",
    "UnknownMechanismError",
    "UnreachablePoseError",
    "available",
    "euler_zyx_to_rotation",
    "load",
    "metadata",
    "pose_from_xyz_euler",
    "pose_from_xyz_euler_deg",
    "symbolic",
    "xyz_euler_deg_from_pose",
    "xyz_euler_from_pose",
]
