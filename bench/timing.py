"""The one timing rule of ``make bench``: best of repeated runs within a budget."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_time(function: Callable[[], object], budget: float = 0.5) -> float:
    """Best of repeated runs (after one warm-up): at least 3, more while within ``budget``
    seconds, at most 200; in seconds."""
    function()
    best, spent, runs = float("inf"), 0.0, 0
    while (runs < 3 or spent < budget) and runs < 200:
        start = time.perf_counter()
        function()
        elapsed = time.perf_counter() - start
        best, spent, runs = min(best, elapsed), spent + elapsed, runs + 1
    return best
