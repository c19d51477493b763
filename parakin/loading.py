"""Loading a generated package as a Mechanism (``load``), and what is known about the packages
without loading one: their names (``available``), manifests (``metadata``) and exact SymPy models
(``symbolic``). Re-exported by ``parakin``: call them as ``parakin.load`` and so on.

Loading a package runs its code (its Python modules, and the C it compiles): load only
packages you trust.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Mapping
from typing import Any

from parakin.errors import ArchitectureSingularityWarning, BadInputError, UnsupportedOperationError
from parakin.mechanism import Mechanism
from parakin.packages.backends import make_backend
from parakin.packages.manifest import Manifest, unknown_name
from parakin.packages.package import GeneratedPackage, readable_names
from parakin.validation import as_array, in_domain, in_magnitude, real_number


def available() -> list[str]:
    """Names of the generated packages found (shipped ones, then ``$PARAKIN_PATH``); a package
    whose manifest cannot be read is skipped with a BrokenPackageWarning naming it."""
    return readable_names()


def metadata(name: str | os.PathLike[str]) -> Manifest:
    """The typed manifest of a mechanism (by name or package folder): variables with units and
    limits, parameters, kernels, capabilities, examples."""
    return GeneratedPackage.find(name).manifest


def _parameter_values(manifest: Manifest, given: dict[str, object]) -> dict[str, float]:
    """Defaults overridden by ``given``: finite reals, each in its manifest domain."""
    values = manifest.parameter_defaults
    groups = {g.name: g for g in manifest.parameter_groups}
    for key, value in given.items():
        if key in groups:
            group = groups[key]
            array = as_array(value, f"parameter {key!r}", group.shape)  # type: ignore[arg-type]
            if array.shape != group.shape:
                raise BadInputError(f"parameter {key!r} must have shape {group.shape}, got {array.shape}")
            values.update(zip(group.symbols, (float(v) for v in array.ravel()), strict=True))
        elif key in values:
            values[key] = real_number(value, f"parameter {key!r}")
        else:
            raise unknown_name("parameter", key, manifest.parameter_names, manifest.name)
    for parameter in manifest.parameters:
        in_domain(values[parameter.name], parameter.name, parameter.domain)
        in_magnitude(values[parameter.name], f"parameter {parameter.name!r}")
    return values


def _bound(value: object, key: str) -> float:
    """One side of a joint range: a finite real, or -inf / inf for an open side."""
    if isinstance(value, float) and math.isinf(value):
        return value
    return real_number(value, f"limits[{key!r}]")


def load(
    name: str | os.PathLike[str],
    *,
    backend: str = "auto",
    limits: dict[str, tuple[float, float]] | None = None,
    **parameters: Any,
) -> Mechanism:
    """Load a mechanism, by name or generated-package folder, with its paper's default
    parameters overridden by ``parameters`` (scalars by name, vector parameters such as point
    lists by their group name).

    ``backend``: 'auto' (compiled C if a compiler and the cache work, else NumPy with a
    BackendFallbackWarning naming the cause), 'compiled', 'numpy' or 'casadi'. ``limits``
    overrides joint ranges (name -> (low, high), SI units): passive joint limits, and actuated
    ranges (actuator strokes), which every solver then checks instead of the declared ones. An unknown parameter or limit
    is a BadInputError suggesting the closest names. Warns (ArchitectureSingularityWarning) when
    the geometry is singular at every pose.

    Loading a package runs its code: its generated Python modules are imported and, on the
    compiled backend, its C sources are compiled and loaded. Load only packages you trust.
    """
    package = GeneratedPackage.find(name)
    manifest = package.manifest
    values = _parameter_values(manifest, parameters)
    bounds = {v.name: v.limits for v in manifest.passive if v.limits != (-math.inf, math.inf)}
    if limits is not None and not isinstance(limits, Mapping):
        raise BadInputError(f"limits must be a mapping name -> (low, high), got {type(limits).__name__}")
    ranges: dict[str, tuple[float, float]] = {}
    for key, bound in (limits or {}).items():
        if key not in manifest.passive_names and key not in manifest.actuated_names:
            raise unknown_name("limit", key, [*manifest.actuated_names, *manifest.passive_names], manifest.name)
        if not isinstance(bound, tuple | list) or len(bound) != 2:
            raise BadInputError(f"limits[{key!r}] must be a (low, high) pair, got {bound!r}")
        low, high = (_bound(value, key) for value in bound)
        if not low < high:
            raise BadInputError(f"limits[{key!r}] must be (low, high) with low < high, got {bound!r}")
        (bounds if key in manifest.passive_names else ranges)[key] = (float(low), float(high))
    mechanism = Mechanism(package, make_backend(package, backend), values, bounds, ranges)
    if mechanism.is_architecturally_singular():
        measures = ", ".join(f"{k} = {v:.3g}" for k, v in mechanism.architecture().items())
        warnings.warn(
            f"{manifest.name} geometry is architecturally singular (singular at every pose): {measures}",
            ArchitectureSingularityWarning,
            stacklevel=2,
        )
    return mechanism


def symbolic(name: str | os.PathLike[str]) -> dict[str, object]:
    """The derived SymPy objects of a mechanism (needs SymPy, the ``generator`` extra): loop
    closure, leg Jacobians, determinants, named singularity factors, inverse steps, forward
    polynomial."""
    try:
        import sympy  # noqa: F401
    except ImportError as error:
        raise UnsupportedOperationError("symbolic expressions need SymPy: pip install 'parakin[generator]'") from error
    return GeneratedPackage.find(name).symbolic()


__all__ = ["available", "load", "metadata", "symbolic"]
