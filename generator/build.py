"""``make generate``: rebuild ``generated/`` from ``mechanisms/``, deterministically and atomically.

Every mechanism is one file; its name is the file's stem (a Python identifier, underscores
welcome) and its generated package is the folder ``generated/<name>/``. Mechanisms are found by
listing ``mechanisms/`` (no registry) and built in parallel processes. Everything is written to
a staging directory next to the destination and swapped in only when every mechanism succeeded,
so a failure (or an interrupt) leaves the previous tree intact. The swap is one atomic exchange
of the two directories where the system has one (Linux ``renameat2``), else two renames whose
half-done state (destination missing, the previous tree retired next to it) the next run
restores before anything else; a kill at any instant therefore leaves the previous or the new
complete tree. Nothing the generator did not write is deleted, moved or overwritten: a
destination that holds other files is refused (``generate_file`` can write next to them with
``force``).
"""

from __future__ import annotations

import ast
import ctypes
import errno
import functools
import hashlib
import importlib.metadata
import importlib.util
import json
import logging
import logging.handlers
import multiprocessing
import multiprocessing.queues
import os
import queue
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from types import ModuleType, TracebackType
from typing import Any

import casadi

from parakin.log import logger

from . import emit, stages
from .checks import check_inverse, check_variables
from .derive import derive
from .errors import GenerationError
from .manifest_writer import build_manifest
from .model import Mechanism
from .program import LoweredProgram

MECHANISMS = Path(__file__).resolve().parent.parent / "mechanisms"
GENERATED = Path(__file__).resolve().parent.parent / "generated"
GENERATED_INIT = '"""Generated code only: written by `make generate`, never edited by hand."""\n'
#: every file of a generated package, in the order written; ``{name}`` is the mechanism's name.
#: Telling a package folder from a user's folder, and what ``force`` may overwrite, go by this list.
PACKAGE_FILES = (
    "manifest.json",
    "numpy_kernels.py",
    "casadi_functions.py",
    "symbolic.py",
    "kernels.c",
    "kernels.h",
    "driver.c",
    "{name}.h",
    "real_roots.h",
    "example_main.c",
    "README_C.md",
)
#: CasADi's generated C keeps every function's full ABI signature (``iw``, ``w``, ``mem``...)
#: whether it uses the argument or not: the unused-parameter warning is silenced around its code
#: (and only there), so that kernels.c compiles under -Wall -Wextra -Werror
C_WARNINGS_OFF = (
    '#if defined(__GNUC__)\n#pragma GCC diagnostic push\n#pragma GCC diagnostic ignored "-Wunused-parameter"\n#endif\n'
)
C_WARNINGS_ON = "#if defined(__GNUC__)\n#pragma GCC diagnostic pop\n#endif\n"
#: test hook (never set in use): ``SECONDS`` to wait at each step of the swap, or ``STEP:SECONDS``
#: to wait at that step only; every step is announced on stderr as ``parakin-test-pause STEP``,
#: so that a test can kill a real build inside the window
PAUSE_SWAP = "PARAKIN_TEST_PAUSE_SWAP"


def discover(directory: Path = MECHANISMS) -> dict[str, Path]:
    """Every mechanism file in ``directory``: name (the file stem) -> path, sorted by name."""
    found = {}
    for path in sorted(directory.glob("*.py")):
        if path.stem.startswith("_"):
            continue
        found[validate_name(path.stem)] = path
    return found


def validate_name(name: str) -> str:
    """Mechanism names are lower-case Python identifiers (they name folders and C symbols)."""
    if not (name.isidentifier() and name == name.lower() and name.isascii()):
        raise GenerationError(f"mechanism name {name!r} must be a lower-case Python identifier")
    return name


class Terminated(SystemExit):
    """The exit a termination signal raises (``parakin generate`` turns SIGTERM into one, so that
    a build unwinds and removes its staging folder): it passes through ``load_definition``,
    which reports a mechanism file's own SystemExit as an error."""


