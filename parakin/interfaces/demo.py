"""``parakin demo NAME``: every named example of a mechanism's manifest, reproduced.

An example gives a pose (solved by ``inverse_pose``) or actuated inputs (solved by
``forward_pose_all``) and the values printed in the paper; each comparison reports our value,
the printed one, the digits of agreement and whether it holds to the example's tolerance.
Generic over mechanisms: longer paper walkthroughs are scripts in ``examples/``.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from parakin.errors import ParakinError
from parakin.packages.manifest import Example
from parakin.results import Array, AssemblyModes, modes_table


@dataclass(frozen=True)
class Comparison:
    """One printed quantity: ``ours`` against ``printed``, agreeing to ``error`` (max abs)."""

    quantity: str
    ours: Array
    printed: Array
    error: float
    tolerance: float

    @property
    def holds(self) -> bool:
        return bool(self.error <= self.tolerance)

    @property
    def digits(self) -> float:
        """Significant digits of agreement (relative to the largest printed magnitude): inf when
        equal, NaN when the printed values are all zero (no digits to count: the error says it)."""
        scale = float(np.abs(self.printed).max(initial=0.0))
        if self.error == 0:
            return math.inf
        return max(0.0, -math.log10(self.error / scale)) if scale > 0 else math.nan


@dataclass(frozen=True)
class ExampleResult:
    example: Example
    comparisons: tuple[Comparison, ...]
    error: str | None = None  # a ParakinError raised while solving, by name and message
    #: for actuated inputs: one line per assembly mode found (pose, residual, conditioning)
    modes: tuple[str, ...] = ()

    @property
    def holds(self) -> bool:
        return self.error is None and all(c.holds for c in self.comparisons)


def _compare(
    quantity: str, ours: object, printed: object, tolerance: float, revolute: Array | None = None
) -> Comparison:
    a, b = np.asarray(ours, dtype=float), np.asarray(printed, dtype=float)
    difference = a - b
    if revolute is not None:  # angles compare modulo 2 pi
        difference = np.where(revolute, (difference + np.pi) % (2 * np.pi) - np.pi, difference)
    return Comparison(quantity, a, b, float(np.abs(difference).max(initial=0.0)), tolerance)


def _inverse_example(m: object, example: Example) -> list[Comparison]:
    from parakin.mechanism import Mechanism

    assert isinstance(m, Mechanism)
    branches = m.inverse_pose(example.pose, strict=False)
    expected = example.expected
    revolute_a = np.array([v.revolute for v in m.manifest.actuated])
    revolute_p = np.array([v.revolute for v in m.manifest.passive])
    if example.branch is not None:
        k = example.branch
    else:  # the valid branch nearest the printed values
        distance = np.zeros(branches.actuated.shape[0])
        if "actuated" in expected:
            distance += np.abs(branches.actuated - np.asarray(expected["actuated"], dtype=float)).max(-1)
        if "passive" in expected:
            distance += np.abs(branches.passive - np.asarray(expected["passive"], dtype=float)).max(-1)
        distance = np.where(branches.valid, np.nan_to_num(distance, nan=np.inf), np.inf)
        k = int(np.argmin(distance))
    comparisons = [_compare("branch valid", float(branches.valid[k]), 1.0, 0.0)]
    if "actuated" in expected:
        comparisons.append(
            _compare(
                f"actuated (branch {k})", branches.actuated[k], expected["actuated"], example.tolerance, revolute_a
            )
        )
    if "passive" in expected:
        comparisons.append(
            _compare(f"passive (branch {k})", branches.passive[k], expected["passive"], example.tolerance, revolute_p)
        )
    return comparisons


#: the first line of every mode table (the header is the second)
def mode_table(modes: AssemblyModes, pose_kind: str | None = None) -> tuple[str, ...]:
    """Every valid mode of one input, as ``print(modes)`` shows them, with the closure residual:
    the convention line, the header, a rule and one line per mode; the pose columns of
    ``pose_kind`` (default ``modes.pose_kind``)."""
    return tuple(modes_table(modes, residual=True, rows_shown=len(modes.valid), pose_kind=pose_kind).splitlines())


def _forward_example(modes: AssemblyModes, example: Example) -> list[Comparison]:
    expected = example.expected
    comparisons = []
    if "mode_count" in expected:
        comparisons.append(_compare("mode count", float(modes.count), float(expected["mode_count"]), 0.0))  # type: ignore[arg-type]
    valid = np.asarray(modes.valid)
    modes_found = np.flatnonzero(valid)  # the slots that hold modes, mode k in slot modes_found[k]
    for index, pose in enumerate(expected.get("poses", [])):  # type: ignore[arg-type]
        printed = np.asarray(pose, dtype=float)
        quantity = f"printed pose {index + 1}"
        if not modes_found.size:  # nothing to compare with: a slot that holds no mode is no answer
            nothing = np.full_like(printed, np.nan)
            comparisons.append(Comparison(f"{quantity} (no mode found)", nothing, printed, math.inf, example.tolerance))
            continue
        distance = np.abs(modes.poses[modes_found] - printed).max(axis=(-2, -1))
        k = int(np.argmin(np.nan_to_num(distance, nan=np.inf)))  # the nearest mode, numbered as the table
        comparisons.append(_compare(f"{quantity} (mode {k})", modes.poses[modes_found[k]], printed, example.tolerance))
    return comparisons


def library_cached(name: str | os.PathLike[str]) -> bool:
    """Whether the compiled C library of package ``name`` is already in the cache (so that
    backend 'compiled' loads it without running the compiler): where
    ``parakin.packages.compiled.library_target`` puts it; anything unreadable counts as not cached."""
    from parakin.packages import compiled
    from parakin.packages.package import GeneratedPackage

    try:
        return compiled.library_target(GeneratedPackage.find(name))[2].is_file()
    except (OSError, ParakinError):
        return False


#: ``parakin demo``'s default backend: compiled where its library is already built, else NumPy
CACHED = "cached"


def demo_backend(name: str | os.PathLike[str], backend: str = CACHED) -> str:
    """The backend the demo of ``name`` runs on: ``backend``, except that ``"cached"`` is
    'compiled' where the C library is already in the cache and 'numpy' where it is not (so the
    demo never waits for the C compiler: 1-20 s per mechanism on first use)."""
    if backend != CACHED:
        return backend
    return "compiled" if library_cached(name) else "numpy"


def run_examples(name: str | os.PathLike[str], backend: str = "auto") -> list[ExampleResult]:
    """Solve every example of a mechanism's manifest and compare with the printed values.
    ``backend``: as ``parakin.load``, or ``"cached"`` (``demo_backend``)."""
    import parakin

    manifest = parakin.metadata(name)
    backend = demo_backend(name, backend)
    results = []
    for example in manifest.examples:
        try:
            overrides: dict[str, Any] = dict(example.parameters)
            m = parakin.load(name, backend=backend, **overrides)
            if example.pose is not None:
                results.append(ExampleResult(example, tuple(_inverse_example(m, example))))
            else:
                modes = m.forward_pose_all(np.asarray(example.actuated, dtype=float))
                table = mode_table(modes, m.manifest.pose_kind)
                results.append(ExampleResult(example, tuple(_forward_example(modes, example)), modes=table))
        except ParakinError as error:
            results.append(ExampleResult(example, (), f"{type(error).__name__}: {error}"))
    return results


def _values(values: Array) -> str:
    """(v1, v2, ...) to 6 significant digits; below 1e-12 in magnitude shown as 0 (no "-0")."""
    return "(" + ", ".join(f"{round(float(v), 12) + 0.0:.6g}" for v in np.ravel(values)) + ")"


def format_comparison(c: Comparison) -> str:
    """One line per printed quantity: ``[ok ]`` or ``[FAIL]``, what was compared, our value and
    the printed one (vectors; poses only by their error) and the error against the tolerance."""
    mark = "ok " if c.holds else "FAIL"
    if c.tolerance == 0 and c.ours.ndim == 0:  # an exact quantity: a count, or validity
        if c.quantity == "branch valid":
            return f"  [{mark}] the branch is {'valid' if c.ours == 1 else 'not valid'}"
        return f"  [{mark}] {c.quantity}: {c.ours:g} (printed {c.printed:g})"
    values = f"ours {_values(c.ours)}, printed {_values(c.printed)}; " if c.ours.ndim < 2 else ""
    digits = "" if math.isnan(c.digits) else ", equal" if math.isinf(c.digits) else f", {c.digits:.1f} digits"
    return f"  [{mark}] {c.quantity}: {values}|error| {c.error:.1e} (tolerance {c.tolerance:.0e}{digits})"


def format_results(name: str, results: list[ExampleResult]) -> str:
    """The table ``parakin demo`` prints."""
    import parakin

    manifest = parakin.metadata(name)
    lines = [f"{manifest.title}", f"  {manifest.citation}", ""]
    if not results:
        lines += ["  (no named examples in this mechanism's manifest)", ""]
    for result in results:
        e = result.example
        lines.append(f"example {e.name}: {e.description}")
        if result.error:
            lines.append(f"  raised {result.error}")
        lines += [format_comparison(c) for c in result.comparisons]
        if result.modes:
            count = len(result.modes) - 3
            lines.append(f"  {count} assembly mode{'s' if count != 1 else ''}:")
            lines += result.modes
        lines.append("")
    return "\n".join(lines)


__all__ = [
    "CACHED",
    "Comparison",
    "ExampleResult",
    "demo_backend",
    "library_cached",
    "format_comparison",
    "format_results",
    "mode_table",
    "run_examples",
]
