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
    magic_formula_mu(s, c0, c1, c2, c3, xs) -> mu
        the Magic Formula law (`plants.mf_curve`: Pacejka 2012 eq. 4.E9 with the constants of
        4.E10-4.E18 at a constant load): mu = d sin[C arctan{B x - E (B x - arctan B x)}] + v at
        x = S_Hx - s, with (B, C, d, v) = (c0, c1, c2, c3), E = xs[0] for x < 0 and xs[1] for
        x > 0, S_Hx = xs[2] (its `kernel_data` nodes, which `table_tuples` pads like a table's).
        Its arctan and sine are `sim.branchfree_trig`'s, so that the loop vectorizes: within
        1e-15 of the scalar force `magic_formula.longitudinal_force_pure_n` / F_z
        (tests/sim/test_abs_wheel_mf.py).
    magic_formula_law_mu(law, s, c0, c1, c2, c3, xs) -> mu
        `magic_formula_mu` where the tire kind `law` may be KIND_MAGIC_FORMULA, and 0 where it is
        another constant (then never called): numba inlines every branch of a function before
        LLVM folds the constant, and the Magic Formula's code inlined into every law's vector
        loop would more than double the loops' compile time.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic, overload

from chassistune._branchfree import select
from chassistune.errors import InputError
from chassistune.plants.tires import (
    KIND_BILINEAR,
    KIND_BURCKHARDT,
    KIND_MAGIC_FORMULA,
    KIND_TABLE,
    MAX_TABLE_NODES,
)
from chassistune.sim.branchfree_trig import atan_branchfree, sin_3pi_2

TABLE_CAP = MAX_TABLE_NODES
"""Most nodes a table tire may have (TableTire refuses more)."""

__all__ = [
    "KIND_BILINEAR",
    "KIND_BURCKHARDT",
    "KIND_MAGIC_FORMULA",
    "KIND_TABLE",
    "TABLE_CAP",
    "local_table",
    "magic_formula_law_mu",
    "magic_formula_mu",
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
def magic_formula_mu(s, c0, c1, c2, c3, xs):
    """The Magic Formula law's friction coefficient at slip s (see the module docstring)."""
    x = xs[2] - s
    bx = c0 * x
    e = select(x < 0.0, xs[0], xs[1])
    return c2 * sin_3pi_2(c1 * atan_branchfree(bx - e * (bx - atan_branchfree(bx)))) + c3


def magic_formula_law_mu(law, s, c0, c1, c2, c3, xs):
    """`magic_formula_mu` under tire kind `law` (module docstring; compiled only)."""
    raise NotImplementedError("magic_formula_law_mu runs in compiled code only")


def _inlined_unless_another_law(expr, caller_info, callee_info):
    """Inline `magic_formula_law_mu` except under another constant law, where its stub stays a
    call in a branch LLVM removes (inlined, numba would compile the stub at every call site)."""
    law = caller_info.typemap[expr.args[0].name]
    return not (isinstance(law, types.IntegerLiteral) and law.literal_value != KIND_MAGIC_FORMULA)


@overload(magic_formula_law_mu, prefer_literal=True, inline=_inlined_unless_another_law)
def _magic_formula_law_mu(law, s, c0, c1, c2, c3, xs):
    if isinstance(law, types.IntegerLiteral) and law.literal_value != KIND_MAGIC_FORMULA:

        def another_law(law, s, c0, c1, c2, c3, xs):
            return 0.0

        return another_law

    def magic_formula(law, s, c0, c1, c2, c3, xs):
        return magic_formula_mu(s, c0, c1, c2, c3, xs)

    return magic_formula


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
