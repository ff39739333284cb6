"""Bookkeeping shared by the lane kernels (`sim.abs_wheel_kernel`, `sim.abs_vehicle_kernel`):
every per-candidate quantity in one flat array `st` of rows of `lanes` values (row r of lane l at
r * lanes + l), the candidate of each lane in `lane_of`, the live lanes packed at the front."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def close_lane(
    st: np.ndarray, l: int, live: int, lane_of: np.ndarray, n_rows: int, lanes: int
) -> int:  # pragma: no cover - compiled
    """Lane l's run ended and the queue is empty: the last live lane moves into lane l (rows and
    candidate) so that the live lanes stay packed at the front. Returns the new live count."""
    live -= 1
    if l < live:
        for row in range(n_rows):
            st[row * lanes + l] = st[row * lanes + live]
        lane_of[l] = lane_of[live]
    return live
