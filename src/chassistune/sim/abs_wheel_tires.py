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
    magic_formula_mu(s, c0, c1, c2, c3, poly) -> mu
        the Magic Formula's piecewise cubic (`plants.mf_curve`): u = s c0 + c1 fused, or
        s c2 + c3 from u = FINE_SEGMENTS on, segment i = min(floor u, SEGMENTS) and its
        coefficients a = poly[4 i ... 4 i + 3] in f = u - i by Estrin's scheme with fused
        multiply-adds, (a0 + f a1) + f^2 (a2 + f a3); poly a stack copy (`local_poly`). A NaN
        slip (a diverged run) reads segment 0 and gives NaN.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from chassistune._branchfree import fma, select
from chassistune.errors import InputError
from chassistune.plants.mf_curve import DEGREE, FINE_SEGMENTS, POLY_SIZE, SEGMENTS
from chassistune.plants.tires import (
    KIND_BILINEAR,
    KIND_BURCKHARDT,
    KIND_MAGIC_FORMULA,
    KIND_TABLE,
    MAX_TABLE_NODES,
)

TABLE_CAP = MAX_TABLE_NODES
"""Most nodes a table tire may have (TableTire refuses more)."""

__all__ = [
    "KIND_BILINEAR",
    "KIND_BURCKHARDT",
    "KIND_MAGIC_FORMULA",
    "KIND_TABLE",
    "TABLE_CAP",
    "local_poly",
    "local_table",
    "magic_formula_mu",
    "magic_formula_mu_many",
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


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def magic_formula_mu(s, c0, c1, c2, c3, poly):
    """The Magic Formula law's friction coefficient at slip s (see the module docstring)."""
    u = fma(s, c0, c1)
    u = select(u < FINE_SEGMENTS, u, fma(s, c2, c3))
    i = min(int(select(u >= 0.0, u, 0.0)), SEGMENTS)
    f = u - i
    k = (DEGREE + 1) * i
    return fma(f * f, fma(f, poly[k + 3], poly[k + 2]), fma(f, poly[k + 1], poly[k]))


@njit(cache=True, nogil=True, error_model="numpy")
def magic_formula_mu_many(s, c0, c1, c2, c3, poly):
    """`magic_formula_mu` at each slip of the array s (for `mf_curve.polynomial_mu`)."""
    out = np.empty(s.size)
    for j in range(s.size):
        out[j] = magic_formula_mu(s[j], c0, c1, c2, c3, poly)
    return out


def _local_copier(n: int, of_array: bool) -> Any:
    """An intrinsic copying n floats from a pointer (of_array: an array's data) to the stack of
    the function it is inlined into, returning a pointer to the copy."""

    @intrinsic
    def local_copy(typingctx, src):
        float_array = isinstance(src, types.Array) and src.dtype == types.float64
        if not (float_array if of_array else src == types.CPointer(types.float64)):
            return None

        def codegen(context, builder, signature, args):
            ptr = args[0]
            if of_array:
                ptr = context.make_array(signature.args[0])(context, builder, args[0]).data
            slot = cgutils.alloca_once(builder, ir.ArrayType(ir.DoubleType(), n))
            dst = builder.bitcast(slot, ir.DoubleType().as_pointer())
            cgutils.raw_memcpy(builder, dst, ptr, context.get_constant(types.intp, n), 8)
            return dst

        return types.CPointer(types.float64)(src), codegen

    return local_copy


_local_copy = _local_copier(TABLE_CAP, of_array=False)
_local_poly_copy = _local_copier(POLY_SIZE, of_array=True)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def local_table(tire):
    """The tire (c0, c1, c2, c3, xc, xs, ys) with its table nodes copied to this function's
    stack: a vector loop reading a table its caller passed by pointer would have to assume
    that its stores may change it (and does not vectorize); copies unused fold away."""
    c0, c1, c2, c3, xc, xs, ys = tire
    return c0, c1, c2, c3, _local_copy(xc), _local_copy(xs), _local_copy(ys)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def local_poly(poly):
    """A stack copy of the POLY_SIZE coefficients of the array poly (`local_table`'s reason);
    unused, it folds away."""
    return _local_poly_copy(poly)
