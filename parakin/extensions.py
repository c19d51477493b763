"""Runtime extensions: hand-written NumPy modules that add design-level checks to a mechanism.

A module registered here may define ``is_architecturally_singular(m) -> bool`` and
``on_load(m) -> None`` (run by ``parakin.load``, e.g. to warn about an unusable geometry).
One registry instead of name checks scattered through the runtime.
"""

from __future__ import annotations

import importlib
from types import ModuleType

EXTENSIONS: dict[str, str] = {"gough": "parakin.architecture"}


def extension(name: str) -> ModuleType | None:
    """The runtime extension module of mechanism ``name``, if it has one."""
    module = EXTENSIONS.get(name)
    return importlib.import_module(module) if module else None
