"""The model-predictive slip law's QP: pressure moves over a horizon of 1 to 5 samples
(docs/abs_laws.md, "Model-predictive slip control").

    minimise    0.5 z' H z + f' z                     z_j = q_(j+1) - q_j, the pressure move
    subject to  move_lo_j <= z_j <= move_hi_j          (the pressure-rate limit times ts)
                0 <= q0 + z_0 + ... + z_j <= q_max     (the predicted pressure), j = 0 .. N-1

with H symmetric positive definite: N variables, 2N two-sided rows l <= C z <= u, C = [I; L]
(L the lower triangle of ones). Solved with a FIXED amount of work, so that a population on SIMD
lanes runs in lock step and a C replay of the same operations gives the same bits: no test on
convergence, no early exit, only selects (min, max, a ? b : c) on the data.

1. Scaling: moves in units of the largest move limit, the cost divided so that max |H| = 1.
2. `iterations` steps of Mehrotra's predictor-corrector interior-point method (Nocedal and
   Wright, "Numerical Optimization", 2nd ed., Springer 2006, section 16.6 for QPs; the fixed
   iteration count as in Wang and Boyd, "Fast model predictive control using online
   optimization", IEEE Trans. Control Syst. Technol. 18(2), 2010): slacks su = u - Cz,
   sl = Cz - l and multipliers lu, ll, started strictly inside the feasible set (each move half
   of the way to the middle pressure, within half its interval) on the central path; each step
   solves the N x N normal equations (H + C' W C) dz = ... (W = lu/su + ll/sl) by an L D L'
   factorisation twice (predictor, corrector) and moves 0.99 of the longest step that keeps
   slacks and multipliers positive. The centring target never falls below MU_FLOOR, which keeps
   W finite and the normal matrix factorable after convergence (further steps change nothing).
3. `polish_steps` augmented-Lagrangian steps on the rows the interior point marks active
   (multiplier above slack), each one L D L' solve of (H + rho C_A' C_A): they remove the
   central path's offset (the same polish as OSQP's, Stellato et al., Math. Prog. Comp. 2020).
4. A clamp of each move, in order, into what the previous moves leave of its interval
   (`feasible`): the result satisfies every constraint exactly.

Why this solver: dual coordinate ascent (Hildreth's procedure, Wang, "Model Predictive Control
System Design and Implementation Using MATLAB", Springer 2009, 2.4.4) and projected dual
gradients converge linearly at a rate set by the conditioning of C H^-1 C', which is singular
here (2N rows, rank N): on the test's instances Hildreth still erred by 5 pressure units after
1600 sweeps. An interior point needs a number of iterations almost independent of the data.

The start matters: from z = 0 a QP whose pressure starts on its limit (q0 = q_max: the row
q0 + z_0 <= q_max has zero slack at z = 0, floored to START_SLACK with a multiplier of 100
times the others') sends the predictor-corrector into a cycle of period 4 (z alternating
between two points that each take 0.99 of the step to a bound, the complementarity stuck near
1 at any iteration count), and the polish then clamps onto two contradictory active rows
(tests/controllers/test_mpc_law.py: minimiser -25.49, result -25.0). Started strictly inside,
every slack is a true distance and the iterates stay centred.

Measured (tests/controllers/test_slip_mpc_qp.py: 60 random instances per horizon 1..5, half
the MPC law's own QPs, half generic): `ITERATIONS_MEASURED` iterations with `POLISH_STEPS`
polish steps bring every instance within 1e-8 (in units of its largest move limit; the largest
absolute error 1.6e-8 pressure units on moves of up to 100) of the exact solution (an active-set
enumeration in the test; 400 more per horizon from other seeds, by hand: within 3e-9);
`IPM_ITERATIONS` keeps a margin. One solve with those counts costs about 4 us at N = 3 and 8 us
at N = 5 inside the law in the ideal kernel (docs/abs_laws.md, "The registered model-predictive
law"), mostly the divisions of the slack and multiplier updates. The caller provides the
scratch (`scratch`, or `stack_scratch` on its own stack in the kernels); a solve allocates nothing
and makes no array view in its loop.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic
from numba.np.arrayobj import populate_array

from chassistune.controllers.slip_mpc_qp_c import (
    IPM_ITERATIONS as IPM_ITERATIONS,
)
from chassistune.controllers.slip_mpc_qp_c import (
    ITERATIONS_MEASURED as ITERATIONS_MEASURED,
)
from chassistune.controllers.slip_mpc_qp_c import (
    MAX_HORIZON,
    MU_FLOOR,
    POLISH_RHO,
    START_SLACK,
    STEP_FRACTION,
)
from chassistune.controllers.slip_mpc_qp_c import POLISH_STEPS as POLISH_STEPS

(
    V_F,
    V_BASE,
    V_DX,
    V_X,
    V_RHS,
    V_Y,
    V_LO,
    V_HI,
    V_SU,
    V_SL,
    V_LU,
    V_LL,
    V_DSU,
    V_DSL,
    V_DLU,
    V_DLL,
    V_TU,
    V_TL,
    V_CX,
    V_W,
    V_ROWS_RHS,
    V_NU,
    V_BOUND,
    N_VECTORS,
) = range(24)
"""Rows of the vector scratch `vec` (each 2N long; the first six use N)."""


def scratch(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The scratch of one solve of horizon n: (mat, vec), allocated once by the caller."""
    return np.empty((3, n, n)), np.empty((N_VECTORS, 2 * n))


