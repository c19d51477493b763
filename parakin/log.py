"""What parakin tells its user while it works: the ``parakin`` logger and progress bars.

The logger says what takes time or changes how parakin runs (compiling a generated package's C
library on first use, the generator's stages). It writes ``parakin: message`` lines to stderr at
INFO and above, through its own handler (it does not propagate to the root logger, so a
program's own logging configuration does not print them twice). Quieter: ``PARAKIN_LOG=warning``
in the environment, or ``logging.getLogger("parakin").setLevel(logging.WARNING)``; louder:
``PARAKIN_LOG=debug``.

Progress bars (tqdm, on stderr) show how far a long piece of work is: generating packages
(``make generate``, ``parakin generate``: one bar over every package's stages), and a batch of at
least ``LARGE_BATCH`` inputs (``forward_pose_all``, ``count_modes``) or a ``sweep`` that is still
running after ``BAR_DELAY`` seconds. ``PARAKIN_PROGRESS`` decides where they appear: ``auto``
(the default) only when stderr is a terminal or the process is a Jupyter kernel (a notebook
widget with ipywidgets, else a text bar in the cell's output), so never in a log file, a pipe or
a test's captured output; ``on`` also when it is not; ``off`` never (the generator then reports each stage as a
logger line, as it does whenever no bar is shown). ``sweep(progress=True / False)`` asks for its
bar or refuses it whatever the setting. Logger lines written while a bar is shown appear above it.
"""

from __future__ import annotations

import logging
import os
import sys
import threading
from types import TracebackType
from typing import Any

from parakin.errors import BadInputError

logger = logging.getLogger("parakin")

#: the least number of inputs of a batch that gets a progress bar
LARGE_BATCH = 1000
#: seconds a batch runs before its bar appears (``PARAKIN_PROGRESS=on``: at once), so that a
#: large batch that finishes fast draws nothing
BAR_DELAY = 1.0
PROGRESS_SETTINGS = ("auto", "on", "off")


class _Handler(logging.StreamHandler):  # type: ignore[type-arg]
    """stderr, above an open progress bar (through ``tqdm.write``, which redraws the bar below)."""

    def emit(self, record: logging.LogRecord) -> None:
        if not _shown:
            super().emit(record)
            return
        try:
            from tqdm import tqdm

            tqdm.write(self.format(record), file=self.stream)
        except Exception:
            self.handleError(record)


def _configure() -> None:
    if logger.handlers:  # configured already (a reload, or by the user before import)
        return
    handler = _Handler()
    handler.setFormatter(logging.Formatter("parakin: %(message)s"))
    logger.addHandler(handler)
    logger.propagate = False
    level = os.environ.get("PARAKIN_LOG", "info").upper()
    logger.setLevel(level if level in logging.getLevelNamesMapping() else logging.INFO)


_configure()

#: every Progress open in this process (shown or not): while one is, no other bar appears
_open: list[Progress] = []
#: the open Progress objects that draw a bar
_shown: list[Progress] = []
_lock = threading.Lock()


class Progress:
    """A progress bar over ``total`` units of work, or nothing where no bar is shown: ``update``,
    ``describe`` and ``close`` work either way (``active`` says whether anything is drawn, or fed:
    a request nested in an open bar of the same unit counts into that bar). A context manager."""

    def __init__(self, bar: Any = None, into: Progress | None = None, unit: str = "", owner: bool = True) -> None:
        self.bar, self.into, self.unit, self.owner = bar, into, unit, owner
        self.thread = threading.get_ident()

    @property
    def active(self) -> bool:
        """Whether updates reach a bar on the screen."""
        return self.bar is not None or (self.into is not None and self.into.active)

    def update(self, count: int = 1) -> None:
        """``count`` more units done.

        Parameters
        ----------
        count : int
            Units finished since the last update.

        Examples
        --------
        >>> from parakin.log import progress
        >>> with progress(4, "four points", unit="point", show=False) as bar:
        ...     bar.update(4)
        >>> bar.active
        False
        """
        if self.bar is not None:
            self.bar.update(count)
        elif self.into is not None:
            self.into.update(count)

    def restart(self, total: int) -> None:
        """Count to ``total`` from zero (work whose size is known once it starts: a dask graph).

        Parameters
        ----------
        total : int
            The units of work now known.

        Examples
        --------
        >>> from parakin.log import progress
        >>> with progress(None, "a graph", unit="task", show=False) as bar:
        ...     bar.restart(12)
        ...     bar.update(12)
        """
        if self.bar is not None:
            self.bar.reset(total=total)

    def describe(self, text: str) -> None:
        """What is being done now, shown after the bar.

        Parameters
        ----------
        text : str
            A short note (e.g. the current chunk).

        Examples
        --------
        >>> from parakin.log import progress
        >>> with progress(2, "sweep", unit="point", show=False) as bar:
        ...     bar.describe("chunk 1 of 2")
        """
        if self.bar is not None:
            self.bar.set_postfix_str(text, refresh=False)

    def close(self) -> None:
        """Remove the bar (once); a nested request leaves the bar it fed open.

        Examples
        --------
        >>> from parakin.log import progress
        >>> bar = progress(2, "two inputs", show=False)
        >>> bar.close()
        >>> bar.close()  # a second close does nothing
        """
        if not self.owner:
            return
        self.owner = False
        with _lock:
            if self in _open:
                _open.remove(self)
            if self in _shown:
                _shown.remove(self)
        if self.bar is not None:
            self.bar.close()

    def __enter__(self) -> Progress:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.close()


