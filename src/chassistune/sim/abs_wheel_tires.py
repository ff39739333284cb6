"""Branch-free tire laws mu(S) for the vectorized ABS kernel, one per tire family (design.md 3.2).

Bitwise the same numbers as the tests' scalar oracle (tests/tire_oracle.py), in a form a vector
loop accepts: no calls (inline), no branches (selects), no data-dependent reads of argument
arrays. A piecewise-linear
table is passed as three tuples of TABLE_CAP floats (`table_tuples`), copied once per kernel call
to the stack (`_branchfree.stack_copy`); the segment index is a count of the interior nodes below
s (the segment the oracle's search stops at) and its four nodes are loads from the stack copies
(gathers in a vector loop).

    tire_law_mu(law, s, c0, c1, c2, c3, xc, xs, ys) -> mu
        law: KIND_BILINEAR, KIND_BURCKHARDT or KIND_TABLE (a compile-time constant in each entry
        point, so the other laws fold away); c0..c3: the tire's coefficients (0 where unused);
        xc, xs, ys: pointers to stack copies of the padded table (any for the other laws).
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from chassistune._branchfree import select
from chassistune.errors import InputError
from chassistune.plants.tires import KIND_BILINEAR, KIND_BURCKHARDT, KIND_TABLE, MAX_TABLE_NODES

TABLE_CAP = MAX_TABLE_NODES
"""Most nodes a table tire may have (TableTire refuses more)."""

__all__ = [
    "KIND_BILINEAR",
    "KIND_BURCKHARDT",
    "KIND_TABLE",
    "TABLE_CAP",
    "local_table",
    "table_tuples",
    "tire_law_mu",
]


def table_tuples(
    xs: np.ndarray, ys: np.ndarray
) -> tuple[tuple[float, ...], tuple[float, ...], tuple[float, ...]]:
    """(xc, xs, ys) padded to TABLE_CAP: xc holds the interior nodes xs[1:n-1] that the scan
    compares with (+inf elsewhere, so padding never matches)."""
    n = len(xs)
    if not 2 <= n <= TABLE_CAP:
        raise InputError("tire", f"a table tire needs 2 to {TABLE_CAP} nodes, got {n}")
    xc = np.full(TABLE_CAP, np.inf)
    xc[1 : n - 1] = xs[1 : n - 1]
    xp = np.full(TABLE_CAP, float(xs[-1]))
    yp = np.full(TABLE_CAP, float(ys[-1]))
    xp[:n], yp[:n] = xs, ys
    return tuple(xc.tolist()), tuple(xp.tolist()), tuple(yp.tolist())


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def tire_law_mu(law, s, c0, c1, c2, c3, xc, xs, ys):
    """Friction coefficient at slip s under tire law `law` (see the module docstring)."""
    if law == KIND_BILINEAR:
        return select(s <= c0, c1 * s, c2 - c3 * s)
    if law == KIND_BURCKHARDT:
        return c0 * (1.0 - math.exp(-c1 * s)) - c2 * s
    j = 1
    for m in range(1, TABLE_CAP - 1):
        j += s > xc[m]
    return ys[j - 1] + (ys[j] - ys[j - 1]) * (s - xs[j - 1]) / (xs[j] - xs[j - 1])


@intrinsic
def _local_copy(typingctx, ptr):
    if ptr != types.CPointer(types.float64):
        return None

    def codegen(context, builder, signature, args):
        slot = cgutils.alloca_once(builder, ir.ArrayType(ir.DoubleType(), TABLE_CAP))
        dst = builder.bitcast(slot, ir.DoubleType().as_pointer())
        cgutils.raw_memcpy(builder, dst, args[0], context.get_constant(types.intp, TABLE_CAP), 8)
        return dst

    return ptr(ptr), codegen


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def local_table(tire):
    """The tire (c0, c1, c2, c3, xc, xs, ys) with its table nodes copied to this function's
    stack: a vector loop reading a table its caller passed by pointer would have to assume
    that its stores may change it (and does not vectorize); copies unused fold away."""
    c0, c1, c2, c3, xc, xs, ys = tire
    return c0, c1, c2, c3, _local_copy(xc), _local_copy(xs), _local_copy(ys)  # type: ignore[call-arg]