def load_definition(path: Path, name: str | None = None) -> tuple[Mechanism, ModuleType]:
    """Import a mechanism file and call its ``build()``; the mechanism takes the file's name. An
    error in the file is a GenerationError naming the file and the line where it happened: any
    exception, SystemExit included (a file that calls ``sys.exit`` would otherwise end the
    generator with that status and no package). KeyboardInterrupt and ``Terminated`` pass: they
    interrupt.

    The file's own folder is importable while it loads and builds, so that it may import an
    accelerator module beside it (``import _mine_forward``: a hand elimination, ``_``-prefixed so
    that ``discover`` skips it); such sibling modules are forgotten afterwards, so that a file in
    another folder gets its own module of the same name."""
    name = validate_name(name or path.stem)
    spec = importlib.util.spec_from_file_location(f"parakin_mechanism_{name}", path)
    if spec is None or spec.loader is None:
        raise GenerationError(f"{path}: not a Python file")
    module = importlib.util.module_from_spec(spec)
    folder = str(path.resolve().parent)
    loaded = set(sys.modules)
    sys.path.insert(0, folder)
    try:
        spec.loader.exec_module(module)
        if not callable(getattr(module, "build", None)):
            raise GenerationError(f"{path}: a mechanism file defines build() -> parakin.generator.Mechanism")
        mechanism = module.build()
    except GenerationError:
        raise
    except SyntaxError as error:  # the line is the error's own, not a frame's
        where = f", line {error.lineno}" if error.lineno and _same_file(error.filename, path) else ""
        raise GenerationError(f"{path}{where}: SyntaxError: {error.msg}") from error
    except (KeyboardInterrupt, Terminated):
        raise
    except SystemExit as error:
        line = _last_line_in(error.__traceback__, path)
        where = f", line {line}" if line is not None else ""
        raise GenerationError(
            f"{path}{where}: SystemExit: sys.exit({error.code!r}) ran while the file was imported or built; a "
            "mechanism file defines build() and never exits"
        ) from error
    except BaseException as error:  # the file's own error, in one line with where it happened
        line = _last_line_in(error.__traceback__, path)
        where = f", line {line}" if line is not None else ""
        raise GenerationError(f"{path}{where}: {type(error).__name__}: {error}") from error
    finally:
        _forget_siblings(folder, loaded)
    if not isinstance(mechanism, Mechanism):
        raise GenerationError(f"{path}: build() returned {type(mechanism).__name__}, not a Mechanism")
    mechanism.name = name
    return mechanism, module


def _forget_siblings(folder: str, loaded: set[str]) -> None:
    """Take ``folder`` off the import path again and forget the top-level modules imported from it
    since ``loaded`` (a mechanism file's accelerators)."""
    if folder in sys.path:
        sys.path.remove(folder)
    for key in set(sys.modules) - loaded:
        where = getattr(sys.modules[key], "__file__", None)
        if "." not in key and where is not None and str(Path(where).resolve().parent) == folder:
            del sys.modules[key]


def _same_file(filename: str | None, path: Path) -> bool:
    try:
        return filename is not None and Path(filename).resolve() == path.resolve()
    except OSError:
        return False


def _last_line_in(trace: TracebackType | None, path: Path) -> int | None:
    """The line of the innermost frame of ``trace`` that runs the file ``path`` (the user's own
    line, even when the error was raised deeper, inside SymPy or parakin), or None."""
    line = None
    while trace is not None:
        if _same_file(trace.tb_frame.f_code.co_filename, path):
            line = trace.tb_lineno
        trace = trace.tb_next
    return line


def _c_sources(
    name: str, casadi_source: str, programs: list[LoweredProgram]
) -> tuple[str, str, dict[str, dict[str, int]]]:
    """CasADi C code generation of every function, and each function's work sizes."""
    namespace: dict[str, Any] = {}
    exec(compile(casadi_source, "casadi_functions.py", "exec"), namespace)  # noqa: S102
    functions = namespace["build_functions"]()
    with tempfile.TemporaryDirectory() as scratch:
        # CasADi prefixes its exported helpers with this name: per mechanism, so that the C of
        # two mechanisms links into one program; the files are then named kernels.c/.h
        generator = casadi.CodeGenerator(f"{name}_kernels", {"with_header": True})
        for function in functions.values():
            generator.add(function)
        generator.generate(scratch + "/")
        c_text = Path(scratch, f"{name}_kernels.c").read_text()
        h_text = Path(scratch, f"{name}_kernels.h").read_text()
    sizes = {
        p.name: {
            "arg": functions[p.name].sz_arg(),
            "res": functions[p.name].sz_res(),
            "iw": functions[p.name].sz_iw(),
            "w": functions[p.name].sz_w(),
        }
        for p in programs
    }
    return c_text, h_text, sizes


