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
from parakin.package import GeneratedPackage
from parakin.results import Array


class Backend(Protocol):
    name: str

    def call(self, kernel: str, *inputs: Array) -> dict[str, Array]: ...


def broadcast_shapes(*shapes: tuple[int, ...]) -> tuple[int, ...]:
    """``np.broadcast_shapes`` with the one batch rule of parakin: BadInputError naming them."""
    try:
        return tuple(np.broadcast_shapes(*shapes))
    except ValueError as error:
        raise BadInputError(f"batch shapes do not broadcast: {', '.join(map(str, shapes))}") from error


def batch_shape(inputs: tuple[Array, ...]) -> tuple[int, ...]:
    """The broadcast of the inputs' leading (batch) shapes, or BadInputError naming them."""
    return broadcast_shapes(*(np.shape(x)[:-1] for x in inputs))


def broadcast_batch(inputs: tuple[Array, ...]) -> tuple[tuple[int, ...], list[Array]]:
    """The common batch shape and each input reshaped to (n, size) (or (1, size) to share)."""
    shape = batch_shape(inputs)
    count = int(np.prod(shape, dtype=np.int64))
    flat = []
    for x in inputs:
        array = np.asarray(x, dtype=float)
        size = array.shape[-1]
        if array.shape[:-1] == ():
            flat.append(np.ascontiguousarray(array.reshape(1, size)))
        else:  # the size is explicit: an empty batch has no -1 to infer
            flat.append(np.ascontiguousarray(np.broadcast_to(array, shape + (size,)).reshape(count, size)))
    return shape, flat


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
    """'numpy', 'casadi', 'compiled' (CasADi C code built with the system C compiler), or
    'auto': compiled when a C compiler and the library cache work, otherwise NumPy with a
    BackendFallbackWarning naming the cause ('compiled' raises that cause instead)."""
    if backend == "numpy":
        return NumpyBackend(mechanism)
    if backend == "casadi":
        return CasadiBackend(mechanism)
    if backend in ("compiled", "auto"):
        from parakin.compiled import CompiledBackend

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
