"""The ``parakin`` logger: what the runtime does that takes time or changes how it runs
(compiling a generated package's C library on first use, and the like).

It writes ``parakin: message`` lines to stderr at INFO and above, through its own handler (it
does not propagate to the root logger, so a program's own logging configuration does not print
them twice). Quieter: ``PARAKIN_LOG=warning`` in the environment, or
``logging.getLogger("parakin").setLevel(logging.WARNING)``; louder: ``PARAKIN_LOG=debug``.
"""

from __future__ import annotations

import logging
import os

logger = logging.getLogger("parakin")


def _configure() -> None:
    if logger.handlers:  # configured already (a reload, or by the user before import)
        return
    handler = logging.StreamHandler()
    handler.setFormatter(logging.Formatter("parakin: %(message)s"))
    logger.addHandler(handler)
    logger.propagate = False
    level = os.environ.get("PARAKIN_LOG", "info").upper()
    logger.setLevel(level if level in logging.getLevelNamesMapping() else logging.INFO)


_configure()

__all__ = ["logger"]