def generate_package(path: Path, package: Path, name: str | None = None) -> dict[str, Any]:
    """Write the generated package of the mechanism file ``path`` into the folder ``package``;
    returns its seconds and each stage's (``generator.stages``, reported as they run)."""
    started = time.perf_counter()
    with stages.reporting(validate_name(name or path.stem)) as times:
        stages.begin("model")
        mechanism, module = load_definition(path, name)
        try:
            stages.begin("checks")
            check_variables(mechanism)
            check_inverse(mechanism)
            _write_package(path, package, mechanism, module)
        except GenerationError:
            raise
        except Exception as error:  # a model the checks did not foresee: one line, not a traceback
            raise GenerationError(f"{mechanism.name}: {type(error).__name__}: {error}") from error
    return {"seconds": time.perf_counter() - started, "stages": times}


def _write_package(path: Path, package: Path, mechanism: Mechanism, module: ModuleType) -> None:
    derivation = derive(mechanism)  # its stages: derivations, polynomial form, homotopy
    stages.begin("lower")
    lowered = [program.lower() for program in derivation.programs]
    stages.begin("emit")
    casadi_source = emit.render_casadi(mechanism.name, lowered)
    c_source, h_source, sizes = _c_sources(mechanism.name, casadi_source, lowered)
    manifest = build_manifest(mechanism, module.__doc__ or "", path.name, derivation, lowered, sizes)
    package.mkdir(parents=True, exist_ok=True)
    header = emit.banner(mechanism.name, "casadi.CodeGenerator", lowered, "//")
    files = {
        "manifest.json": json.dumps(manifest, indent=1, sort_keys=False) + "\n",
        "numpy_kernels.py": emit.render_numpy(mechanism.name, lowered),
        "casadi_functions.py": casadi_source,
        "symbolic.py": emit.render_symbolic(mechanism.name, derivation.symbolic),
        "kernels.c": header + C_WARNINGS_OFF + c_source + C_WARNINGS_ON,
        "kernels.h": header + h_source,
        "driver.c": emit.render_c_driver(mechanism.name, lowered, manifest),
        f"{mechanism.name}.h": emit.render_c_header(mechanism.name, lowered, manifest),
        "real_roots.h": emit.banner(mechanism.name, "real_roots.h", [], "//")
        + (emit.TEMPLATES / "real_roots.h").read_text(),
        **emit.render_c_example(mechanism.name, lowered, manifest),
    }
    if list(files) != package_files(mechanism.name):  # the list that tells packages from user folders
        raise GenerationError(
            f"{mechanism.name}: PACKAGE_FILES {package_files(mechanism.name)} != written {list(files)}"
        )
    for filename, text in files.items():
        (package / filename).write_text(text)


def _format(directory: Path) -> None:
    """Format the generated Python with fixed settings: no configuration file of the user's (or of
    this repository's) can change the output, and no cache is written anywhere."""
    python_files = sorted(str(p) for p in directory.rglob("*.py"))
    command = [sys.executable, "-m", "ruff", "format", "--quiet", "--isolated", "--no-cache"]
    command += ["--line-length", "100", "--target-version", "py311", *python_files]
    subprocess.run(command, check=True, cwd=directory)


def package_files(name: str) -> list[str]:
    """The files a generated package of the mechanism ``name`` consists of (``PACKAGE_FILES``)."""
    return [filename.format(name=name) for filename in PACKAGE_FILES]


#: the tools whose versions shape a package (the generator's exact pins in pyproject.toml; mpmath,
#: pinned only from below, is left out so that a newer release cannot make a clean clone differ)
TOOLS = ("sympy", "casadi", "jinja2", "ruff")


