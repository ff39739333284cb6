"""Memory a command will need, estimated from its sizes before anything is allocated, and the
memory the machine has: a population or a study grid too large for it is refused up front
instead of filling memory for minutes and then failing.

The per-item sizes are measured peaks (tracemalloc) with a margin: an optimizer keeps at most
about 100 bytes per candidate and gain (derlsp-ao, 3 gains: 298 bytes per candidate), one
population's simulation about 130 bytes per candidate and road (abs-wheel PID) and more for the
vehicle's per-wheel metrics, a planned study run about 4 KB (its spec, keys and dicts).
"""

from __future__ import annotations

import os
from typing import Any

from chassistune.errors import InputError

OPTIMIZER_BYTES_PER_GAIN = 128
"""Optimizer state per candidate and gain (positions, velocities, bests, trial vectors)."""
EVALUATION_BYTES_PER_SCENARIO = 512
"""Simulation outputs per candidate and scenario (the metric rows and their columns)."""
PLANNED_RUN_BYTES = 8192
"""One run of a study grid while planned and run (its spec, and its key in the store's sets)."""
GIB = 1 << 30


def available_bytes() -> int:
    """Memory this process can still take: the kernel's MemAvailable, within the cgroup's limit
    (a container) when there is one."""
    free = _meminfo_available()
    try:
        with open("/sys/fs/cgroup/memory.max", encoding="ascii") as fh:
            limit = fh.read().strip()
        with open("/sys/fs/cgroup/memory.current", encoding="ascii") as fh:
            used = int(fh.read().strip())
    except (OSError, ValueError):
        return free
    return free if limit == "max" else min(free, max(0, int(limit) - used))


def _meminfo_available() -> int:
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def tune_bytes(pop_size: int, n_gains: int, n_scenarios: int) -> int:
    """Estimated peak memory of one tune (or study run) beyond the process's base."""
    per_candidate = OPTIMIZER_BYTES_PER_GAIN * max(n_gains, 1) + (
        EVALUATION_BYTES_PER_SCENARIO * max(n_scenarios, 1)
    )
    return pop_size * per_candidate


def problem_bytes(problem: Any, pop_size: int) -> int:
    """`tune_bytes` of a tuning problem: its gains, and its scenarios (a robust problem's grid
    of K training scenarios x R roads)."""
    grid = getattr(problem, "grid", None)
    scenarios = sum(len(row) for row in grid) if grid else len(problem.scenarios)
    return tune_bytes(pop_size, len(problem.gain_names), scenarios)


def check_fits(need_bytes: int, field: str, what: str) -> None:
    """Refuse (InputError naming `field`) when `what` needs more memory than is available."""
    have = available_bytes()
    if need_bytes > have:
        raise InputError(
            field,
            f"{what} needs about {need_bytes / GIB:.3g} GiB of memory, more than the "
            f"{have / GIB:.3g} GiB available",
        )
