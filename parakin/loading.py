"""Loading a generated package as a Mechanism (``load``), and what is known about the packages
without loading one: their names (``available``), manifests (``metadata``) and exact SymPy models
(``symbolic``). Re-exported by ``parakin``: call them as ``parakin.load`` and so on.

Loading a package runs its code (its Python modules, and the C it compiles): load only
packages you trust.
"""

from __future__ import annotations

import difflib
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
    """Names of the generated packages found: the shipped ones, then those on ``$PARAKIN_PATH``.

    Returns
    -------
    list of str
        Mechanism names, each one ``load`` and ``metadata`` accept.

    Warns
    -----
    BrokenPackageWarning
        A package whose manifest cannot be read is skipped, named in the warning.
    ShadowedPackageWarning
        Two folders hold a package of one name: the warning says which one the name loads.

    Examples
    --------
    >>> import parakin
    >>> "five_bar" in parakin.available() and "stewart" in parakin.available()
    True
    """
    return readable_names()


def metadata(name: str | os.PathLike[str]) -> Manifest:
    """The typed manifest of a mechanism, read without loading it.

    Parameters
    ----------
    name : str or os.PathLike
        A mechanism name (``available()``) or a generated package folder.

    Returns
    -------
    Manifest
        Variables with units and limits, parameters, kernels, capabilities, examples.

    Raises
    ------
    UnknownMechanismError
        No package of that name or folder (the message suggests the closest names).
    BrokenPackageError
        The package's manifest cannot be read (the message names the field).

    Examples
    --------
    >>> import parakin
    >>> manifest = parakin.metadata("five_bar")
    >>> manifest.actuated_names, manifest.passive_names
    (['theta1', 'theta2'], ['x', 'y'])
    """
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


#: ``load``'s own keywords (everything else it takes is a parameter of the mechanism)
LOAD_KEYWORDS = ("backend", "limits")


def _misspelt_keywords(manifest: Manifest, given: Mapping[str, object]) -> None:
    """A keyword that is no parameter of the mechanism but a misspelling of one of ``load``'s own
    keywords (``backnd=``, ``Limits=``) is named as that keyword, not as an unknown parameter."""
    names = manifest.parameter_names
    for key in given:
        if key in names:
            continue
        same_case = [k for k in LOAD_KEYWORDS if k.lower() == key.lower()]
        close = same_case or difflib.get_close_matches(key, [*LOAD_KEYWORDS, *names], n=1, cutoff=0.6)
        if close and close[0] in LOAD_KEYWORDS:
            raise BadInputError(
                f"unknown keyword {key!r} of parakin.load; did you mean {close[0]!r}? load's keywords: "
                f"{list(LOAD_KEYWORDS)}, and the parameters of {manifest.name!r}: {names}"
            )


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
    """Load a mechanism, by name or generated-package folder, with its paper's default parameters.

    Loading a package runs its code: its generated Python modules are imported and, on the
    compiled backend, its C sources are compiled and loaded. Load only packages you trust.

    Parameters
    ----------
    name : str or os.PathLike
        A mechanism name (``available()``) or a generated package folder.
    backend : {"auto", "compiled", "numpy", "casadi"}
        "auto": compiled C if a compiler and the cache work, else NumPy with a
        BackendFallbackWarning naming the cause. "numpy" loads fastest (no compilation).
    limits : dict of str to (float, float), optional
        Joint ranges by variable name, (low, high) in SI units (m or rad; ``-inf``/``inf`` for
        an open side): passive joint limits, and actuated ranges (actuator strokes), which
        every solver then checks instead of the declared ones.
    **parameters : float or array_like
        The mechanism's parameters overridden, scalars by name (m, rad or the unit
        ``metadata(name).parameters`` gives), vector parameters such as point lists by their
        group name (with the group's shape).

    Returns
    -------
    Mechanism
        Every solver of the mechanism with these parameters bound.

    Raises
    ------
    UnknownMechanismError
        No package of that name or folder (the message suggests the closest names).
    BadInputError
        An unknown parameter, limit or keyword (the message suggests the closest names: a
        misspelt ``backend`` or ``limits`` is named as such), a value out of its domain, a
        malformed limit, or an unknown backend.
    CompiledUnavailableError
        ``backend="compiled"`` without a working compiler or cache.

    Warns
    -----
    ArchitectureSingularityWarning
        The geometry is singular at every pose.
    ShadowedPackageWarning
        Another folder of the search path holds a package of the same name (hidden by this one).

    Examples
    --------
    >>> import parakin
    >>> m = parakin.load("five_bar", backend="numpy", d=0.2)
    >>> m.parameters["d"], m.backend.name
    (0.2, 'numpy')
    >>> parakin.load("five_bar", backnd="numpy")
    Traceback (most recent call last):
        ...
    parakin.errors.BadInputError: unknown keyword 'backnd' of parakin.load; did you mean 'backend'? ...
    """
    package = GeneratedPackage.find(name)
    manifest = package.manifest
    _misspelt_keywords(manifest, parameters)
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
    """The derived SymPy objects of a mechanism (needs SymPy, the ``generator`` extra).

    Parameters
    ----------
    name : str or os.PathLike
        A mechanism name (``available()``) or a generated package folder.

    Returns
    -------
    dict of str to object
        SymPy expressions and matrices by name: loop closure, leg Jacobians or rate matrices,
        determinants, named singularity factors, inverse steps, forward polynomial.

    Raises
    ------
    UnsupportedOperationError
        SymPy is not installed (``pip install 'parakin[generator]'``).
    UnknownMechanismError
        No package of that name or folder.

    Examples
    --------
    >>> import parakin
    >>> expressions = parakin.symbolic("five_bar")
    >>> "loop_closure" in expressions and "forward_polynomial" in expressions
    True
    """
    try:
        import sympy  # noqa: F401
    except ImportError as error:
        raise UnsupportedOperationError("symbolic expressions need SymPy: pip install 'parakin[generator]'") from error
    return GeneratedPackage.find(name).symbolic()


__all__ = ["available", "load", "metadata", "symbolic"]
