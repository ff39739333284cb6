"""The model-predictive law's QP solver (`slip_mpc_qp`, docs/abs_laws.md 5): its fixed settings
and its C text, without numba, so that the law's spec and its C load without the compiler."""

from __future__ import annotations

MAX_HORIZON = 5
"""The longest horizon the law offers (the QP has at most 5 variables and 10 two-sided rows)."""

IPM_ITERATIONS = 12
"""Predictor-corrector iterations of every solve (`ITERATIONS_MEASURED` plus a margin)."""
POLISH_STEPS = 2
"""Augmented-Lagrangian steps of the polish on the identified active set."""
ITERATIONS_MEASURED = 10
"""The fewest iterations (with POLISH_STEPS) that met 1e-8 on every instance of the test."""

MU_FLOOR = 1e-12
"""Smallest complementarity target (scaled units): the iterates settle on the central path at
s l = MU_FLOOR instead of driving slacks to zero, which keeps the normal matrix factorable."""
START_SLACK = 1e-2
"""Smallest starting slack (scaled units), for an interval of zero width (the start is on a
bound only then)."""
STEP_FRACTION = 0.99
"""Fraction of the longest step that keeps the slacks and multipliers positive."""
POLISH_RHO = 1e6
"""Penalty of the polish (scaled units: the largest entry of H is 1)."""

