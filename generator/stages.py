"""The stages of a package's build, timed and shown while they run (``make generate``,
``parakin generate``): for the person waiting up to a minute per mechanism.

A build goes through ``STAGES`` in this order (a mechanism skips a stage it has nothing to do
in): ``model`` runs the mechanism file, ``checks`` checks its variables and inverse,
``derivations`` derives the closure, rates, singularity factors, inverse and drawing, ``own
homotopy`` finds and proves the start systems of the mechanism's own polynomial system (where it
writes one), ``polynomial form`` writes the loop closure as polynomials, ``automatic homotopy``
the start systems of that form (from the cache in seconds; new: monodromy with the trace test or
total-degree runs, minutes), ``lower`` lowers the
programs to code and ``emit`` renders CasADi, C and NumPy. Code in a build marks where a stage
begins (``begin``); the build's ``reporting`` sends each stage's start and finish (``Event``) to
a sink: the ``Display`` of the process that runs ``generate``, directly or, from a worker
process, through a queue. Outside a build (a test calling ``derive``) ``begin`` does nothing.

The display is one progress bar over every stage of every package (``parakin.log.progress``,
shown on a terminal) naming the stage each running build is in, and ``parakin`` logger lines
(INFO): one per finished stage with its seconds where no bar is shown, one per finished package
with its time (and its stages' times under a bar), one per package kept up to date.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from contextvars import ContextVar
from typing import NamedTuple

from parakin.log import logger, progress

STAGES = ("model", "checks", "derivations", "own homotopy", "polynomial form", "automatic homotopy", "lower", "emit")


class Event(NamedTuple):
    """A stage of ``mechanism`` started (``seconds`` None) or finished after ``seconds``; stage
    '' with seconds: the whole build finished."""

    mechanism: str
    stage: str
    seconds: float | None


class _Build:
    def __init__(self, mechanism: str, sink: Callable[[Event], None]) -> None:
        self.mechanism, self.sink = mechanism, sink
        self.times: dict[str, float] = {}
        self.stage: str | None = None
        self.began = time.perf_counter()

    def end_stage(self) -> None:
        if self.stage is not None:
            seconds = time.perf_counter() - self.began
            self.times[self.stage] = self.times.get(self.stage, 0.0) + seconds
            self.sink(Event(self.mechanism, self.stage, seconds))
            self.stage = None

    def begin(self, stage: str) -> None:
        if stage not in STAGES:
            raise ValueError(f"unknown generation stage {stage!r}; the stages are {STAGES}")
        self.end_stage()
        self.stage, self.began = stage, time.perf_counter()
        self.sink(Event(self.mechanism, stage, None))


_current: ContextVar[_Build | None] = ContextVar("parakin_generation_build", default=None)


def _nowhere(event: Event) -> None:
    """The sink of a process that shows nothing (a build outside ``generate``'s display)."""


_sink: Callable[[Event], None] = _nowhere


def send_to(sink: Callable[[Event], None]) -> Callable[[Event], None]:
    """Where this process's builds send their events from now on; returns the previous sink."""
    global _sink
    previous, _sink = _sink, sink
    return previous


@contextlib.contextmanager
def sending(sink: Callable[[Event], None]) -> Iterator[None]:
    """Inside: builds send their events to ``sink``."""
    previous = send_to(sink)
    try:
        yield
    finally:
        send_to(previous)


@contextlib.contextmanager
def reporting(mechanism: str) -> Iterator[dict[str, float]]:
    """Inside: the build of ``mechanism``, its events sent to the sink (``send_to``); yields the
    stages' seconds, filled as they finish, and sends the build's finish with its seconds. A
    build that fails sends no finish for its last stage or itself."""
    build = _Build(mechanism, _sink)
    started = time.perf_counter()
    token = _current.set(build)
    try:
        yield build.times
        build.end_stage()
        build.sink(Event(mechanism, "", time.perf_counter() - started))
    finally:
        _current.reset(token)


def begin(stage: str) -> None:
    """The current build enters ``stage`` (one of ``STAGES``), finishing the stage it was in."""
    build = _current.get()
    if build is not None:
        build.begin(stage)


def _seconds(times: dict[str, float]) -> str:
    return ", ".join(f"{stage} {seconds:.1f} s" for stage, seconds in times.items())


class Display:
    """Shows the builds of ``names`` (module docstring); ``__call__`` takes their events."""

    def __init__(self, names: list[str]) -> None:
        count = len(names)
        what = f"generating {names[0]}" if count == 1 else f"generating {count} packages"
        self.bar = progress(count * len(STAGES), what, unit="stage", minimum=1, delay=0.0)
        self.running: dict[str, str] = {}
        self.times: dict[str, dict[str, float]] = {name: {} for name in names}
        self.started = time.perf_counter()

    def __call__(self, event: Event) -> None:
        name, stage, seconds = event
        times = self.times.setdefault(name, {})
        if not stage:  # the build finished: the stages it skipped count as done
            self.bar.update(len(STAGES) - len(times))
            self.running.pop(name, None)
            shown = f" ({_seconds(times)})" if self.bar.active else ""
            logger.info("generated %s in %.1f s%s", name, seconds, shown)
        elif seconds is None:
            self.running[name] = stage
        else:
            if stage not in times:
                self.bar.update()
            times[stage] = times.get(stage, 0.0) + seconds
            if not self.bar.active:
                logger.info("%s: %s %.2f s", name, stage, seconds)
        self.bar.describe(", ".join(f"{n}: {s}" for n, s in self.running.items()))

    def step(self, what: str) -> None:
        """A step after the builds (formatting, sealing), shown as what is being done."""
        self.running.clear()
        self.bar.describe(what)

    def close(self) -> None:
        """Remove the bar (its last state stays on the screen, with no step named)."""
        self.bar.describe("")
        self.bar.close()


@contextlib.contextmanager
def shown(names: list[str]) -> Iterator[Display]:
    """Inside: this process's builds of ``names`` shown by a ``Display`` (yielded), removed after."""
    display = Display(names)
    try:
        with sending(display):
            yield display
    finally:
        display.close()


def say_kept(names: list[str]) -> None:
    """One line per package kept as it was (up to date)."""
    for name in names:
        logger.info("%s: up to date, kept", name)
