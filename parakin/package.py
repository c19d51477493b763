"""Generated packages: a folder with ``manifest.json`` and the emitted NumPy, CasADi and C code.

The packages shipped with parakin live in ``parakin.generated`` (the repository's
``generated/``); more are found in the folders of ``$PARAKIN_PATH`` (``os.pathsep``-separated),
and any package folder can be loaded by its path. Modules are imported from their files, so a
package needs no installation and two packages never share a module name.
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import os
import shutil
from functools import cached_property
from pathlib import Path
from types import ModuleType
from typing import Any

from parakin.errors import UnknownMechanismError
from parakin.manifest import Manifest

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


class GeneratedPackage:
    """One generated package folder: its manifest and its modules, imported on first use."""

    def __init__(self, path: Path) -> None:
        self.path = Path(path).resolve()
        self.manifest = Manifest.read(self.path / MANIFEST)

    @classmethod
    def find(cls, name_or_path: str | os.PathLike[str]) -> GeneratedPackage:
        """A package by name (on the search path) or by folder path."""
        candidate = Path(name_or_path)
        if (candidate / MANIFEST).is_file():
            return cls(candidate)
        packages = discover()
        if str(name_or_path) not in packages:
            raise UnknownMechanismError(
                f"unknown mechanism {str(name_or_path)!r}: not a package folder; available: {sorted(packages)}"
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
        """Copy the embeddable C library (sources, headers, example program, README) to ``folder``."""
        target = Path(folder)
        target.mkdir(parents=True, exist_ok=True)
        names = [*self.manifest.c_sources, *self.manifest.c_headers, "example_main.c", "README_C.md"]
        written = []
        for name in names:
            destination = target / name
            shutil.copyfile(self.path / name, destination)
            written.append(destination)
        return written

    def c_headers(self) -> list[Path]:
        """Every header the C sources include (CasADi kernels, root isolation, public)."""
        return [self.path / name for name in self.manifest.c_headers]


__all__ = ["GeneratedPackage", "discover", "search_path"]