def _stack_array(shape: tuple[int, ...]) -> Any:
    """An intrinsic returning a C-ordered float array of `shape` on the stack of the function it
    is compiled into (one block per call site, in the entry block: a call in a loop reuses it),
    built in place: no allocation and no runtime call, as code compiled without numba's runtime
    needs (numba's `carray` returns an array from a function, which that code refuses)."""
    array_type = types.Array(types.float64, len(shape), "C")
    strides = tuple(8 * int(np.prod(shape[k + 1 :])) for k in range(len(shape)))

    @intrinsic
    def stack_array(typingctx):  # type: ignore[no-untyped-def]
        def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
            slot = cgutils.alloca_once(builder, ir.ArrayType(ir.DoubleType(), int(np.prod(shape))))
            array = context.make_array(array_type)(context, builder)
            populate_array(
                array,
                data=builder.bitcast(slot, ir.DoubleType().as_pointer()),
                shape=tuple(context.get_constant(types.intp, n) for n in shape),
                strides=tuple(context.get_constant(types.intp, n) for n in strides),
                itemsize=context.get_constant(types.intp, 8),
                meminfo=None,
            )
            return array._getvalue()

        return array_type(), codegen

    return stack_array


_STACK_MAT = _stack_array((3, MAX_HORIZON, MAX_HORIZON))
_STACK_VEC = _stack_array((N_VECTORS, 2 * MAX_HORIZON))
_STACK_SQUARE = _stack_array((MAX_HORIZON, MAX_HORIZON))
_STACK_ROW = _stack_array((MAX_HORIZON,))


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def stack_scratch(n: int) -> Any:  # pragma: no cover - compiled
    """(h, f, move_lo, move_hi, z, mat, vec) of one solve of horizon n <= MAX_HORIZON, on the
    stack of the function this is inlined into, of the largest horizon's size (h
    MAX_HORIZON x MAX_HORIZON, the vectors n long): no allocation, for code compiled without
    numba's runtime (the kernels)."""
    f, move_lo, move_hi, z = _STACK_ROW(), _STACK_ROW(), _STACK_ROW(), _STACK_ROW()
    return _STACK_SQUARE(), f[:n], move_lo[:n], move_hi[:n], z[:n], _STACK_MAT(), _STACK_VEC()


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def clamp(x: float, lo: float, hi: float) -> float:  # pragma: no cover - compiled
    """x clamped into [lo, hi] (hi wins if lo > hi)."""
    return min(max(x, lo), hi)


@njit(cache=True, nogil=True, error_model="numpy")
def horizon1_move(
    h: float, f: float, move_lo: float, move_hi: float, q0: float, q_max: float
) -> float:  # pragma: no cover - compiled
    """The QP with N = 1 in closed form: its two intervals intersect into one, and the minimiser
    of 0.5 h z^2 + f z is clamped into it."""
    return clamp(-f / h, max(move_lo, -q0), min(move_hi, q_max - q0))


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _ldl_solve(
    mat: np.ndarray, vec: np.ndarray, n: int, out: np.ndarray
) -> None:  # pragma: no cover - compiled
    """out = K^-1 rhs for the small symmetric positive definite K = mat[1] (K = L D L', L' and D
    in mat[2] with D on its diagonal, two triangular solves through vec[V_Y]) and rhs =
    vec[V_RHS], the operation order fixed by the size; no square root, so that the C needs no
    library. Indexes the scratch directly: no array view is made in the loop."""
    for j in range(n):
        d = mat[1, j, j]
        for i in range(j):
            d -= mat[2, i, j] * mat[2, i, j] * mat[2, i, i]
        mat[2, j, j] = d
        for i in range(j + 1, n):
            s = mat[1, j, i]
            for m in range(j):
                s -= mat[2, m, j] * mat[2, m, i] * mat[2, m, m]
            mat[2, j, i] = s / d
    for i in range(n):
        s = vec[V_RHS, i]
        for m in range(i):
            s -= mat[2, m, i] * vec[V_Y, m]
        vec[V_Y, i] = s
    for i in range(n - 1, -1, -1):
        s = vec[V_Y, i] / mat[2, i, i]
        for m in range(i + 1, n):
            s -= mat[2, i, m] * out[m]
        out[i] = s


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _span(row: int, n: int) -> tuple[int, int]:  # pragma: no cover - compiled
    """The variables row `row` of C = [I; L] sums: (first, last) inclusive."""
    return (row, row) if row < n else (0, row - n)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _row_value(row: int, n: int, z: np.ndarray) -> float:  # pragma: no cover - compiled
    """C_row z."""
    first, last = _span(row, n)
    s = 0.0
    for m in range(first, last + 1):
        s += z[m]
    return s


