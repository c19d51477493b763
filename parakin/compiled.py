"""The compiled path: generated CasADi C code plus the batched driver, built once with the
system C compiler into a cache outside the repository and called through ctypes.

Cache: ``$PARAKIN_CACHE`` or ``~/.cache/parakin``; one shared library per source hash, built in a
temporary file and renamed, so concurrent builds cannot leave a broken library behind.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from parakin.backends import broadcast_batch
from parakin.errors import ParakinError
from parakin.package import GeneratedPackage
from parakin.results import Array

FLAGS = ["-O2", "-shared", "-fPIC", "-std=c99"]


class CompilerUnavailableError(ParakinError):
    """No working C compiler for the compiled backend (set CC, or use backend='numpy')."""


def cache_directory() -> Path:
    return Path(os.environ.get("PARAKIN_CACHE", Path.home() / ".cache" / "parakin"))


def build_library(package: GeneratedPackage) -> Path:
    """Compile (or find in the cache) the shared library of a generated package."""
    sources = package.c_sources()
    header = package.c_header()
    compiler = shutil.which(os.environ.get("CC", "cc"))
    if compiler is None:
        raise CompilerUnavailableError("no C compiler found (looked for $CC or 'cc')")
    digest = hashlib.sha256()
    for path in [*sources, header]:
        digest.update(path.read_bytes())
    digest.update(" ".join([compiler, *FLAGS]).encode())
    target = cache_directory() / f"{package.manifest.name}-{digest.hexdigest()[:16]}.so"
    if target.exists():
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    handle, scratch = tempfile.mkstemp(suffix=".so", dir=target.parent)
    os.close(handle)
    command = [compiler, *FLAGS, "-I", str(header.parent), *map(str, sources), "-o", scratch, "-lm"]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        os.unlink(scratch)
        raise CompilerUnavailableError(f"C compilation failed: {' '.join(command)}\n{result.stderr[-2000:]}")
    os.replace(scratch, target)
    return target


_POINTER = ctypes.c_void_p
_INT64 = ctypes.c_longlong


class CompiledBackend:
    """Batched kernels and the forward-pose Newton loop in compiled C (no DM conversion)."""

    name = "compiled"

    def __init__(self, package: GeneratedPackage) -> None:
        self.manifest = package.manifest
        self.path = build_library(package)
        self.library = ctypes.CDLL(str(self.path))
        self.kernels = list(self.manifest.kernels)
        self.newton = getattr(self.library, self.manifest.newton.symbol)
        self.newton.restype = ctypes.c_int
        self.newton.argtypes = [
            _INT64, _POINTER, _INT64, _POINTER, _INT64, _POINTER,
            ctypes.c_int, ctypes.c_double, ctypes.c_double, ctypes.c_double,
            _POINTER, _POINTER, _POINTER, _POINTER, _POINTER,
        ]  # fmt: skip

    def external(self, kernel: str) -> Any:
        """The compiled kernel as a ``casadi.Function`` (``casadi.external``)."""
        import casadi

        return casadi.external(kernel, str(self.path))

    def call(self, kernel: str, *inputs: Array) -> dict[str, Array]:
        shape, flat = broadcast_batch(inputs)
        count = int(np.prod(shape, dtype=np.int64))
        description = self.manifest.kernels[kernel]
        outputs = {output.name: np.empty((count, *output.shape)) for output in description.outputs}
        input_pointers = (_POINTER * len(flat))(*(x.ctypes.data for x in flat))
        strides = (_INT64 * len(flat))(*(x.shape[1] if x.shape[0] == count and count > 1 else 0 for x in flat))
        output_pointers = (_POINTER * len(outputs))(*(o.ctypes.data for o in outputs.values()))
        function = getattr(self.library, description.c_symbol)
        if function(_INT64(count), input_pointers, strides, output_pointers) != 0:
            raise ParakinError(f"compiled kernel {kernel} failed")
        return {name: value.reshape(shape + value.shape[1:]) for name, value in outputs.items()}