def _mechanism_sources(path: Path) -> list[Path]:
    """The mechanism file and every sibling mechanism module it imports (``from
    parakin.mechanisms.stewart import ...``, an accelerator ``from parakin.mechanisms import
    _sps_forward``, or a module beside a user's file, ``import _mine_forward`` or ``from
    _mine_forward import ...``), transitively, found by reading the imports."""
    found: list[Path] = []
    pending = [path.resolve()]
    while pending:
        current = pending.pop().resolve()
        if current in found or not current.is_file():
            continue
        found.append(current)
        try:
            tree = ast.parse(current.read_bytes())
        except SyntaxError:  # reported by the build itself
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):  # import _mine_forward: a module beside the file
                pending += [current.parent / f"{alias.name}.py" for alias in node.names if "." not in alias.name]
                continue
            if not isinstance(node, ast.ImportFrom) or node.module is None or node.level:
                continue
            parts = node.module.split(".")
            if len(parts) == 1 and (current.parent / f"{parts[0]}.py").is_file():
                pending.append(current.parent / f"{parts[0]}.py")
            # parakin.mechanisms is the shipped folder, wherever the importing file lies (a user's
            # copy of a shipped file imports the shipped accelerator, not one beside the copy)
            if parts[-1] == "mechanisms" and parts[:-1] in ([], ["parakin"]):
                pending += [MECHANISMS / f"{alias.name}.py" for alias in node.names]
            elif len(parts) >= 2 and parts[-2] == "mechanisms" and parts[:-2] in ([], ["parakin"]):
                pending.append(MECHANISMS / f"{parts[-1]}.py")
    return [found[0], *sorted(found[1:])]


@functools.cache
def _generator_digest() -> bytes:
    """The generator's own code, templates and C runtime, the runtime modules it uses (path tracking, the
    shared-subtree form of ``symbolic.py``), and the versions of the tools: what every package is
    generated from besides its mechanism."""
    import parakin.packages.subtrees
    import parakin.solvers.path_tracking

    digest = hashlib.sha256()
    here = Path(__file__).resolve().parent
    runtime_root = Path(parakin.__file__).resolve().parent
    files = sorted(
        [
            *here.glob("*.py"),
            *(p for folder in ("templates", "runtime") for p in (here / folder).iterdir() if p.is_file()),
        ]
    )
    runtime = [
        Path(module.__file__ or "").resolve() for module in (parakin.solvers.path_tracking, parakin.packages.subtrees)
    ]
    for source in [*files, *runtime]:
        label = (
            source.relative_to(here).as_posix()
            if source.is_relative_to(here)
            else f"parakin/{source.relative_to(runtime_root).as_posix()}"
        )
        digest.update(f"{label}\0{source.stat().st_size}\0".encode() + source.read_bytes())
    for tool in TOOLS:
        digest.update(f"{tool}=={importlib.metadata.version(tool)}\0".encode())
    return digest.digest()


def input_digest(name: str, path: Path) -> str:
    """The SHA-256 of everything the package ``name`` is generated from: its name, its mechanism
    file with the mechanism modules that file imports, and the generator (``_generator_digest``)."""
    digest = hashlib.sha256(_generator_digest())
    digest.update(f"name\0{name}\0".encode())
    for source in _mechanism_sources(path):
        digest.update(f"{source.name}\0{source.stat().st_size}\0".encode() + source.read_bytes())
    return digest.hexdigest()


def _file_digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _seal(package: Path, name: str, source: Path) -> None:
    """Record in the manifest what the package was generated from (``input_digest``) and the
    digest of each of its other files, as written and formatted: ``up_to_date`` reads both."""
    path = package / "manifest.json"
    manifest = json.loads(path.read_text())
    manifest["generator"]["inputs"] = input_digest(name, source)
    manifest["generator"]["files"] = {
        filename: _file_digest(package / filename) for filename in package_files(name) if filename != "manifest.json"
    }
    path.write_text(json.dumps(manifest, indent=1, sort_keys=False) + "\n")


def up_to_date(name: str, source: Path, package: Path) -> bool:
    """Whether the package folder holds exactly what generating ``name`` from ``source`` would
    write: it is a generated package of that name, it was generated from the same inputs, and
    every file is as written (a file edited since is caught by its digest)."""
    if package_name(package) != name:
        return False
    try:
        record = json.loads((package / "manifest.json").read_text())["generator"]
        files = record.get("files")
        if record.get("inputs") != input_digest(name, source) or not isinstance(files, dict):
            return False
        wanted = [f for f in package_files(name) if f != "manifest.json"]
        return sorted(files) == sorted(wanted) and all(_file_digest(package / f) == files[f] for f in wanted)
    except (OSError, ValueError, KeyError, TypeError):
        return False


