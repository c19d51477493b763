"""``make generate``: rebuild ``generated/`` from ``mechanisms/``, deterministically and atomically.

Every mechanism is one file; its name is the file's stem (a Python identifier, underscores
welcome) and its generated package is the folder ``generated/<name>/``. Mechanisms are found by
listing ``mechanisms/`` (no registry) and built in parallel processes. Everything is written to
a staging directory next to the destination and swapped in only when every mechanism succeeded,
so a failure (or an interrupt) leaves the previous tree intact.
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from types import ModuleType
from typing import Any

import casadi

from . import emit
from .checks import check_inverse, check_variables
from .derive import derive
from .errors import GenerationError
from .manifest import build_manifest
from .model import Mechanism
from .program import LoweredProgram

MECHANISMS = Path(__file__).resolve().parent.parent / "mechanisms"
GENERATED = Path(__file__).resolve().parent.parent / "generated"
GENERATED_INIT = '"""Generated code only: written by `make generate`, never edited by hand."""\n'


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


def load_definition(path: Path, name: str | None = None) -> tuple[Mechanism, ModuleType]:
    """Import a mechanism file and call its ``build()``; the mechanism takes the file's name."""
    name = validate_name(name or path.stem)
    spec = importlib.util.spec_from_file_location(f"parakin_mechanism_{name}", path)
    if spec is None or spec.loader is None:
        raise GenerationError(f"{path}: not a Python file")
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
        if not callable(getattr(module, "build", None)):
            raise GenerationError(f"{path}: a mechanism file defines build() -> parakin.generator.Mechanism")
        mechanism = module.build()
    except GenerationError:
        raise
    except Exception as error:  # the file's own error, in one line with where it happened
        raise GenerationError(f"{path}: {type(error).__name__}: {error}") from error
    if not isinstance(mechanism, Mechanism):
        raise GenerationError(f"{path}: build() returned {type(mechanism).__name__}, not a Mechanism")
    mechanism.name = name
    return mechanism, module


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
    """Write the generated package of the mechanism file ``path`` into the folder ``package``."""
    started = time.perf_counter()
    mechanism, module = load_definition(path, name)
    try:
        check_variables(mechanism)
        check_inverse(mechanism)
        return _write_package(path, package, mechanism, module, started)
    except GenerationError:
        raise
    except Exception as error:  # a model the checks did not foresee: one line, not a traceback
        raise GenerationError(f"{mechanism.name}: {type(error).__name__}: {error}") from error


def _write_package(
    path: Path, package: Path, mechanism: Mechanism, module: ModuleType, started: float
) -> dict[str, Any]:
    derivation = derive(mechanism)
    lowered = [program.lower() for program in derivation.programs]
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
        "kernels.c": header + c_source,
        "kernels.h": header + h_source,
        "driver.c": emit.render_c_driver(mechanism.name, lowered, manifest),
        f"{mechanism.name}.h": emit.render_c_header(mechanism.name, lowered, manifest),
        "real_roots.h": emit.banner(mechanism.name, "real_roots.h", [], "//")
        + (emit.TEMPLATES / "real_roots.h").read_text(),
        **emit.render_c_example(mechanism.name, lowered, manifest),
    }
    for filename, text in files.items():
        (package / filename).write_text(text)
    return {"seconds": time.perf_counter() - started}


def _format(directory: Path) -> None:
    python_files = sorted(str(p) for p in directory.rglob("*.py"))
    subprocess.run(
        [sys.executable, "-m", "ruff", "format", "--quiet", "--line-length", "100", *python_files], check=True
    )


def _swap_in(staging: Path, destination: Path) -> None:
    """Replace ``destination`` by the finished ``staging`` folder: two renames, no partial state."""
    if destination.exists():
        retired = destination.with_name(f".{destination.name}.old")
        shutil.rmtree(retired, ignore_errors=True)
        destination.rename(retired)
        staging.rename(destination)
        shutil.rmtree(retired)
    else:
        staging.rename(destination)


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


def generate(
    names: list[str] | None = None,
    destination: Path = GENERATED,
    sources: dict[str, Path] | None = None,
    workers: int | None = None,
) -> dict[str, dict[str, Any]]:
    """Regenerate ``destination`` (default ``generated/``) for ``names`` (default: every file in
    ``mechanisms/``; with names given, the other packages are kept). Atomic: all or nothing."""
    sources = discover() if sources is None else sources
    names = sorted(sources) if names is None else names
    unknown = sorted(set(names) - set(sources))
    if unknown:
        raise GenerationError(f"unknown mechanism(s) {unknown}; found in mechanisms/: {sorted(sources)}")
    destination.parent.mkdir(parents=True, exist_ok=True)
    _remove_abandoned(destination.parent)
    staging = Path(tempfile.mkdtemp(prefix=f".generated-{os.getpid()}-", dir=destination.parent))
    staging.chmod(0o755)
    try:
        (staging / "__init__.py").write_text(GENERATED_INIT)
        jobs = [(name, str(sources[name]), str(staging / name)) for name in names]
        workers = workers or min(len(jobs), os.cpu_count() or 1)
        if workers > 1:
            with ProcessPoolExecutor(max_workers=workers) as pool:
                report = dict(pool.map(_build_one, jobs))
        else:
            report = dict(map(_build_one, jobs))
        _format(staging)
        partial = set(names) != set(sources)
        if destination.exists() and partial:  # a partial rebuild keeps the other packages
            for path in destination.iterdir():
                if path.is_dir() and path.name in sources and path.name not in names:
                    shutil.copytree(path, staging / path.name)
        _swap_in(staging, destination)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return dict(sorted(report.items()))


def generate_file(path: Path, package: Path) -> dict[str, Any]:
    """``parakin generate FILE.py --out DIR``: one user mechanism file into the package folder
    ``DIR`` (atomic: written next to it, then renamed)."""
    path, package = Path(path).resolve(), Path(package).resolve()
    name = validate_name(path.stem)
    package.parent.mkdir(parents=True, exist_ok=True)
    _remove_abandoned(package.parent)
    staging = Path(tempfile.mkdtemp(prefix=f".generated-{os.getpid()}-", dir=package.parent))
    try:
        report = generate_package(path, staging, name)
        _format(staging)
        staging.chmod(0o755)
        _swap_in(staging, package)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return report
