"""Timing helpers for the bench figures (never used by tests)."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_time(
    fn: Callable[[], object], repeats: int, clock: Callable[[], float] = time.perf_counter
) -> float:
    """Shortest time of `repeats` calls on `clock` (wall by default; the machine is shared: the
    minimum is the signal)."""
    best = float("inf")
    for _ in range(repeats):
        t0 = clock()
        fn()
        best = min(best, clock() - t0)
    return best


def best_cpu_time(fn: Callable[[], object], repeats: int) -> float:
    """Shortest thread CPU time of `repeats` calls (time descheduled on a shared machine is not
    counted)."""
    return best_time(fn, repeats, time.thread_time)