def progress_setting() -> str:
    """The ``PARAKIN_PROGRESS`` setting: where progress bars appear (module docstring).

    Returns
    -------
    str
        'auto' (unset or empty: a bar only when stderr is a terminal), 'on' or 'off'.

    Raises
    ------
    BadInputError
        ``PARAKIN_PROGRESS`` holds any other value.

    Examples
    --------
    >>> from parakin.log import progress_setting
    >>> progress_setting() in ("auto", "on", "off")
    True
    """
    setting = os.environ.get("PARAKIN_PROGRESS", "auto").strip().lower() or "auto"
    if setting not in PROGRESS_SETTINGS:
        raise BadInputError(f"PARAKIN_PROGRESS must be 'auto', 'on' or 'off', got {setting!r}")
    return setting


def _terminal() -> bool:
    try:
        return bool(sys.stderr.isatty())
    except (AttributeError, ValueError):  # no stderr, or a closed one
        return False


def _notebook() -> bool:
    """Whether this process is a Jupyter kernel (its stderr is no terminal, but a person reads
    the cell's output): the 'auto' setting shows bars there too."""
    ipython = sys.modules.get("IPython")
    shell = getattr(ipython, "get_ipython", lambda: None)() if ipython is not None else None
    return type(shell).__name__ == "ZMQInteractiveShell"


def _bar_class() -> Any:
    """tqdm's notebook widget in a Jupyter kernel with ipywidgets, else its text bar (in a
    notebook without ipywidgets the text bar redraws in the cell's output)."""
    if _notebook():
        try:
            import ipywidgets  # noqa: F401
            from tqdm.notebook import tqdm as notebook_bar

            return notebook_bar
        except ImportError:
            pass
    from tqdm import tqdm

    return tqdm


def progress(
    total: int | None,
    description: str,
    unit: str = "input",
    show: bool | None = None,
    minimum: int = LARGE_BATCH,
    size: int | None = None,
    delay: float = BAR_DELAY,
) -> Progress:
    """A progress bar over ``total`` units on stderr, or a silent ``Progress``.

    While a bar is open in this process, a request from the same thread with the same unit counts
    into it (``count_modes``' chunks into one bar over the whole batch) and every other stays
    silent.

    Parameters
    ----------
    total : int or None
        The units of work; None: known once the work starts (then ``restart``).
    description : str
        What the bar counts, shown before it.
    unit : str
        The unit counted ("input", "point", "pose").
    show : bool or None
        True or False decides; None (the default): a bar when the work's ``size`` is at least
        ``minimum`` and ``PARAKIN_PROGRESS`` allows it.
    minimum : int
        The least size that gets a bar when ``show`` is None.
    size : int or None
        The work's size for that test (default ``total``).
    delay : float
        Seconds before the bar appears (s), unless the setting is 'on' or ``show`` is True.

    Returns
    -------
    Progress
        A context manager: ``update``, ``describe`` and ``close`` work whether or not a bar is drawn.

    Raises
    ------
    BadInputError
        ``PARAKIN_PROGRESS`` is not 'auto', 'on' or 'off'.

    Examples
    --------
    >>> from parakin.log import progress
    >>> with progress(3, "three inputs", show=False) as outer:
    ...     inner = progress(3, "nested", show=True)  # counts into the open one, draws nothing
    ...     inner.update(3)
    >>> outer.active, inner.owner
    (False, False)
    """
    setting = progress_setting()
    thread = threading.get_ident()
    with _lock:
        outer = _open[-1] if _open else None
        if outer is not None:
            nested = outer.thread == thread and outer.unit == unit
            return Progress(into=outer if nested else None, unit=unit, owner=False)
        large = (size if size is not None else total or 0) >= minimum
        wanted = show if show is not None else (setting != "off" and large)
        wanted = wanted and (show is True or setting == "on" or _terminal() or _notebook())
        handle = Progress(unit=unit)
        _open.append(handle)
        if wanted:
            _shown.append(handle)
    if wanted:
        bar = _bar_class()
        delay = 0.0 if show is True or setting == "on" else delay
        handle.bar = bar(total=total, desc=description, unit=unit, file=sys.stderr, delay=delay, dynamic_ncols=True)
    return handle


__all__ = ["BAR_DELAY", "LARGE_BATCH", "Progress", "logger", "progress", "progress_setting"]
