"""Backends: the same generated kernels evaluated by NumPy, by CasADi, or compiled C.

Every backend has ``call(kernel, *inputs) -> {output name: array}``, where each input is an
array whose last axis indexes its group and whose leading axes broadcast.
"""

from __future__ import annotations

import warnings
from functools import lru_cache
from typing import Any, Protocol

import numpy as np

from parakin.errors import BackendFallbackWarning, BadInputError, CompiledUnavailableError, UnsupportedOperationError
from parakin.packages.compiled import CompiledBackend
from parakin.packages.package import GeneratedPackage
from parakin.results import Array
from parakin.validation import batch_shape, broadcast_batch


class Backend(Protocol):
    name: str

    def call(self, kernel: str, *inputs: Array) -> dict[str, Array]: ...


class NumpyBackend:
    """The generated NumPy module: pure Python + NumPy, no compiler needed."""

    name = "numpy"

    def __init__(self, package: GeneratedPackage) -> None:
        self.kernels = package.numpy_kernels

    def call(self, kernel: str, *inputs: Array) -> dict[str, Array]:
        batch_shape(inputs)  # the same broadcasting rule (and error) as the other backends
        return self.kernels[kernel](*inputs)


class CasadiBackend:
    """The generated CasADi Functions, mapped over the batch (one DM conversion per call)."""

    name = "casadi"

    def __init__(self, package: GeneratedPackage) -> None:
        try:
            builders = package.casadi_builders
        except ImportError as error:
            raise UnsupportedOperationError(f"backend 'casadi' needs the casadi module: {error}") from error
        self.functions: dict[str, Any] = {name: build() for name, build in builders.items()}

    @lru_cache(maxsize=64)  # noqa: B019  (the backend lives as long as its mechanism)
    def _mapped(self, kernel: str, count: int) -> Any:
        return self.functions[kernel].map(count)

    def call(self, kernel: str, *inputs: Array) -> dict[str, Array]:
        shape, flat = broadcast_batch(inputs)
        count = int(np.prod(shape, dtype=np.int64))
        function = self.functions[kernel]
        if count == 0:  # CasADi cannot map over nothing
            return {
                name: np.zeros(shape + _shape(function.size_out(index)))
                for index, name in enumerate(function.name_out())
            }
        mapped = self._mapped(kernel, count) if count > 1 else function
        arguments = [x.T if x.shape[0] == count else np.repeat(x.T, count, axis=1) for x in flat]
        outputs = mapped.call(arguments)
        result = {}
        for index, name in enumerate(function.name_out()):
            rows, cols = function.size_out(index)
            value = np.asarray(outputs[index], dtype=float).reshape(rows, count, cols).transpose(1, 0, 2)
            result[name] = value.reshape(shape + ((rows,) if cols == 1 else (rows, cols)))
        return result


def _shape(size: tuple[int, int]) -> tuple[int, ...]:
    rows, cols = size
    return (rows,) if cols == 1 else (rows, cols)


def make_backend(mechanism: GeneratedPackage, backend: str) -> Backend:
    """The backend of a package by name.

    Parameters
    ----------
    mechanism : GeneratedPackage
        The package whose kernels the backend evaluates.
    backend : str
        'numpy', 'casadi', 'compiled' (CasADi C code built with the system C compiler), or
        'auto': compiled when a C compiler works and the library cache is usable and private
        (``parakin.packages.compiled.distrust``), otherwise NumPy with a BackendFallbackWarning
        naming the cause ('compiled' raises that cause instead: a CompiledUnavailableError such
        as UntrustedCacheError or StaleLibraryError).

    Returns
    -------
    Backend
        An object with ``call(kernel, *inputs)``.
    """
    if backend == "numpy":
        return NumpyBackend(mechanism)
    if backend == "casadi":
        return CasadiBackend(mechanism)
    if backend in ("compiled", "auto"):
        try:
            return CompiledBackend(mechanism)
        except CompiledUnavailableError as error:
            if backend == "compiled":
                raise
            warnings.warn(
                f"backend 'auto' runs {mechanism.manifest.name} on NumPy: compiled C is unavailable "
                f"({type(error).__name__}: {error})",
                BackendFallbackWarning,
                stacklevel=3,
            )
            return NumpyBackend(mechanism)
    raise BadInputError(f"unknown backend {backend!r}; valid: 'auto', 'numpy', 'casadi', 'compiled'")
