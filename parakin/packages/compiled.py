"""The compiled path: generated CasADi C code plus the batched driver, built once with the
system C compiler into a cache outside the repository and called through ctypes.

Cache: ``$PARAKIN_CACHE`` or ``~/.cache/parakin``; one shared library per source hash, built in a
scratch file and renamed, so concurrent builds cannot leave a broken library behind. The
library's file name is the manifest's checked name (an identifier), so it stays in the cache.
A cache that cannot be written (no permission, a file in its place) is a CacheUnavailableError:
backend 'auto' falls back to NumPy and says why.

Loading a library runs its code, so the cache is trusted only when it is private: the folder
(created 0700) and the library owned by this user (or root) and writable by no one else, and no
folder above it writable by anyone without the sticky bit; otherwise UntrustedCacheError. A
library under the cache's name that lacks the package's symbols is a StaleLibraryError. A
scratch file is named ``<library>.<host>.<pid>.<random>.partial``: a compile killed before its
rename leaves one, which the next compile removes once that process is gone (or after a day).
"""

from __future__ import annotations

import contextlib
import ctypes
import dataclasses
import functools
import hashlib
import math
import os
import platform
import re
import shutil
import socket
import stat
import subprocess
import tempfile
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from parakin.errors import (
    BadInputError,
    CacheUnavailableError,
    CompilerUnavailableError,
    ParakinError,
    StaleLibraryError,
    UntrustedCacheError,
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
#: added where the CPU has AVX2 (x86-64): the same IEEE operations in wider registers, so the
#: library stays bit-equal to the plain build and to NumPy, with 10-35 % less CPU in the path
#: tracker (bench.floor's packages). Not -march=native: its other extensions change roundings.
WIDE_FLAGS = ["-mavx2"]


#: a scratch file older than this belongs to a dead compile whatever its process id says (ids are reused)
STALE_SCRATCH_AGE = 24 * 3600.0
#: build_library's scratch files: "<library>.<host>.<pid>.<random>.partial" (see host_tag)
_SCRATCH = re.compile(r"\w+-[0-9a-f]{16}\.so\.(?P<host>[A-Za-z0-9-]+)\.(?P<pid>[0-9]{1,10})\.\w+\.partial")
#: tempfile.mkstemp's default names: parakin's scratch files before they named their compile
_OLD_SCRATCH = re.compile(r"tmp[a-z0-9_]{8}\.so")
_OTHERS_WRITE = stat.S_IWGRP | stat.S_IWOTH


def cache_directory() -> Path:
    """The compiled-library cache folder (it may not exist yet).

    Returns
    -------
    Path
        ``$PARAKIN_CACHE``, else ``~/.cache/parakin``.
    """
    return Path(os.environ.get("PARAKIN_CACHE", Path.home() / ".cache" / "parakin"))


def _cache_error(error: OSError, what: str) -> CacheUnavailableError:
    return CacheUnavailableError(
        f"the compiled-library cache {cache_directory()} cannot be used ({what}: {type(error).__name__}: "
        f"{error}); set PARAKIN_CACHE to a writable folder, or use backend='numpy'"
    )


def _user(uid: int) -> str:
    try:
        import pwd

        return f"{pwd.getpwuid(uid).pw_name} (uid {uid})"
    except (ImportError, KeyError):
        return f"uid {uid}"


def distrust(path: Path) -> str | None:
    """Why a folder or file of the cache cannot be trusted, or None when it can.

    Trusted: owned by this user (or root), writable by no one else, and below no folder that
    anyone may write to without the sticky bit (where anyone could rename it and put their own in
    its place). Anything else could hold a file another local user wrote.

    Parameters
    ----------
    path : Path
        A cache folder or file; symbolic links are followed.

    Returns
    -------
    str or None
        What is wrong, as a clause that starts with the path and says what fixes it; None when
        the path is trusted, or on a system without POSIX owners (Windows).
    """
    if not hasattr(os, "geteuid"):
        return None
    try:
        info = os.stat(path)
    except OSError as error:
        return f"{path} cannot be examined ({type(error).__name__}: {error})"
    me = os.geteuid()
    if info.st_uid not in (me, 0):
        return f"{path} belongs to {_user(info.st_uid)}, not to you, {_user(me)}"
    if info.st_mode & _OTHERS_WRITE:
        who = {stat.S_IWGRP: "its group", stat.S_IWOTH: "others"}.get(
            info.st_mode & _OTHERS_WRITE, "its group and others"
        )
        return (
            f"{path} is writable by {who} (mode {stat.S_IMODE(info.st_mode):04o}; `chmod go-w {path}` makes it private)"
        )
    absolute = Path(os.path.abspath(path))
    for folder in dict.fromkeys([*absolute.parents, *absolute.resolve().parents]):
        try:
            mode = os.stat(folder).st_mode
        except OSError:
            continue
        if mode & stat.S_IWOTH and not mode & stat.S_ISVTX:
            return (
                f"{path} lies in {folder}, which anyone may write to and rename in (mode "
                f"{stat.S_IMODE(mode):04o}, no sticky bit; `chmod o-w {folder}` or `chmod +t {folder}`)"
            )
    return None


def _untrusted(cache: Path, reason: str) -> UntrustedCacheError:
    return UntrustedCacheError(
        f"the compiled-library cache {cache} is not private: {reason}. A library another user put there "
        "would run inside this process, so none is loaded from it: make it private, or set PARAKIN_CACHE "
        "to a folder only you can write, or use backend='numpy'"
    )


def host_tag() -> str:
    """This machine and process-id namespace, as a part of a file name.

    A scratch file names the compile that writes it with this tag and its process id: whether
    that process is alive can only be asked where the id means the same process (a cache shared
    over the network, or by containers with their own process ids, sees other ids).

    Returns
    -------
    str
        The host name (letters, digits and '-'), '-', and the inode of ``/proc/self/ns/pid``
        (0 where there is none).
    """
    host = re.sub(r"[^A-Za-z0-9-]", "-", socket.gethostname())[:63] or "host"
    try:
        namespace = os.stat("/proc/self/ns/pid").st_ino
    except OSError:
        namespace = 0
    return f"{host}-{namespace}"


def _alive(pid: int) -> bool:
    if pid == os.getpid() or os.name != "posix":  # elsewhere os.kill(pid, 0) would end the process
        return True
    if not 0 < pid < 2**31:  # no process has that id (0 and -1 would signal whole groups)
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process: alive
        return True
    return True


def remove_dead_scratch(cache: Path) -> list[Path]:
    """Remove the scratch libraries that killed compiles left in the cache.

    Only regular files named as ``build_library`` names them: one of this host whose process is
    gone, and any one (also the older ``tmpXXXXXXXX.so`` names) older than STALE_SCRATCH_AGE.
    A compile in progress elsewhere keeps its file.

    Parameters
    ----------
    cache : Path
        The cache folder (already checked to be private).

    Returns
    -------
    list of Path
        The files removed.
    """
    here, now = host_tag(), time.time()
    removed: list[Path] = []
    try:
        entries = list(os.scandir(cache))
    except OSError:
        return removed
    for entry in entries:
        match = _SCRATCH.fullmatch(entry.name)
        if match is None and _OLD_SCRATCH.fullmatch(entry.name) is None:
            continue
        try:
            info = entry.stat(follow_symlinks=False)
        except OSError:
            continue
        if not stat.S_ISREG(info.st_mode):
            continue
        dead = match is not None and match["host"] == here and not _alive(int(match["pid"]))
        if dead or now - info.st_mtime > STALE_SCRATCH_AGE:
            try:
                os.unlink(entry.path)
            except OSError:  # removed by another compile meanwhile, or not ours to remove
                continue
            removed.append(Path(entry.path))
    if removed:
        logger.debug("removed %d scratch files of killed compiles from %s", len(removed), cache)
    return removed


@functools.cache
def _has_avx2() -> bool:
    if platform.machine().lower() not in {"x86_64", "amd64"}:
        return False
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:  # not Linux: the plain flags
        return False
    # the kernel lists avx2 only where it also saves the wide registers
    return any(line.startswith("flags") and "avx2" in line.split() for line in text.splitlines())


def compile_flags() -> list[str]:
    """The C compiler's flags for a package's library on this machine.

    Returns
    -------
    list of str
        FLAGS, and WIDE_FLAGS where the CPU has AVX2 (Linux on x86-64): both builds give the same
        bits.
    """
    return [*FLAGS, *WIDE_FLAGS] if _has_avx2() else list(FLAGS)


def library_target(package: GeneratedPackage) -> tuple[str, list[str], Path]:
    """Where a package's library is cached: its C sources, the compiler and its flags name it.

    Parameters
    ----------
    package : GeneratedPackage
        The package.

    Returns
    -------
    compiler : str
        The C compiler (``$CC``, else ``cc``) as found on the path.
    flags : list of str
        ``compile_flags()``.
    target : Path
        The library's path in ``cache_directory()`` (it may not exist yet).

    Raises
    ------
    CompilerUnavailableError
        No C compiler.
    BadInputError
        A C file of the package cannot be read.
    """
    compiler = shutil.which(os.environ.get("CC", "cc"))
    if compiler is None:
        raise CompilerUnavailableError("no C compiler found (looked for $CC or 'cc')")
    flags = compile_flags()
    digest = hashlib.sha256()
    for path in [*package.c_sources(), *package.c_headers()]:
        try:
            digest.update(path.read_bytes())
        except OSError as error:
            raise BadInputError(f"package {package.path}: cannot read its C file {path.name} ({error})") from error
    digest.update(" ".join([compiler, *flags]).encode())
    return compiler, flags, cache_directory() / f"{package.manifest.name}-{digest.hexdigest()[:16]}.so"


def build_library(package: GeneratedPackage) -> Path:
    """Compile (or find in the cache) the shared library of a generated package.

    Parameters
    ----------
    package : GeneratedPackage
        The package whose C sources are built.

    Returns
    -------
    Path
        The library, in a cache folder checked to be private (``distrust``).

    Raises
    ------
    CompilerUnavailableError
        No C compiler, or the compilation failed.
    CacheUnavailableError
        The cache cannot be created or written; UntrustedCacheError where it, or the library,
        is not private.
    """
    compiler, flags, target = library_target(package)
    cache = cache_directory()
    if target.resolve().parent != cache.resolve():  # the manifest check makes this unreachable
        raise CacheUnavailableError(f"the library path {target} leads outside the cache {cache}")
    try:
        if target.is_file():
            reason = distrust(cache) or distrust(target)
            if reason is not None:
                raise _untrusted(cache, reason)
            return target
        # private from the start, whatever the umask (parents as `mkdir -p` makes them)
        cache.mkdir(parents=True, exist_ok=True, mode=0o700)
    except OSError as error:
        raise _cache_error(error, "creating the library") from error
    reason = distrust(cache)
    if reason is not None:  # a library compiled here could be swapped before it is loaded
        raise _untrusted(cache, reason)
    remove_dead_scratch(cache)
    try:
        prefix = f"{target.name}.{host_tag()}.{os.getpid()}."
        handle, scratch = tempfile.mkstemp(prefix=prefix, suffix=".partial", dir=cache)
    except OSError as error:
        raise _cache_error(error, "creating the library") from error
    os.close(handle)
    sources = map(str, package.c_sources())
    command = [compiler, *flags, "-I", str(package.path), *sources, "-o", scratch, "-lm"]
    logger.info("compiling the C library of %s (first use; cached in %s)", package.manifest.name, cache)
    start = time.perf_counter()
    try:
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode != 0:
            raise CompilerUnavailableError(f"C compilation failed: {' '.join(command)}\n{result.stderr[-2000:]}")
        # the linker gives its output the umask's mode: nobody else may write the library
        os.chmod(scratch, stat.S_IMODE(os.stat(scratch).st_mode) & ~_OTHERS_WRITE)
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


#: NAME_step_job of the C header (c_header.h.j2): a tracker's buffers for NAME_forward_pose_step
STEP_JOB = (
    ("actuated", "pointer"),
    ("incoming", "pointer"),
    ("previous_actuated", "pointer"),
    ("previous", "pointer"),
    ("previous_pose", "pointer"),
    ("previous_orientation", "pointer"),
    ("mode_change", "pointer"),
    ("low", "pointer"),
    ("high", "pointer"),
    ("jump_ratio", "double"),
    ("trust_step", "double"),
)


#: NAME_certify_job of the C header (c_header.h.j2; generator/runtime/krawczyk.h's kw_job): Krawczyk's
#: certificate of candidate roots of a sparse polynomial system (NAME_certify_roots)
CERTIFY_JOB = (
    ("systems", "int64"),
    ("candidates", "int64"),
    ("terms", "int64"),
    ("unknowns", "int64"),
    ("coefficients", "pointer"),
    ("exponents", "pointer"),
    ("equation", "pointer"),
    ("roots", "pointer"),
    ("real_coefficients", "int64"),
    ("homogeneous", "pointer"),
    ("homogeneous_count", "int64"),
    ("patch_equation", "int64"),
    ("unique", "pointer"),
    ("real", "pointer"),
    ("radius", "pointer"),
    ("center", "pointer"),
    ("radii", "pointer"),
    ("workspace", "pointer"),
    ("workspace_bytes", "int64"),
)


def job_structure(name: str, fields: tuple[tuple[str, str], ...]) -> type[ctypes.Structure]:
    """A ctypes structure with the manifest's field list (pointers as void*): the C header is
    printed from the same list, so the two layouts cannot drift apart."""
    return type(name, (ctypes.Structure,), {"_fields_": [(n, _CTYPES.get(t, _POINTER)) for n, t in fields]})


def _plain_batch(inputs: tuple[Array, ...]) -> tuple[tuple[int, ...], list[np.ndarray]] | None:
    """``broadcast_batch`` for the common case, without its general broadcasting: every input a
    C-contiguous float64 array (size,) or (n, size), the batched ones sharing n (n > 0). The
    same shape and rows as ``broadcast_batch`` gives them; None for anything else."""
    rows = 0
    flat = []
    for x in inputs:
        if type(x) is not np.ndarray or x.dtype != np.float64 or not x.flags.c_contiguous:
            return None
        if x.ndim == 1:
            flat.append(x.reshape(1, x.shape[0]))
        elif x.ndim == 2 and x.shape[0] > 0 and rows in (0, x.shape[0]):
            rows = x.shape[0]
            flat.append(x)
        else:
            return None
    return ((rows,) if rows else ()), flat


@dataclasses.dataclass
class TrackCounts:
    """What the C path tracker did, summed over calls (``CompiledBackend.counting``): paths
    tracked (a sign symmetry's partner paths are not tracked), step attempts, rejected steps,
    homotopy evaluations (value and Jacobian) and LU factorisations."""

    paths: int = 0
    steps: int = 0
    rejected: int = 0
    evaluations: int = 0
    factorisations: int = 0

    def add(self, values: list[int]) -> None:
        """Add one call's five counts, in the order of the fields."""
        self.paths += values[0]
        self.steps += values[1]
        self.rejected += values[2]
        self.evaluations += values[3]
        self.factorisations += values[4]


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
        # a library under the cache's name built from other sources (or not by parakin at all)
        # would fail at its first call, or call the wrong code: every symbol is looked up now
        needed = [self.manifest.newton.symbol, *([abi.modes_symbol] if abi.modes_symbol else [])]
        needed += [description.c_symbol for description in self.manifest.kernels.values()]
        missing = [symbol for symbol in dict.fromkeys(needed) if not hasattr(self.library, symbol)]
        if missing:
            shown = ", ".join(missing[:3]) + (", ..." if len(missing) > 3 else "")
            raise StaleLibraryError(
                f"{self.path} lacks {len(missing)} of the {len(set(needed))} C symbols {self.manifest.name} needs "
                f"({shown}): it is stale, damaged or not built by parakin; delete it (rm {self.path}) and a new "
                "Python process rebuilds it at its first load (this one keeps the library it loaded), or use "
                "backend='numpy'"
            )
        self.functions = {kernel: getattr(self.library, d.c_symbol) for kernel, d in self.manifest.kernels.items()}
        #: per kernel: (name, shape) of each output (read once: every call allocates them)
        self._outputs = {
            kernel: tuple((output.name, tuple(output.shape)) for output in d.outputs)
            for kernel, d in self.manifest.kernels.items()
        }
        #: per thread: each kernel's foreign-call arrays (``_KernelCall``), made at its first call
        self._local = threading.local()
        #: id -> (array, data address) of read-only inputs (``_address``)
        self._addresses: dict[int, tuple[np.ndarray, int]] = {}
        self.NewtonJob = job_structure("NewtonJob", abi.newton_job)
        self.newton = getattr(self.library, self.manifest.newton.symbol)
        self.newton.restype = ctypes.c_int
        self.newton.argtypes = [_POINTER]
        # a tracker's step with its checks in C (ForwardPoseTracker.solve); a library of an older
        # generator lacks it, and the tracker then checks in Python
        self.newton_step: Any = getattr(self.library, f"{self.manifest.newton.symbol}_step", None)
        if self.newton_step is not None:
            self.newton_step.restype = ctypes.c_longlong
            self.newton_step.argtypes = [_POINTER, _POINTER]
        self.StepJob = job_structure("StepJob", STEP_JOB)
        self.ModesJob = job_structure("ModesJob", abi.modes_job)
        self.forward_pose_all = None
        # Krawczyk's certificate in C (certify_roots_compiled); a library of an older generator, or
        # of a closed-form package, lacks it
        self.certify: Any = getattr(self.library, f"{self.manifest.name}_certify_roots", None)
        self.certify_workspace: Any = getattr(self.library, f"{self.manifest.name}_certify_workspace", None)
        self.CertifyJob = job_structure("CertifyJob", CERTIFY_JOB)
        if self.certify is not None and self.certify_workspace is not None:
            self.certify.restype = ctypes.c_int
            self.certify.argtypes = [_POINTER]
            self.certify_workspace.restype = ctypes.c_longlong
            self.certify_workspace.argtypes = [_INT64, _INT64, _INT64, _INT64]
        # the clusters of overlapping certified boxes (certify.cluster_labels) in C; a library of an
        # older generator lacks it (the NumPy function serves then)
        self.certify_clusters: Any = getattr(self.library, f"{self.manifest.name}_certify_clusters", None)
        if self.certify_clusters is not None:
            self.certify_clusters.restype = None
            self.certify_clusters.argtypes = [_INT64, _INT64, _INT64, *[_POINTER] * 5]
        # the certificate's target system at the inputs in one call (modes._certificate_system); a
        # library of an older generator, or of a closed-form package, lacks it
        self.target_coefficients: Any = getattr(self.library, f"{self.manifest.name}_target_coefficients", None)
        if self.target_coefficients is not None:
            self.target_coefficients.restype = None
            self.target_coefficients.argtypes = [_INT64, _POINTER, _INT64, _POINTER, _POINTER]
        # forward_pose_all that also sums what path tracking cost (``counting``); a library of an
        # older generator lacks it
        self._counted: Any = None
        if abi.modes_symbol is not None:
            self.forward_pose_all = getattr(self.library, abi.modes_symbol)
            self.forward_pose_all.restype = ctypes.c_int
            self.forward_pose_all.argtypes = [_POINTER]
            self._counted = getattr(self.library, f"{abi.modes_symbol}_counted", None)
            if self._counted is not None:
                self._counted.restype = ctypes.c_int
                self._counted.argtypes = [_POINTER, _POINTER]

    @contextlib.contextmanager
    def counting(self) -> Iterator[TrackCounts]:
        """Count what the C path tracker does while the block runs (every ``forward_pose_all``
        through this backend, from this thread or others; not thread-safe: for measurements).

        Yields
        ------
        TrackCounts
            Summed over the calls made in the block; filled as they return.

        Raises
        ------
        StaleLibraryError
            The library was built by an older generator, without the counted entry point.

        Example
        -------
        >>> m = parakin.load("stewart", backend="compiled")  # doctest: +SKIP
        >>> with m.backend.counting() as counts:  # doctest: +SKIP
        ...     m.forward_pose_all(m.home_actuated)
        >>> counts.steps / counts.paths  # doctest: +SKIP
        """
        if self._counted is None or self.forward_pose_all is None:
            raise StaleLibraryError(f"{self.path} has no counted forward_pose_all: regenerate its package")
        counts = TrackCounts()
        original, counted = self.forward_pose_all, self._counted
        buffer = (_INT64 * 5)()

        def call(pointer: Any) -> int:
            status = int(counted(pointer, buffer))
            counts.add(list(buffer))
            return status

        self.forward_pose_all = call
        try:
            yield counts
        finally:
            self.forward_pose_all = original

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
        """One kernel over a batch: each input (n_i,) or (..., n_i), broadcast over the leading
        axes; each output (..., *shape) in fresh arrays.

        The solvers' usual call (every input a C-contiguous float64 array (n_i,) or (n, n_i), the
        batched ones sharing n) takes the short way: the thread's pointer arrays of the kernel
        (``_KernelCall``) are filled in place, with no reshaped views; anything else is broadcast
        first (``broadcast_batch``). Both give the same outputs."""
        try:
            prepared: _KernelCall = self._local.calls[kernel]
        except AttributeError:
            self._local.calls = {}
            prepared = self._prepare(kernel)
        except KeyError:
            prepared = self._prepare(kernel)
        if len(inputs) == prepared.size:
            rows = 0
            input_pointers, strides = prepared.inputs, prepared.strides
            for k, x in enumerate(inputs):
                if (
                    type(x) is not np.ndarray
                    or (x.dtype is not _FLOAT64 and x.dtype != _FLOAT64)
                    or not x.flags.c_contiguous
                ):
                    break
                if x.ndim == 2 and x.shape[0] > 0 and rows in (0, x.shape[0]):
                    rows = x.shape[0]
                    strides[k] = x.shape[1]
                elif x.ndim == 1:
                    strides[k] = 0
                else:
                    break
                input_pointers[k] = self._address(x)
            else:
                count = rows or 1
                if count == 1:  # one row: every input shared (the C reads row 0)
                    for k in range(prepared.size):
                        strides[k] = 0
                outputs = []
                output_pointers = prepared.outputs
                for k, size in enumerate(prepared.shapes):
                    value = np.empty((count, *size))
                    output_pointers[k] = _writable_address(value)
                    outputs.append(value)
                if prepared.function(_INT64(count), input_pointers, strides, output_pointers) != 0:
                    raise ParakinError(f"compiled kernel {kernel} failed")
                if rows:
                    return dict(zip(prepared.names, outputs, strict=True))
                return {
                    name: value.reshape(value.shape[1:]) for name, value in zip(prepared.names, outputs, strict=True)
                }
        return self._call_broadcast(kernel, inputs)

    def _prepare(self, kernel: str) -> _KernelCall:
        """This thread's foreign-call arrays of ``kernel`` (made at its first call in the thread)."""
        description = self.manifest.kernels[kernel]
        size = len(description.inputs)
        prepared = _KernelCall(
            function=self.functions[kernel],
            size=size,
            names=tuple(name for name, _ in self._outputs[kernel]),
            shapes=tuple(shape for _, shape in self._outputs[kernel]),
            inputs=(_POINTER * size)(),
            strides=(_INT64 * size)(),
            outputs=(_POINTER * len(self._outputs[kernel]))(),
        )
        self._local.calls[kernel] = prepared
        return prepared

    def _address(self, x: np.ndarray) -> int:
        """The data address of a C-contiguous float array: through the buffer protocol for a
        writable one (a third of ``x.ctypes.data``'s cost); a read-only one's (the parameters,
        the same array at every call) is remembered with the array itself, so that its id names
        it while remembered."""
        known = self._addresses.get(id(x))
        if known is not None and known[0] is x:
            return known[1]
        try:
            return ctypes.addressof(ctypes.c_char.from_buffer(x))  # type: ignore[arg-type]  # a NumPy array is a buffer
        except (TypeError, ValueError):  # read-only, or empty (no byte to point at)
            pass
        address = int(x.ctypes.data)
        if x.size and x.size <= _REMEMBERED_SIZE:
            if len(self._addresses) >= _REMEMBERED_ARRAYS:
                self._addresses.clear()
            self._addresses[id(x)] = (x, address)
        return address

    def _call_broadcast(self, kernel: str, inputs: tuple[Array, ...]) -> dict[str, Array]:
        """``call`` for inputs that are not plain: broadcast, made contiguous float64, then called."""
        plain = _plain_batch(inputs)
        shape, flat = plain if plain is not None else broadcast_batch(inputs)
        count = math.prod(shape)
        outputs = {name: np.empty((count, *size)) for name, size in self._outputs[kernel]}
        input_pointers = (_POINTER * len(flat))(*(x.ctypes.data for x in flat))
        strides = (_INT64 * len(flat))(*(x.shape[1] if x.shape[0] == count and count > 1 else 0 for x in flat))
        output_pointers = (_POINTER * len(outputs))(*(o.ctypes.data for o in outputs.values()))
        function = self.functions[kernel]
        if function(_INT64(count), input_pointers, strides, output_pointers) != 0:
            raise ParakinError(f"compiled kernel {kernel} failed")
        return {name: value.reshape(shape + value.shape[1:]) for name, value in outputs.items()}


#: float64, the one dtype a plain kernel input has (NumPy keeps one instance of each builtin dtype:
#: compared by identity first)
_FLOAT64 = np.dtype(np.float64)
#: read-only arrays whose address ``CompiledBackend._address`` remembers: at most this many
#: elements each (parameter vectors), at most this many arrays (then it starts again)
_REMEMBERED_SIZE = 4096
_REMEMBERED_ARRAYS = 64


def _writable_address(x: np.ndarray) -> int:
    """The data address of a fresh (writable, C-contiguous) array; ``x.ctypes.data`` for an empty one."""
    try:
        return ctypes.addressof(ctypes.c_char.from_buffer(x))  # type: ignore[arg-type]  # a NumPy array is a buffer
    except ValueError:  # no byte to point at
        return int(x.ctypes.data)


@dataclasses.dataclass(frozen=True)
class _KernelCall:
    """One kernel's foreign call as one thread makes it: the function, its output names and
    shapes, and the pointer and stride arrays that each call fills in place (one set per
    thread: a batch's threads call kernels side by side)."""

    function: Any
    size: int
    names: tuple[str, ...]
    shapes: tuple[tuple[int, ...], ...]
    inputs: Any
    strides: Any
    outputs: Any