@njit(cache=True, nogil=True, error_model="numpy")
def _weighted_solve(
    n: int,
    w: np.ndarray,
    rows_rhs: np.ndarray,
    base: np.ndarray,
    out: np.ndarray,
    mat: np.ndarray,
    vec: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """out = (H + sum_r w_r C_r' C_r)^-1 (base - sum_r C_r' rows_rhs_r) with H = mat[0]; the
    matrix is formed in mat[1], the right-hand side in vec[V_RHS]."""
    for a in range(n):
        vec[V_RHS, a] = base[a]
        for b in range(n):
            mat[1, a, b] = mat[0, a, b]
    for row in range(2 * n):
        first, last = _span(row, n)
        for a in range(first, last + 1):
            vec[V_RHS, a] -= rows_rhs[row]
            for b in range(first, last + 1):
                mat[1, a, b] += w[row]
    _ldl_solve(mat, vec, n, out)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _longest_step(x: float, dx: float, a: float) -> float:  # pragma: no cover - compiled
    """min(a, the step that takes x > 0 to 0 along dx)."""
    return min(a, -x / dx if dx < 0.0 else a)


@njit(cache=True, nogil=True, error_model="numpy")
def feasible(
    z: np.ndarray, move_lo: np.ndarray, move_hi: np.ndarray, q0: float, q_max: float
) -> None:  # pragma: no cover - compiled
    """Clamps z in place, move by move, into [max(move_lo, -q), min(move_hi, q_max - q)] with q
    the pressure the previous moves reach: afterwards every constraint holds (for 0 <= q0 <=
    q_max and move_lo <= 0 <= move_hi the interval is never empty)."""
    q = q0
    for j in range(z.shape[0]):
        z[j] = clamp(z[j], max(move_lo[j], -q), min(move_hi[j], q_max - q))
        q += z[j]


@njit(cache=True, nogil=True, error_model="numpy")
def solve_moves(
    h: np.ndarray,
    f: np.ndarray,
    move_lo: np.ndarray,
    move_hi: np.ndarray,
    q0: float,
    q_max: float,
    iterations: int,
    polish_steps: int,
    z: np.ndarray,
    mat: np.ndarray,
    vec: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """Writes into z (length N) the QP's moves: `iterations` predictor-corrector steps, then
    `polish_steps` of the polish, then the clamp (module docstring). h: N x N positive definite;
    f, move_lo, move_hi: length N; mat, vec: the scratch of `scratch(N)` (no allocation here)."""
    n = f.shape[0]
    m = 2 * n
    # scale: moves in units of the largest move limit, the cost so that max |H| = 1
    scale = 1e-300
    hmax = 0.0
    for j in range(n):
        scale = max(scale, abs(move_lo[j]), abs(move_hi[j]))
        for k in range(n):
            hmax = max(hmax, abs(h[j, k]))
    hs = mat[0]
    fs, base, dx, x = vec[V_F, :n], vec[V_BASE, :n], vec[V_DX, :n], vec[V_X, :n]
    lo, hi, su, sl, lu, ll = vec[V_LO], vec[V_HI], vec[V_SU], vec[V_SL], vec[V_LU], vec[V_LL]
    dsu, dsl, dlu, dll = vec[V_DSU], vec[V_DSL], vec[V_DLU], vec[V_DLL]
    tu, tl = vec[V_TU], vec[V_TL]  # complementarity right-hand sides
    cx, w, rows_rhs = vec[V_CX], vec[V_W], vec[V_ROWS_RHS]
    nu, bound = vec[V_NU], vec[V_BOUND]
    for j in range(n):
        fs[j] = f[j] * (1.0 / (hmax * scale))
        for k in range(n):
            hs[j, k] = h[j, k] * (1.0 / hmax)
    for j in range(n):
        lo[j], hi[j] = move_lo[j] / scale, move_hi[j] / scale
        lo[n + j], hi[n + j] = -q0 / scale, (q_max - q0) / scale
    # start strictly inside: each move half of the way to the middle pressure, within half
    # its interval; slacks its distances to the bounds (at least START_SLACK), multipliers on
    # the central path at mu0
    middle = 0.5 * (lo[n] + hi[n])
    reached = 0.0
    for j in range(n):
        x[j] = clamp(0.5 * (middle - reached), 0.5 * lo[j], 0.5 * hi[j])
        reached += x[j]
    mu0 = 1.0
    for j in range(n):
        mu0 = max(mu0, abs(fs[j]))
    for row in range(m):
        cx[row] = _row_value(row, n, x)
        su[row] = max(hi[row] - cx[row], START_SLACK)
        sl[row] = max(cx[row] - lo[row], START_SLACK)
        lu[row] = mu0 / su[row]
        ll[row] = mu0 / sl[row]
    for _ in range(iterations):
        # residuals: dual rd = H x + f + C'(lu - ll); primal rpu = Cx + su - hi, rpl = lo - Cx + sl
        for a in range(n):
            s = fs[a]
            for b in range(n):
                s += hs[a, b] * x[b]
            base[a] = -s
        mu = 0.0
        for row in range(m):
            cx[row] = _row_value(row, n, x)
            first, last = _span(row, n)
            for a in range(first, last + 1):
                base[a] -= lu[row] - ll[row]
            mu += su[row] * lu[row] + sl[row] * ll[row]
            tu[row] = -su[row] * lu[row]
            tl[row] = -sl[row] * ll[row]
        mu /= 2 * m
        step = 1.0
        for phase in range(2):  # 0: affine predictor, 1: centred corrector
            for row in range(m):
                wu, wl = lu[row] / su[row], ll[row] / sl[row]
                rpu = cx[row] + su[row] - hi[row]
                rpl = lo[row] - cx[row] + sl[row]
                w[row] = wu + wl
                rows_rhs[row] = tu[row] / su[row] + wu * rpu - tl[row] / sl[row] - wl * rpl
            _weighted_solve(n, w, rows_rhs, base, dx, mat, vec)
            step = 1.0
            for row in range(m):
                cd = _row_value(row, n, dx)
                dsu[row] = -(cx[row] + su[row] - hi[row]) - cd
                dsl[row] = -(lo[row] - cx[row] + sl[row]) + cd
                dlu[row] = (tu[row] - lu[row] * dsu[row]) / su[row]
                dll[row] = (tl[row] - ll[row] * dsl[row]) / sl[row]
                step = _longest_step(su[row], dsu[row], step)
                step = _longest_step(sl[row], dsl[row], step)
                step = _longest_step(lu[row], dlu[row], step)
                step = _longest_step(ll[row], dll[row], step)
            if phase == 0:  # Mehrotra's centring and second-order terms
                mu_aff = 0.0
                for row in range(m):
                    mu_aff += (su[row] + step * dsu[row]) * (lu[row] + step * dlu[row])
                    mu_aff += (sl[row] + step * dsl[row]) * (ll[row] + step * dll[row])
                ratio = mu_aff / (2 * m * mu)
                target = ratio * ratio * ratio * mu + MU_FLOOR
                for row in range(m):
                    tu[row] += target - dsu[row] * dlu[row]
                    tl[row] += target - dsl[row] * dll[row]
        step *= STEP_FRACTION
        for j in range(n):
            x[j] += step * dx[j]
        for row in range(m):
            su[row] += step * dsu[row]
            sl[row] += step * dsl[row]
            lu[row] += step * dlu[row]
            ll[row] += step * dll[row]
    # polish: the rows whose multiplier exceeds their slack are active at their bound; on them,
    # augmented-Lagrangian steps reach the equality-constrained minimiser
    for row in range(m):
        up = lu[row] > su[row]
        down = ll[row] > sl[row]
        w[row] = POLISH_RHO if up | down else 0.0
        bound[row] = hi[row] if up else lo[row]
        nu[row] = lu[row] - ll[row]
    for _ in range(polish_steps):
        for a in range(n):
            base[a] = -fs[a]
        for row in range(m):
            rows_rhs[row] = w[row] * (nu[row] / POLISH_RHO - bound[row])
        _weighted_solve(n, w, rows_rhs, base, x, mat, vec)
        for row in range(m):
            nu[row] += w[row] * (_row_value(row, n, x) - bound[row])
    for j in range(n):
        z[j] = x[j] * scale
    feasible(z, move_lo, move_hi, q0, q_max)
