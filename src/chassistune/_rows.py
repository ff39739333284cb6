"""Values at a constant stride of a flat array as a tuple, and back: the lane kernels' rows
(`sim.lanes`) and the ECU law dispatch's signal rows (`controllers.discrete`) read and write
them so, in loops of known length that LLVM unrolls."""

from __future__ import annotations

import numpy as np
from numba import njit
from numba.cpython.unsafe.tuple import tuple_setitem


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def read_rows(st: np.ndarray, first: int, step: int, zeros: tuple) -> tuple:  # pragma: no cover
    """The values st[first], st[first + step], ... as a tuple shaped like `zeros` (a constant
    tuple of the length wanted): a loop of known length that LLVM unrolls into loads, where a
    strided view copied into a tuple costs a view and a bounds-checked loop at every tick."""
    out = zeros
    for m in range(len(zeros)):
        out = tuple_setitem(out, m, st[first + m * step])  # type: ignore[call-arg]
    return out


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def write_rows(st: np.ndarray, first: int, step: int, values: tuple) -> None:  # pragma: no cover
    """st[first + m * step] = values[m] for every m (`read_rows`'s inverse)."""
    for m in range(len(values)):
        st[first + m * step] = values[m]
