"""Run a compiled batch kernel over chunks of candidates on a thread pool.

The kernels compute each candidate independently of the others: no reduction across candidates,
and vector lanes (the ABS kernel's persistent SIMD lanes) apply the same IEEE operations to each
lane as scalar code would (no fastmath, no reassociation, no implicit contraction), so a
candidate's numbers do not depend on its lane, its neighbours or the chunk it lands in: results
are bitwise identical for any worker count. Kernels must be nogil. Chunks of at least MIN_CHUNK
candidates: a lane kernel runs whole vectors of 8 lanes, so tiny chunks waste lanes.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np

MIN_CHUNK = 8
_POOLS: dict[int, ThreadPoolExecutor] = {}


def _pool(workers: int) -> ThreadPoolExecutor:
    """A process-wide pool per size (creating threads for every batch costs more than small
    batches take)."""
    if workers not in _POOLS:
        _POOLS[workers] = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="kernel")
    return _POOLS[workers]


def default_workers() -> int:
    """Parallel workers to use (kernel threads here, study worker processes in
    `studies.executors`): CHASSISTUNE_THREADS if set, else the cores this process may use."""
    env = os.environ.get("CHASSISTUNE_THREADS")
    if env:
        return max(1, int(env))
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - non-Linux
        return max(1, os.cpu_count() or 1)


def run_chunked(
    kernel_call: Callable[[np.ndarray, np.ndarray], None],
    gains: np.ndarray,
    n_out: int,
    workers: int | None = None,
) -> np.ndarray:
    """Call `kernel_call(gains_chunk, out_chunk)` on chunks; return out of shape (n, n_out)."""
    n = gains.shape[0]
    out = np.empty((n, n_out))
    workers = default_workers() if workers is None else workers
    chunk = max(MIN_CHUNK, -(-n // max(workers, 1)))
    starts = list(range(0, n, chunk))
    if workers <= 1 or len(starts) <= 1:
        kernel_call(np.ascontiguousarray(gains), out)
        return out
    pool = _pool(workers)
    futures = [
        pool.submit(kernel_call, np.ascontiguousarray(gains[s : s + chunk]), out[s : s + chunk])
        for s in starts
    ]
    for f in futures:
        f.result()
    return out
