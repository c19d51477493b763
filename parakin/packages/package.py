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
import json
import os
import re
import warnings
from functools import cached_property
from pathlib import Path
from types import ModuleType
from typing import Any

from parakin.errors import BadInputError, BrokenPackageWarning, ShadowedPackageWarning, UnknownMechanismError
from parakin.packages.manifest import Manifest

MANIFEST = "manifest.json"
#: the example program and the README of the exported C library (package files, not in the manifest)
EXAMPLE_MAIN = "example_main.c"
README_C = "README_C.md"
#: what ``export_c`` wrote into a folder: each file's mechanism and SHA-256 (JSON)
EXPORT_RECORD = ".parakin-export.json"
RECORD_VERSION = 1
_INCLUDE = re.compile(rb'^(\s*#\s*include\s*")([^"]+)(")', re.MULTILINE)


def search_path() -> list[Path]:
    """Folders searched for packages by name: the shipped ones, then ``$PARAKIN_PATH``."""
    shipped = Path(next(iter(importlib.import_module("parakin.generated").__path__)))
    extra = [Path(p) for p in os.environ.get("PARAKIN_PATH", "").split(os.pathsep) if p]
    return [shipped, *extra]


def _every_folder() -> dict[str, list[Path]]:
    """Every package folder on the search path by name, in search order."""
    found: dict[str, list[Path]] = {}
    for folder in search_path():
        if not folder.is_dir():
            continue
        for manifest in sorted(folder.glob(f"*/{MANIFEST}")):
            found.setdefault(manifest.parent.name, []).append(manifest.parent)
    return found


def discover() -> dict[str, Path]:
    """Every generated package on the search path: name -> folder (first found wins; ``find``
    warns when it loads a name that another folder also holds)."""
    return {name: folders[0] for name, folders in sorted(_every_folder().items())}


def _shadow_message(name: str, folders: list[Path]) -> str | None:
    """The message where more than one folder holds ``name`` (``folders`` in search order)."""
    if len(folders) < 2:
        return None
    hidden = ", ".join(str(f) for f in folders[1:])
    return (
        f"two packages are named {name!r}: {folders[0]} is the one loaded by that name, {hidden} is hidden "
        f"(the search path: the shipped packages, then $PARAKIN_PATH in order); load the other by its folder "
        f"path, e.g. parakin.load({str(folders[1])!r}), or generate it under a name of its own"
    )


def shadowings() -> dict[str, str]:
    """What hides packages: per name that more than one folder of the search path holds, which
    folder loading by that name takes, which it hides and how to load the other (one look at
    the search path).

    Returns
    -------
    dict of str to str
        Package name -> the message; no entry for a name that one folder holds.
    """
    found = ((name, _shadow_message(name, folders)) for name, folders in _every_folder().items())
    return {name: message for name, message in found if message is not None}


def _warn_shadowed(message: str | None) -> None:
    """A ShadowedPackageWarning with ``message``, once per process (a command loads a package
    often)."""
    if message is not None and message not in _WARNED:
        _WARNED.add(message)
        warnings.warn(message, ShadowedPackageWarning, stacklevel=4)