def _only_bytecode(folder: Path) -> bool:
    """A ``__pycache__`` that Python wrote when the package was imported: nothing but .pyc files."""
    return folder.is_dir() and not folder.is_symlink() and all(p.suffix == ".pyc" for p in folder.iterdir())


def package_name(folder: Path) -> str | None:
    """The mechanism name of ``folder`` if it is a generated package and holds nothing else: a
    ``manifest.json`` the generator wrote (schema, name, the ``generator`` record) and only the
    files of that package, plus Python's ``__pycache__``. None for anything else."""
    try:
        manifest = json.loads((folder / "manifest.json").read_text())
        entries = list(folder.iterdir())
    except (OSError, ValueError):
        return None
    if not isinstance(manifest, dict) or not isinstance(manifest.get("schema"), int):
        return None
    name, generator = manifest.get("name"), manifest.get("generator")
    if not (isinstance(name, str) and name.isidentifier() and isinstance(generator, dict) and "source" in generator):
        return None
    allowed = set(package_files(name))
    for entry in entries:
        if entry.name == "__pycache__" and _only_bytecode(entry):
            continue
        if entry.name not in allowed or entry.is_symlink() or not entry.is_file():
            return None
    return name


def _foreign(folder: Path) -> list[str]:
    """The entries of the generated tree ``folder`` (``generated/``) that the generator did not
    write: anything but its ``__init__.py``, ``__pycache__`` and generated packages."""
    foreign = []
    for entry in sorted(folder.iterdir()):
        if entry.name == "__init__.py" and entry.is_file() and entry.read_text() == GENERATED_INIT:
            continue
        if entry.name == "__pycache__" and _only_bytecode(entry):
            continue
        if entry.is_dir() and not entry.is_symlink() and package_name(entry) is not None:
            continue
        foreign.append(entry.name)
    return foreign


def _retired(destination: Path) -> Path:
    """Where the two-rename swap parks the previous tree (a name the generator owns)."""
    return destination.with_name(f".{destination.name}.parakin-old")


def _ours(folder: Path) -> bool:
    """``folder`` is a tree the generator wrote (a package, or a generated tree of packages)."""
    if not folder.is_dir() or folder.is_symlink():
        return False
    return package_name(folder) is not None or ((folder / "__init__.py").is_file() and not _foreign(folder))


def _recover(destination: Path) -> None:
    """Finish a two-rename swap that a kill interrupted, before anything else is decided: the
    previous tree retired next to a missing ``destination`` is put back; one retired next to a
    complete new tree is removed. A retired name that holds anything else is left alone."""
    retired = _retired(destination)
    if not retired.exists() or not _ours(retired):
        return
    if destination.exists() or destination.is_symlink():
        shutil.rmtree(retired)
    else:
        retired.rename(destination)


def _pause(step: str) -> None:
    """The swap's test hook (``PARAKIN_TEST_PAUSE_SWAP``); does nothing unless it is set."""
    value = os.environ.get(PAUSE_SWAP)
    if value:
        print(f"parakin-test-pause {step}", file=sys.stderr, flush=True)
        only, _, seconds = value.rpartition(":")
        if only in ("", step):
            time.sleep(float(seconds))


def _load_renameat2() -> Callable[..., int] | None:
    """libc's ``renameat2`` (Linux, glibc 2.28+), or None where there is none."""
    try:
        function = ctypes.CDLL(None, use_errno=True).renameat2
    except (OSError, AttributeError, TypeError):
        return None
    function.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    function.restype = ctypes.c_int
    return function  # type: ignore[no-any-return]


_renameat2 = _load_renameat2()
_AT_FDCWD = -100
_RENAME_EXCHANGE = 2


def _exchange(first: Path, second: Path) -> bool:
    """Swap two existing directory entries in one atomic step; False where the system or the file
    system cannot (then nothing happened)."""
    if _renameat2 is None:
        return False
    if _renameat2(_AT_FDCWD, os.fsencode(first), _AT_FDCWD, os.fsencode(second), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP, errno.ENOTSUP):
        return False
    raise OSError(code, os.strerror(code), str(first), None, str(second))


