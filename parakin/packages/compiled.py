"""The compiled path: generated CasADi C code plus the batched driver, built once with the
system C compiler into a cache outside the repository and called through ctypes.

Cache: ``$PARAKIN_CACHE`` or ``~/.cache/parakin``; one shared library per source hash, built in a
temporary file and renamed, so concurrent builds cannot leave a broken library behind. The
library's file name is the manifest's checked name (an identifier), so it stays in the cache.
A cache that cannot be written (no permission, a file in its place) is a CacheUnavailableError:
backend 'auto' falls back to NumPy and says why.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from parakin.errors import (
    BadInputError,
    CacheUnavailableError,
    CompilerUnavailableError,
    ParakinError,
)
from parakin.log import logger
from parakin.packages.package import GeneratedPackage
from parakin.results import Array
from parakin.validation import broadcast_batch

FLAGS = [
    "-O3",
    "-shared",
    "-fPIC",
    "-std=c99",
    "-ffp-contract=off",
    "-fno-semantic-interposition",
    "-fno-math-errno",
]  # no FMA: bit-equal to NumPy


def cache_directory() -> Path:
    return Path(os.environ.get("PARAKIN_CACHE", Path.home() / ".cache" / "parakin"))


def _cache_error(error: OSError, what: str) -> CacheUnavailableError:
    return CacheUnavailableError(
        f"the compiled-library cache {cache_directory()} cannot be used ({what}: {type(error).__name__}: "
        f"{error}); set PARAKIN_CACHE to a writable folder, or use backend='numpy'"
    )


def build_library(package: GeneratedPackage) -> Path:
    """Compile (or find in the cache) the shared library of a generated package."""
    sources = package.c_sources()
    headers = package.c_headers()
    compiler = shutil.which(os.environ.get("CC", "cc"))
    if compiler is None:
        raise CompilerUnavailableError("no C compiler found (looked for $CC or 'cc')")
    digest = hashlib.sha256()
    for path in [*sources, *headers]:
        try:
            digest.update(path.read_bytes())
        except OSError as error:
            raise BadInputError(f"package {package.path}: cannot read its C file {path.name} ({error})") from error
    digest.update(" ".join([compiler, *FLAGS]).encode())
    cache = cache_directory()
    target = cache / f"{package.manifest.name}-{digest.hexdigest()[:16]}.so"
    if target.resolve().parent != cache.resolve():  # the manifest check makes this unreachable
        raise CacheUnavailableError(f"the library path {target} leads outside the cache {cache}")
    try:
        if target.is_file():
            return target
        cache.mkdir(parents=True, exist_ok=True)
        handle, scratch = tempfile.mkstemp(suffix=".so", dir=cache)
    except OSError as error:
        raise _cache_error(error, "creating the library") from error
    os.close(handle)
    command = [compiler, *FLAGS, "-I", str(package.path), *map(str, sources), "-o", scratch, "-lm"]
    logger.info("compiling the C library of %s (first use; cached in %s)", package.manifest.name, cache)
    start = time.perf_counter()
    try:
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode != 0:
            raise CompilerUnavailableError(f"C compilation failed: {' '.join(command)}\n{result.stderr[-2000:]}")
        os.replace(scratch, target)
        logger.info("compiled %s in %.1f s", package.manifest.name, time.perf_counter() - start)
    except OSError as error:
        raise _cache_error(error, "storing the library") from error
    finally:
        if os.path.exists(scratch):
            os.unlink(scratch)
    return target


_POINTER = ctypes.c_void_p
_INT64 = ctypes.c_longlong
_CTYPES = {"int64": ctypes.c_longlong, "double": ctypes.c_double}


def job_structure(name: str, fields: tuple[tuple[str, str], ...]) -> type[ctypes.Structure]:
    """A ctypes structure with the manifest's field list (pointers as void*): the C header is
    printed from the same list, so the two layouts cannot drift apart."""
    return type(name, (ctypes.Structure,), {"_fields_": [(n, _CTYPES.get(t, _POINTER)) for n, t in fields]})


class CompiledBackend:
    """Batched kernels, the forward-pose Newton loop and the all-modes pipeline in compiled C."""

    name = "compiled"

    def __init__(self, package: GeneratedPackage) -> None:
        self.manifest = package.manifest
        self.path = build_library(package)
        try:
            self.library = ctypes.CDLL(str(self.path))
        except OSError as error:  # a damaged library in the cache
            raise _cache_error(error, f"loading {self.path.name}; delete it to rebuild") from error
        self.kernels = list(self.manifest.kernels)
        abi = self.manifest.abi
        self.NewtonJob = job_structure("NewtonJob", abi.newton_job)
        self.newton = getattr(self.library, self.manifest.newton.symbol)
        self.newton.restype = ctypes.c_int
        self.newton.argtypes = [_POINTER]
        self.ModesJob = job_structure("ModesJob", abi.modes_job)
        self.forward_pose_all = None
        if abi.modes_symbol is not None:
            self.forward_pose_all = getattr(self.library, abi.modes_symbol)
            self.forward_pose_all.restype = ctypes.c_int
            self.forward_pose_all.argtypes = [_POINTER]

    def job(self, structure: type[ctypes.Structure], values: dict[str, Any]) -> ctypes.Structure:
        """Fill a job structure: arrays become their data pointers (the caller keeps them alive)."""
        job = structure()
        for field, _ in structure._fields_:  # type: ignore[misc]
            value = values[field]
            setattr(job, field, value.ctypes.data if isinstance(value, np.ndarray) else value)
        return job

    def external(self, kernel: str) -> Any:
        """The compiled kernel as a ``casadi.Function`` (``casadi.external``)."""
        import casadi

        return casadi.external(f"{self.manifest.name}_{kernel}", str(self.path))

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
