"""Generated packages: a folder with ``manifest.json`` and the emitted NumPy, CasADi and C code.

The packages shipped with parakin live in ``parakin.generated`` (the repository's
``generated/``); more are found in the folders of ``$PARAKIN_PATH`` (``os.pathsep``-separated),
and any package folder can be loaded by its path. Modules are imported from their files, so a
package needs no installation and two packages never share a module name.

Loading a package runs its code: its Python modules are imported and its C sources compiled and
loaded by the compiled backend. Load only packages you trust. What the manifest names is checked
when it is read (``parakin.packages.manifest``): names are identifiers and files stay inside the folder.
"""

from __future__ import annotations

import difflib
import hashlib
import importlib
import importlib.util
import os
import shutil
import warnings
from functools import cached_property
from pathlib import Path
from types import ModuleType
from typing import Any

from parakin.errors import BadInputError, BrokenPackageWarning, UnknownMechanismError
from parakin.packages.manifest import Manifest

MANIFEST = "manifest.json"


def search_path() -> list[Path]:
    """Folders searched for packages by name: the shipped ones, then ``$PARAKIN_PATH``."""
    shipped = Path(next(iter(importlib.import_module("parakin.generated").__path__)))
    extra = [Path(p) for p in os.environ.get("PARAKIN_PATH", "").split(os.pathsep) if p]
    return [shipped, *extra]


def discover() -> dict[str, Path]:
    """Every generated package on the search path: name -> folder (first found wins)."""
    found: dict[str, Path] = {}
    for folder in search_path():
        if not folder.is_dir():
            continue
        for manifest in sorted(folder.glob(f"*/{MANIFEST}")):
            found.setdefault(manifest.parent.name, manifest.parent)
    return dict(sorted(found.items()))


def survey() -> tuple[dict[str, Manifest], dict[str, str]]:
    """Every package on the search path, read: name -> manifest for the readable ones, and
    name -> the reason (folder and error) for those whose manifest is broken."""
    readable: dict[str, Manifest] = {}
    broken: dict[str, str] = {}
    for name, folder in discover().items():
        try:
            readable[name] = Manifest.read(folder / MANIFEST)
        except BadInputError as error:
            broken[name] = str(error)
    return readable, broken


def readable_names() -> list[str]:
    """The names of the packages whose manifest reads; each broken one is skipped with a
    BrokenPackageWarning that names it and says why."""
    readable, broken = survey()
    for name, reason in broken.items():
        warnings.warn(f"skipped the package {name!r}: {reason}", BrokenPackageWarning, stacklevel=3)
    return list(readable)


class GeneratedPackage:
    """One generated package folder: its manifest and its modules, imported on first use."""

    def __init__(self, path: Path) -> None:
        self.path = Path(path).resolve()
        self.manifest = Manifest.read(self.path / MANIFEST)

    @classmethod
    def find(cls, name_or_path: str | os.PathLike[str]) -> GeneratedPackage:
        """A package by name (on the search path) or by folder path."""
        if not isinstance(name_or_path, str | os.PathLike):
            raise BadInputError(
                f"a mechanism is a name (parakin.available()) or a package folder path, got "
                f"{type(name_or_path).__name__} {name_or_path!r}"
            )
        try:
            candidate = Path(name_or_path)
            is_package = (candidate / MANIFEST).is_file()
        except (OSError, ValueError):  # a name too long for a path, a NUL byte: not a folder
            is_package = False
        if is_package:
            return cls(candidate)
        packages = discover()
        if str(name_or_path) not in packages:
            shown = str(name_or_path) if len(str(name_or_path)) <= 80 else f"{str(name_or_path)[:77]}..."
            close = difflib.get_close_matches(str(name_or_path).lower(), sorted(packages), n=3, cutoff=0.6)
            hint = f"did you mean {' or '.join(map(repr, close))}? " if close else ""
            raise UnknownMechanismError(
                f"unknown mechanism {shown!r}: not a package folder; {hint}available: {sorted(packages)}"
            )
        return cls(packages[str(name_or_path)])

    def _module(self, filename: str) -> ModuleType:
        path = self.path / filename
        tag = hashlib.sha1(str(path).encode()).hexdigest()[:10]
        spec = importlib.util.spec_from_file_location(f"parakin._generated_{self.manifest.name}_{tag}", path)
        if spec is None or spec.loader is None:
            raise UnknownMechanismError(f"missing generated module {path}")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    @cached_property
    def numpy_kernels(self) -> dict[str, Any]:
        return dict(self._module("numpy_kernels.py").KERNELS)

    @cached_property
    def casadi_builders(self) -> dict[str, Any]:
        return dict(self._module("casadi_functions.py").BUILDERS)

    def symbolic(self) -> dict[str, Any]:
        """The derived SymPy objects (needs SymPy)."""
        return dict(self._module("symbolic.py").load())

    def c_sources(self) -> list[Path]:
        return [self.path / name for name in self.manifest.c_sources]

    def c_header(self) -> Path:
        """The public header ``<name>.h``."""
        return self.path / self.manifest.c_header

    def export_c(self, folder: str | os.PathLike[str]) -> list[Path]:
        """Copy the embeddable C library (sources, headers, example program, README) to ``folder``.

        Writes only inside ``folder``: the file names are the manifest's checked plain names, and
        a destination that is a symbolic link (it could point anywhere) is refused, not followed."""
        target = Path(folder)
        target.mkdir(parents=True, exist_ok=True)
        inside = target.resolve()
        names = [*self.manifest.c_sources, *self.manifest.c_headers, "example_main.c", "README_C.md"]
        for name in names:
            destination = target / name
            if destination.is_symlink() or destination.resolve().parent != inside:
                raise BadInputError(
                    f"export to {target}: {destination} is a symbolic link or leads outside the folder; "
                    "remove it or export to a new folder"
                )
        written = []
        for name in dict.fromkeys(names):
            destination = target / name
            shutil.copyfile(self.path / name, destination)
            written.append(destination)
        return written

    def c_headers(self) -> list[Path]:
        """Every header the C sources include (CasADi kernels, root isolation, public)."""
        return [self.path / name for name in self.manifest.c_headers]


__all__ = ["BrokenPackageWarning", "GeneratedPackage", "discover", "readable_names", "search_path", "survey"]