#: the ShadowedPackageWarning messages given in this process
_WARNED: set[str] = set()


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
    BrokenPackageWarning that names it and says why, and a name that two folders hold gets a
    ShadowedPackageWarning."""
    readable, broken = survey()
    for name, reason in broken.items():
        warnings.warn(f"skipped the package {name!r}: {reason}", BrokenPackageWarning, stacklevel=3)
    messages = shadowings()
    for name in readable:
        _warn_shadowed(messages.get(name))
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
        every = _every_folder()  # one look at the search path: the package, and any it hides
        packages = {name: folders[0] for name, folders in every.items()}
        if str(name_or_path) not in packages:
            shown = str(name_or_path) if len(str(name_or_path)) <= 80 else f"{str(name_or_path)[:77]}..."
            close = difflib.get_close_matches(str(name_or_path).lower(), sorted(packages), n=3, cutoff=0.6)
            hint = f"did you mean {' or '.join(map(repr, close))}? " if close else ""
            raise UnknownMechanismError(
                f"unknown mechanism {shown!r}: not a package folder; {hint}available: {sorted(packages)}"
            )
        _warn_shadowed(_shadow_message(str(name_or_path), every[str(name_or_path)]))
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

    def export_names(self) -> dict[str, str]:
        """The package's C files (sources, headers, example program, README) -> their names in an
        export folder (``export_name``)."""
        files = [*self.manifest.c_sources, *self.manifest.c_headers, EXAMPLE_MAIN, README_C]
        return {name: export_name(self.manifest.name, name) for name in dict.fromkeys(files)}

    def export_c(self, folder: str | os.PathLike[str], force: bool = False) -> list[Path]:
        """Write the embeddable C library (sources, headers, example program, README) to ``folder``.

        Every file is named with the mechanism's prefix (``export_name``: ``NAME_driver.c``,
        ``NAME_kernels.h``, ...; the public header ``NAME.h`` as it is), its ``#include`` lines
        naming the same files, so that several mechanisms share one folder and link into one
        program. ``EXPORT_RECORD`` (``.parakin-export.json``) lists what parakin exported there,
        with each file's SHA-256 and mechanism.

        Parameters
        ----------
        folder : str or PathLike
            The folder to write into: created if missing.
        force : bool
            Write into a non-empty folder that is not an export, and over files of the export's
            names that parakin did not write or that changed since. No other file is touched,
            with or without ``force``.

        Returns
        -------
        list of Path
            The files written, the record last.

        Raises
        ------
        BadInputError
            Without ``force``: ``folder`` is not empty and holds no export record, or a file of
            an exported name was not written by an export of this mechanism or changed since
            (a user's own ``NAME_kernels.c``, an edited ``NAME_driver.c``). Always: ``folder`` is
            a file, or a file to write (or the record) is a symbolic link, a folder, or leads
            outside ``folder``; or the record is damaged and ``force`` is not given.
        """
        target = Path(folder)
        if target.exists() and not target.is_dir():
            raise BadInputError(f"export to {target}: it is a file, not a folder; pass a new or empty folder")
        target.mkdir(parents=True, exist_ok=True)
        inside = target.resolve()
        names = self.export_names()
        for name in [*names.values(), EXPORT_RECORD]:
            destination = target / name
            if destination.is_symlink() or destination.resolve().parent != inside or destination.is_dir():
                raise BadInputError(
                    f"export to {target}: {destination} is a symbolic link, a folder or leads outside the folder; "
                    "remove it or export to a new folder"
                )
        record = _read_record(target, force)
        if record is None and not force:
            entries = sorted(target.iterdir())
            if entries:
                shown = ", ".join(f"{e.name} (a symbolic link)" if e.is_symlink() else e.name for e in entries[:5]) + (
                    f" and {len(entries) - 5} more" if len(entries) > 5 else ""
                )
                raise BadInputError(
                    f"export to {target}: a non-empty folder that parakin export did not write (no {EXPORT_RECORD}; "
                    f"it holds {shown}); pass a new or empty folder, or --force (force=True) to write the C files "
                    "into it (other files are kept)"
                )
        record = record or {}
        mechanism = self.manifest.name
        if not force:
            foreign = [
                name
                for name in names.values()
                if (target / name).exists() and not _written_by_export(target / name, record.get(name), mechanism)
            ]
            if foreign:
                raise BadInputError(
                    f"export to {target}: would overwrite {', '.join(foreign)}, not written by parakin export of "
                    f"{mechanism!r} or changed since; move them, export to another folder, or pass --force "
                    "(force=True) to overwrite them"
                )
        written = []
        for source, name in names.items():
            data = (self.path / source).read_bytes()
            if name.endswith((".c", ".h")):
                data = _renamed_includes(data, names)
            _replace(target / name, data)
            record[name] = {"mechanism": mechanism, "sha256": hashlib.sha256(data).hexdigest()}
            written.append(target / name)
        kept = {name: entry for name, entry in sorted(record.items()) if (target / name).is_file()}
        text = json.dumps({"parakin_export": RECORD_VERSION, "files": kept}, indent=1)
        _replace(target / EXPORT_RECORD, (text + "\n").encode())
        return [*written, target / EXPORT_RECORD]

    def c_headers(self) -> list[Path]:
        """Every header the C sources include (CasADi kernels, root isolation, public)."""
        return [self.path / name for name in self.manifest.c_headers]


def export_name(mechanism: str, filename: str) -> str:
    """The name of a package's C file in an export folder.

    Parameters
    ----------
    mechanism : str
        The mechanism's name.
    filename : str
        The file's name in the package (``driver.c``, ``kernels.h``, ``NAME.h``, ...).

    Returns
    -------
    str
        ``<mechanism>_<filename>``; the public header ``<mechanism>.h`` keeps its name.
    """
    return filename if filename == f"{mechanism}.h" else f"{mechanism}_{filename}"


def _renamed_includes(source: bytes, names: dict[str, str]) -> bytes:
    """``#include "X"`` of a package file X as its exported name; every other line as it is."""

    def rename(match: re.Match[bytes]) -> bytes:
        included = match.group(2).decode()
        return match.group(1) + names.get(included, included).encode() + match.group(3)

    return _INCLUDE.sub(rename, source)


def _read_record(folder: Path, force: bool) -> dict[str, dict[str, str]] | None:
    """The export record of ``folder`` (file name -> its mechanism and SHA-256), None when there
    is none. A damaged record is refused (nothing in the folder can be told to be an export's)
    unless ``force``, which then treats the folder as not an export."""
    path = folder / EXPORT_RECORD
    if not path.exists():
        return None
    try:
        data = json.loads(path.read_text())
        files = data["files"]
        if not isinstance(files, dict) or not all(
            isinstance(name, str)
            and isinstance(entry, dict)
            and isinstance(entry.get("mechanism"), str)
            and isinstance(entry.get("sha256"), str)
            for name, entry in files.items()
        ):
            raise TypeError("files is not a table of names, mechanisms and digests")
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError) as error:
        if force:
            return None
        raise BadInputError(
            f"export to {folder}: its {EXPORT_RECORD} is damaged ({type(error).__name__}: {error}); nothing in the "
            "folder can be told to be parakin's: export to a new folder, or pass --force (force=True)"
        ) from error
    return {name: dict(entry) for name, entry in files.items()}


def _written_by_export(path: Path, entry: dict[str, str] | None, mechanism: str) -> bool:
    """Whether ``path`` is what an export of ``mechanism`` wrote there, unchanged since."""
    if entry is None or entry["mechanism"] != mechanism:
        return False
    return hashlib.sha256(path.read_bytes()).hexdigest() == entry["sha256"]


def _replace(path: Path, data: bytes) -> None:
    """Write ``path`` through a new file renamed over it: a symbolic link put in its place since
    it was checked is replaced, not followed, and a reader never sees half a file."""
    scratch = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        scratch.write_bytes(data)
        os.replace(scratch, path)
    finally:
        scratch.unlink(missing_ok=True)


__all__ = [
    "EXPORT_RECORD",
    "BrokenPackageWarning",
    "GeneratedPackage",
    "discover",
    "export_name",
    "readable_names",
    "search_path",
    "survey",
]