def _swap_in(staging: Path, destination: Path) -> None:
    """Replace ``destination`` by the finished ``staging`` folder so that a kill at any instant
    leaves the previous or the new complete tree: one atomic exchange where the system has one
    (the previous tree then sits under the staging name, which ``_remove_abandoned`` clears after
    a kill), else two renames whose half-done state ``_recover`` restores."""
    _pause("staged")
    if not (destination.exists() or destination.is_symlink()):
        staging.rename(destination)
        return
    if _exchange(staging, destination):
        _pause("exchanged")
        shutil.rmtree(staging)
        return
    retired = _retired(destination)
    if retired.exists():  # _recover ran first: anything still there is not ours
        raise GenerationError(f"{retired} is in the way of the swap; move it away and run again")
    destination.rename(retired)
    _pause("retired")
    staging.rename(destination)
    _pause("renamed")
    shutil.rmtree(retired)


def _remove_abandoned(parent: Path) -> None:
    """Staging folders of builds that were killed (SIGKILL leaves no chance to clean up): their
    name carries the builder's process id, so a folder whose process is gone is removed."""
    for folder in parent.glob(".generated-*-*"):
        try:
            pid = int(folder.name.split("-")[1])
        except (IndexError, ValueError):
            continue
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            shutil.rmtree(folder, ignore_errors=True)
        except PermissionError:  # alive, someone else's
            continue


def _build_one(job: tuple[str, str, str]) -> tuple[str, dict[str, Any]]:
    name, source, package = job
    return name, generate_package(Path(source), Path(package), name)


def _worker(events: multiprocessing.queues.Queue[Any]) -> None:
    """A build process: its builds' stage events and ``parakin`` log records go into ``events``,
    for the display of the process that runs ``generate``."""
    events.cancel_join_thread()  # an exit never waits for a queue that nobody reads any more
    stages.send_to(events.put)
    logger.handlers[:] = [logging.handlers.QueueHandler(events)]


def _build_in_processes(
    jobs: list[tuple[str, str, str]], workers: int, display: stages.Display
) -> dict[str, dict[str, Any]]:
    """Every job in a pool of ``workers`` processes, their events shown here as they come; the
    first failure (in the jobs' order) is raised once the running builds end, the others cancelled."""
    events: multiprocessing.queues.Queue[Any] = multiprocessing.Queue()
    with ProcessPoolExecutor(max_workers=workers, initializer=_worker, initargs=(events,)) as pool:
        futures = [pool.submit(_build_one, job) for job in jobs]
        building = {name for name, _, _ in jobs}
        while building:
            try:
                item = events.get(timeout=0.1)
            except queue.Empty:
                if any(f.done() and f.exception() is not None for f in futures):
                    for future in futures:
                        future.cancel()
                    break
                continue
            if isinstance(item, logging.LogRecord):
                logger.handle(item)
                continue
            display(item)
            if not item.stage:
                building.discard(item.mechanism)
        failed = [f.exception() for f in futures if f.done() and not f.cancelled() and f.exception() is not None]
        if failed:
            raise failed[0]  # type: ignore[misc]
        return dict(f.result() for f in futures)