C_SOLVER = (
    r"""/* the model-predictive law's QP: slip_mpc_qp.solve_moves in the same operations (selects
 * written as numba's min and max; no library call) */
#define CT_QP_N 5
static double ct_qp_min(double a, double b) { return b < a ? b : a; }
static double ct_qp_max(double a, double b) { return b > a ? b : a; }
static double ct_qp_abs(double x) { return x < 0.0 ? -x : x; }
static double ct_qp_clamp(double x, double lo, double hi)
{
    return ct_qp_min(ct_qp_max(x, lo), hi);
}
static double ct_qp_longest_step(double x, double dx, double a)
{
    return ct_qp_min(a, dx < 0.0 ? -x / dx : a);
}
/* the variables row `row` of C = [I; L] sums, first .. last */
static void ct_qp_span(int row, int n, int *first, int *last)
{
    *first = row < n ? row : 0;
    *last = row < n ? row : row - n;
}
static double ct_qp_row_value(int row, int n, const double *z)
{
    int first, last, m;
    double s = 0.0;
    ct_qp_span(row, n, &first, &last);
    for (m = first; m <= last; m++) s += z[m];
    return s;
}
/* out = (H + sum_r w_r C_r' C_r)^-1 (base - sum_r C_r' rows_rhs_r), by L D L'; each entry
 * sums its rows in row order (row a of I, then the rows n + t, t >= a, of L), as the loop over
 * the rows does */
static void ct_qp_weighted_solve(int n, double h[][CT_QP_N], const double *w,
                                 const double *rows_rhs, const double *base, double *out)
{
    double k[CT_QP_N][CT_QP_N], r[CT_QP_N][CT_QP_N], rhs[CT_QP_N], y[CT_QP_N], d, s;
    int a, b, t, i, j, m;
    for (a = 0; a < n; a++) {
        s = base[a] - rows_rhs[a];
        for (t = a; t < n; t++) s -= rows_rhs[n + t];
        rhs[a] = s;
        for (b = 0; b < n; b++) {
            s = h[a][b];
            if (a == b) s += w[a];
            for (t = a > b ? a : b; t < n; t++) s += w[n + t];
            k[a][b] = s;
        }
    }
    for (j = 0; j < n; j++) {
        d = k[j][j];
        for (i = 0; i < j; i++) d -= r[i][j] * r[i][j] * r[i][i];
        r[j][j] = d;
        for (i = j + 1; i < n; i++) {
            s = k[j][i];
            for (m = 0; m < j; m++) s -= r[m][j] * r[m][i] * r[m][m];
            r[j][i] = s / d;
        }
    }
    for (i = 0; i < n; i++) {
        s = rhs[i];
        for (m = 0; m < i; m++) s -= r[m][i] * y[m];
        y[i] = s;
    }
    for (i = n - 1; i >= 0; i--) {
        s = y[i] / r[i][i];
        for (m = i + 1; m < n; m++) s -= r[i][m] * out[m];
        out[i] = s;
    }
}
static void ct_qp_solve_moves(int n, double h[][CT_QP_N], const double *f,
                              const double *move_lo, const double *move_hi, double q0,
                              double q_max, double *z)
{
    double hs[CT_QP_N][CT_QP_N], fs[CT_QP_N], base[CT_QP_N], dx[CT_QP_N], x[CT_QP_N];
    double lo[2 * CT_QP_N], hi[2 * CT_QP_N], su[2 * CT_QP_N], sl[2 * CT_QP_N];
    double lu[2 * CT_QP_N], ll[2 * CT_QP_N], dsu[2 * CT_QP_N], dsl[2 * CT_QP_N];
    double dlu[2 * CT_QP_N], dll[2 * CT_QP_N], tu[2 * CT_QP_N], tl[2 * CT_QP_N];
    double cx[2 * CT_QP_N], w[2 * CT_QP_N], rows_rhs[2 * CT_QP_N], nu[2 * CT_QP_N];
    double bound[2 * CT_QP_N];
    double scale = 1e-300, hmax = 0.0, middle, reached, mu0, mu, step, s, wu, wl, rpu, rpl;
    double cd, mu_aff, ratio, target, q;
    int m = 2 * n, j, k, a, b, row, it, phase, first, last, up, down;
    for (j = 0; j < n; j++) {
        scale = ct_qp_max(ct_qp_max(scale, ct_qp_abs(move_lo[j])), ct_qp_abs(move_hi[j]));
        for (k = 0; k < n; k++) hmax = ct_qp_max(hmax, ct_qp_abs(h[j][k]));
    }
    for (j = 0; j < n; j++) {
        fs[j] = f[j] * (1.0 / (hmax * scale));
        for (k = 0; k < n; k++) hs[j][k] = h[j][k] * (1.0 / hmax);
    }
    for (j = 0; j < n; j++) {
        lo[j] = move_lo[j] / scale;
        hi[j] = move_hi[j] / scale;
        lo[n + j] = -q0 / scale;
        hi[n + j] = (q_max - q0) / scale;
    }
    middle = 0.5 * (lo[n] + hi[n]);
    reached = 0.0;
    for (j = 0; j < n; j++) {
        x[j] = ct_qp_clamp(0.5 * (middle - reached), 0.5 * lo[j], 0.5 * hi[j]);
        reached += x[j];
    }
    mu0 = 1.0;
    for (j = 0; j < n; j++) mu0 = ct_qp_max(mu0, ct_qp_abs(fs[j]));
    for (row = 0; row < m; row++) {
        cx[row] = ct_qp_row_value(row, n, x);
        su[row] = ct_qp_max(hi[row] - cx[row], CT_QP_START_SLACK);
        sl[row] = ct_qp_max(cx[row] - lo[row], CT_QP_START_SLACK);
        lu[row] = mu0 / su[row];
        ll[row] = mu0 / sl[row];
    }
    for (it = 0; it < CT_QP_ITERATIONS; it++) {
        for (a = 0; a < n; a++) {
            s = fs[a];
            for (b = 0; b < n; b++) s += hs[a][b] * x[b];
            base[a] = -s;
        }
        mu = 0.0;
        for (row = 0; row < m; row++) {
            cx[row] = ct_qp_row_value(row, n, x);
            ct_qp_span(row, n, &first, &last);
            for (a = first; a <= last; a++) base[a] -= lu[row] - ll[row];
            mu += su[row] * lu[row] + sl[row] * ll[row];
            tu[row] = -su[row] * lu[row];
            tl[row] = -sl[row] * ll[row];
        }
        mu /= 2 * m;
        step = 1.0;
        for (phase = 0; phase < 2; phase++) {
            for (row = 0; row < m; row++) {
                wu = lu[row] / su[row];
                wl = ll[row] / sl[row];
                rpu = cx[row] + su[row] - hi[row];
                rpl = lo[row] - cx[row] + sl[row];
                w[row] = wu + wl;
                rows_rhs[row] = tu[row] / su[row] + wu * rpu - tl[row] / sl[row] - wl * rpl;
            }
            ct_qp_weighted_solve(n, hs, w, rows_rhs, base, dx);
            step = 1.0;
            for (row = 0; row < m; row++) {
                cd = ct_qp_row_value(row, n, dx);
                dsu[row] = -(cx[row] + su[row] - hi[row]) - cd;
                dsl[row] = -(lo[row] - cx[row] + sl[row]) + cd;
                dlu[row] = (tu[row] - lu[row] * dsu[row]) / su[row];
                dll[row] = (tl[row] - ll[row] * dsl[row]) / sl[row];
                step = ct_qp_longest_step(su[row], dsu[row], step);
                step = ct_qp_longest_step(sl[row], dsl[row], step);
                step = ct_qp_longest_step(lu[row], dlu[row], step);
                step = ct_qp_longest_step(ll[row], dll[row], step);
            }
            if (phase == 0) {
                mu_aff = 0.0;
                for (row = 0; row < m; row++) {
                    mu_aff += (su[row] + step * dsu[row]) * (lu[row] + step * dlu[row]);
                    mu_aff += (sl[row] + step * dsl[row]) * (ll[row] + step * dll[row]);
                }
                ratio = mu_aff / (2 * m * mu);
                target = ratio * ratio * ratio * mu + CT_QP_MU_FLOOR;
                for (row = 0; row < m; row++) {
                    tu[row] += target - dsu[row] * dlu[row];
                    tl[row] += target - dsl[row] * dll[row];
                }
            }
        }
        step *= CT_QP_STEP_FRACTION;
        for (j = 0; j < n; j++) x[j] += step * dx[j];
        for (row = 0; row < m; row++) {
            su[row] += step * dsu[row];
            sl[row] += step * dsl[row];
            lu[row] += step * dlu[row];
            ll[row] += step * dll[row];
        }
    }
    for (row = 0; row < m; row++) {
        up = lu[row] > su[row];
        down = ll[row] > sl[row];
        w[row] = (up | down) ? CT_QP_POLISH_RHO : 0.0;
        bound[row] = up ? hi[row] : lo[row];
        nu[row] = lu[row] - ll[row];
    }
    for (it = 0; it < CT_QP_POLISH_STEPS; it++) {
        for (a = 0; a < n; a++) base[a] = -fs[a];
        for (row = 0; row < m; row++)
            rows_rhs[row] = w[row] * (nu[row] / CT_QP_POLISH_RHO - bound[row]);
        ct_qp_weighted_solve(n, hs, w, rows_rhs, base, x);
        for (row = 0; row < m; row++)
            nu[row] += w[row] * (ct_qp_row_value(row, n, x) - bound[row]);
    }
    for (j = 0; j < n; j++) z[j] = x[j] * scale;
    q = q0;
    for (j = 0; j < n; j++) {
        z[j] = ct_qp_clamp(z[j], ct_qp_max(move_lo[j], -q), ct_qp_min(move_hi[j], q_max - q));
        q += z[j];
    }
}
""".replace("CT_QP_START_SLACK", repr(START_SLACK))
    .replace("CT_QP_MU_FLOOR", repr(MU_FLOOR))
    .replace("CT_QP_STEP_FRACTION", repr(STEP_FRACTION))
    .replace("CT_QP_POLISH_RHO", repr(POLISH_RHO))
    .replace("CT_QP_POLISH_STEPS", repr(POLISH_STEPS))
    .replace("CT_QP_ITERATIONS", repr(IPM_ITERATIONS))
    .replace("CT_QP_N 5", f"CT_QP_N {MAX_HORIZON}")
)
"""`solve_moves` with IPM_ITERATIONS and POLISH_STEPS in C (n <= MAX_HORIZON), operation by
operation, so that a C build without FMA contraction gives the same bits."""
