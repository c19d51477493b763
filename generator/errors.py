"""The generator's one error: what could not be generated, in one line naming the mechanism."""

from __future__ import annotations


class GenerationError(RuntimeError):
    """A mechanism file could not be turned into a generated package (the message says why)."""