def generate(
    names: list[str] | None = None,
    destination: Path = GENERATED,
    sources: dict[str, Path] | None = None,
    workers: int | None = None,
    force: bool = False,
) -> dict[str, dict[str, Any]]:
    """Regenerate ``destination`` (default ``generated/``) for ``names`` (default: every file in
    ``mechanisms/``; with names given, the other packages are kept). Atomic: all or nothing. A
    destination holding anything but a generated tree is refused before anything is written.

    Without names, only the packages that are not ``up_to_date`` are built (a changed mechanism
    file or generator, a package file edited since); ``force`` builds every one (CI, to check
    that the output is reproducible). Named mechanisms are always built. The report marks the
    packages kept as they were with ``up_to_date``."""
    sources = discover() if sources is None else sources
    everything = names is None
    names = sorted(sources) if names is None else names
    unknown = sorted(set(names) - set(sources))
    if unknown:
        raise GenerationError(f"unknown mechanism(s) {unknown}; found in mechanisms/: {sorted(sources)}")
    _recover(destination)
    if destination.exists() or destination.is_symlink():
        if not destination.is_dir():
            raise GenerationError(f"{destination} is not a folder; pass a new folder to generate into")
        foreign = _foreign(destination)
        if foreign:
            raise GenerationError(
                f"{destination} holds files the generator did not write ({', '.join(foreign[:5])}"
                f"{', ...' if len(foreign) > 5 else ''}); pass an empty or new folder"
            )
    current: dict[str, dict[str, Any]] = {}
    if everything and not force and destination.is_dir():
        current = {n: {"seconds": 0.0, "up_to_date": True} for n in names if up_to_date(n, sources[n], destination / n)}
        stages.say_kept(list(current))
        packages = {p.name for p in destination.iterdir() if p.is_dir() and package_name(p) is not None}
        if len(current) == len(names) and packages == set(names):
            return current  # nothing to write: the tree is not touched
        names = [n for n in names if n not in current]
    destination.parent.mkdir(parents=True, exist_ok=True)
    _remove_abandoned(destination.parent)
    staging = Path(tempfile.mkdtemp(prefix=f".generated-{os.getpid()}-", dir=destination.parent))
    staging.chmod(0o755)
    try:
        (staging / "__init__.py").write_text(GENERATED_INIT)
        jobs = [(name, str(sources[name]), str(staging / name)) for name in names]
        workers = workers or min(len(jobs), os.cpu_count() or 1)
        with stages.shown(names) as display:
            report = _build_in_processes(jobs, workers, display) if workers > 1 else dict(map(_build_one, jobs))
            display.step("formatting")
            _format(staging)
        for name in names:
            _seal(staging / name, name, sources[name])
        partial = set(names) != set(sources)
        if destination.exists() and partial:  # a partial rebuild keeps the other packages
            for path in destination.iterdir():
                if path.is_dir() and path.name in sources and path.name not in names:
                    shutil.copytree(path, staging / path.name, ignore=shutil.ignore_patterns("__pycache__"))
        _swap_in(staging, destination)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return dict(sorted((report | current).items()))


def generate_file(path: Path, package: Path, force: bool = False) -> dict[str, Any]:
    """``parakin generate FILE.py --out DIR``: one user mechanism file into the package folder
    ``DIR``. A new or empty folder, or a generated package (nothing but its files), is replaced
    atomically (written next to it, then swapped in). A non-empty folder that holds anything
    else is refused before anything is written, unless ``force``: then the package's files
    (``package_files``: manifest.json, numpy_kernels.py, casadi_functions.py, symbolic.py,
    kernels.c, kernels.h, driver.c, NAME.h, real_roots.h, example_main.c, README_C.md) are
    written into it, each replaced atomically, overwriting files of those names and nothing else;
    every other file stays. A file in place of ``DIR`` is refused, with or without ``force``."""
    path, package = Path(path).resolve(), Path(package).resolve()
    name = validate_name(path.stem)
    _recover(package)
    into_folder = False  # True: write next to the user's files (force), not swap the folder
    if package.exists() or package.is_symlink():
        if not package.is_dir():
            raise GenerationError(f"--out {package} is a file, not a folder; pass a new folder to generate into")
        if any(package.iterdir()) and package_name(package) is None:
            if not force:
                raise GenerationError(
                    f"--out {package} is a non-empty folder that is not a generated package; pass a new"
                    f" folder, or --force to write the package's files into it (other files are kept)"
                )
            in_the_way = [f for f in package_files(name) if (package / f).is_dir()]
            if in_the_way:
                raise GenerationError(f"--out {package}: {in_the_way} are folders where the package writes files")
            into_folder = True
    try:
        package.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise GenerationError(f"--out {package}: cannot create its parent folder ({error})") from error
    _remove_abandoned(package.parent)
    staging = Path(tempfile.mkdtemp(prefix=f".generated-{os.getpid()}-", dir=package.parent))
    try:
        with stages.shown([name]) as display:
            report = generate_package(path, staging, name)
            display.step("formatting")
            _format(staging)
        _seal(staging, name, path)
        staging.chmod(0o755)
        if into_folder:
            for filename in package_files(name):
                os.replace(staging / filename, package / filename)
            shutil.rmtree(staging)
        else:
            _swap_in(staging, package)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return report
