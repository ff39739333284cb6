"""ABS figures: `abs_sims_per_s`, `abs_max_rel_err`, `abs_speedup_vs_solve_ivp` (DESIGN 8).

Population: 50 gain triples 10 ** U(log10 lo, log10 hi) with (lo, hi) = (10, 3162), (1, 1000),
(0.01, 10) for kp, ki, kd from make_rng(12345); preset paper-derlsp-ao, PID, dry concrete,
simulated to v_stop on one core. The baseline is what a Python user writes today: the same closed
loop as a scipy `solve_ivp` RK45 right-hand side (max_step 1e-3, terminal event at v_stop).
"""

from __future__ import annotations

import numpy as np

from chassistune._rng import make_rng
from chassistune.perf.timing import best_time
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario


def bench_population() -> np.ndarray:
    """The 50 (kp, ki, kd) rows of DESIGN 8."""
    rng = make_rng(12345)
    lo = np.log10([10.0, 1.0, 0.01])
    hi = np.log10([3162.0, 1000.0, 10.0])
    return np.asarray(10 ** rng.uniform(lo, hi, (50, 3)))


def solve_ivp_run(scenario: AbsWheelScenario, gains: np.ndarray) -> tuple[float, float]:
    """(stop distance, slip ITAE) of one PID run with scipy's RK45, the baseline."""
    from scipy.integrate import solve_ivp

    pp = scenario.plant_params
    kp, ki, kd = (float(g) for g in gains)
    tire = scenario.tire
    target = scenario.target_slip
    nf = scenario.controller_params["n_filter"]

    def rhs(t: float, y: np.ndarray) -> list[float]:
        v, w, q, r, z, xf, _x, _itae = y
        s = min(max((v - w * pp.wheel_radius_m) / v, 0.0), 1.0)
        e = target - s
        fx = float(tire.mu(s)) * pp.load_fraction * pp.mass_kg * pp.g_m_s2
        dw = (pp.wheel_radius_m * fx - pp.brake_gain * q) / pp.wheel_inertia_kg_m2
        if w <= 0.0 and dw < 0.0:
            dw = 0.0
        u = kp * e + ki * z + kd * nf * (e - xf)
        dq = 0.0 if (q >= pp.q_max and r > 0) or (q <= 0 and r < 0) else r
        dz = 0.0 if (q >= pp.q_max and e > 0) or (q <= 0 and e < 0) else e
        return [-fx / pp.mass_kg, dw, dq, (pp.actuator_gain * u - r) / pp.actuator_tau_s, dz,
                nf * (e - xf), v, t * abs(e)]

    def stopped(t: float, y: np.ndarray) -> float:
        return float(y[0] - pp.v_stop_m_s)

    stopped.terminal = True  # type: ignore[attr-defined]
    y0 = [pp.v0_m_s, pp.v0_m_s / pp.wheel_radius_m, 0.0, 0.0, 0.0, target, 0.0, 0.0]
    sol = solve_ivp(rhs, (0.0, pp.t_max_s), y0, method="RK45", max_step=1e-3, events=stopped)
    return float(sol.y[6, -1]), float(sol.y[7, -1])


def figures(quick: bool = False) -> dict[str, float]:
    """Measure the three ABS figures in this run."""
    gains = bench_population()
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    sc.raw(gains[:2], workers=1)  # compile / load the cache outside the timing
    t_kernel = best_time(lambda: sc.raw(gains, workers=1), 3 if quick else 7)
    sims_per_s = len(gains) / t_kernel
    ref = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid",
                         {"dt_s": sc.plant_params.dt_s / 100}).raw(gains)
    ours = sc.raw(gains, workers=1)
    errs = []
    for col in ("stop_distance_m", "slip_itae"):
        from chassistune.scenarios.abs_wheel import METRIC_COLUMNS

        c = METRIC_COLUMNS[col]
        errs.append(np.max(np.abs(ours[:, c] - ref[:, c]) / np.abs(ref[:, c])))
    subset = gains[: 2 if quick else 5]
    t_ivp = best_time(lambda: [solve_ivp_run(sc, g) for g in subset], 1) / len(subset)
    return {
        "abs_sims_per_s": sims_per_s,
        "abs_max_rel_err": float(max(errs)),
        "abs_speedup_vs_solve_ivp": sims_per_s * t_ivp,
        "abs_solve_ivp_sims_per_s": 1.0 / t_ivp,
    }
