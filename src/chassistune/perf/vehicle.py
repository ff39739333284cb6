"""Vehicle ABS figures: `vehicle_sims_per_s`, `vehicle_speedup_vs_solve_ivp`,
`vehicle_split_mu_sims_per_s`, `vehicle_driver_sims_per_s` (design.md 8).

Population: 50 fuzzy-PID gain vectors drawn uniformly within the vehicle catalogue's tuning bounds
by default_rng(12345); preset paper-deffao, dry concrete, four wheels, simulated to v_stop on one
core. The baseline is what a Python user writes today: the same 7-DOF model (loads solved by
fixed-point iteration, the combined-slip tire, four actuators and PID laws whose gains the fuzzy
surface schedules continuously) as a scipy `solve_ivp` RK45 right-hand side, max_step 1e-3,
terminal event at v_stop.

The general path's figures: the PID on split-mu with the steering fixed and with the driver, 50
gain vectors drawn the same way from the PID's bounds, one core (every step of these runs is the
kernel's general pass: yaw, lateral slip, the loads by Newton's method).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from chassistune.perf.timing import best_time
from chassistune.plants.abs_vehicle import geometry
from chassistune.scenarios.abs_vehicle import PLANT, AbsVehicleScenario


def bench_population(scenario: AbsVehicleScenario) -> np.ndarray:
    """The 50 gain rows of design.md 8, uniform in the controller's tuning bounds."""
    box = np.array(scenario.controller.bounds())
    return np.random.default_rng(12345).uniform(box[:, 0], box[:, 1], (50, len(box)))


SPLIT_MU_CASES = {
    "vehicle_split_mu_sims_per_s": {"steering": "fixed"},
    "vehicle_driver_sims_per_s": {"steering": "driver"},
}
"""The general path's figures: their split-mu overrides (the PID, paper-deffao)."""


def sims_per_s(scenario: AbsVehicleScenario, repeats: int) -> float:
    """Simulations per second of the scenario's `bench_population` on one core (best of
    `repeats`, compile and cache load outside the timing)."""
    gains = bench_population(scenario)
    scenario.raw(gains[:2], workers=1)
    return len(gains) / best_time(lambda: scenario.raw(gains, workers=1), repeats)


def reference_rhs(
    scenario: AbsVehicleScenario, gains: np.ndarray
) -> Callable[[float, np.ndarray], np.ndarray]:
    """The closed loop's right-hand side in plain Python (straight steering, no driver).

    State: vx, vy, r, X, Y, psi, then per wheel w, q, qrate, z, xf (wheel-major), then the CG
    path length; with relaxation lengths (`lagged_states`), then the four wheels' lagged slips
    s' = -kappa' and tan(alpha') (docs/tires.md, "Transient slip on the vehicle"). Fuzzy PID
    (gains ke, kec, ku_p, ku_i, ku_d, kp0, ki0, kd0) or PID (kp, ki, kd).
    """
    from chassistune.fuzzy.surface import surface_lookup
    from chassistune.plants.magic_formula import lateral_force_n, longitudinal_force_n

    pp = scenario.plant_params
    geo = geometry(pp)
    xs, ys, fz0, ca, cb = geo
    road = scenario.road_spec
    surf = [(t.slip_opt, t.mu_peak, t.mu_lock) for t in road.surfaces]
    side = [0, 1, 0, 1] if road.kind == 2 else [0, 0, 0, 0]
    stiff = pp.cornering_stiffness_n_rad
    nf = float(scenario.controller_params.get("n_filter", 100.0))
    table = scenario.fuzzy_surface
    fuzzy = len(gains) == 8
    out = np.zeros(3)
    mf = scenario.tire
    mf_coefficients = [t.kernel_array() for t in mf.surfaces] if mf is not None else []

    def mf_tire(
        kappa: float, tan_alpha: float, fz: float, k: int, right: bool
    ) -> tuple[float, float]:
        # the TIR file's tyre on the left wheels, its mirror image on the right ones (ISO-W)
        c = mf_coefficients[k]
        a = -tan_alpha if right else tan_alpha
        fx = longitudinal_force_n(c, kappa, a, fz) if fz > 0.0 else 0.0
        fy = lateral_force_n(c, kappa, a, fz) if fz > 0.0 else 0.0
        return fx, -fy if right else fy

    def mu_of(s: float, k: int) -> float:
        st, h, g = surf[k]
        return h * s / st if s <= st else (h - g * st) / (1 - st) - (h - g) * s / (1 - st)

    def tire(sx: float, vr: float, fz: float, k: int) -> tuple[float, float]:
        if fz <= 0.0:
            return 0.0, 0.0
        st, h, _ = surf[k]
        sy = vr * stiff * st / (h * fz)
        s = math.hypot(sx, sy)
        if s == 0.0:
            return 0.0, 0.0
        f = fz * mu_of(min(s, 1.0), k)
        return -f * sx / s, -f * sy / s

    sigma_x, sigma_y = pp.relaxation_length_m, pp.lateral_relaxation_length_m
    lagged = lagged_states(scenario) > 0

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        vx, vy, r, _x, _y, psi = y[:6]
        wheel = y[6:26].reshape(4, 5)
        sx = np.zeros(4)
        vr = np.zeros(4)
        tire_sx = np.zeros(4)
        tire_vr = np.zeros(4)
        slips = []
        dy = np.zeros_like(y)
        for j in range(4):
            u, v = vx - r * ys[j], vy + r * xs[j]
            vabs = max(math.hypot(u, v), pp.min_speed_m_s)
            slip_speed = u - max(wheel[j, 0], 0.0) * pp.wheel_radius_m
            sx[j] = slip_speed / vabs
            vr[j] = v / vabs
            s_tire, t_tire = slip_speed / abs(u), v / abs(u)
            if lagged:  # the lag: sigma ds'/dt = (u - w R) - |u| s', sigma dt'/dt = v - |u| t'
                s_lag, t_lag = y[27 + j], y[31 + j]
                if sigma_x > 0.0:
                    dy[27 + j] = (slip_speed - abs(u) * s_lag) / sigma_x
                    s_tire = s_lag
                if sigma_y > 0.0:
                    dy[31 + j] = (v - abs(u) * t_lag) / sigma_y
                    t_tire = t_lag
            slips.append((-s_tire, t_tire))
            cos = 1.0 / math.hypot(1.0, t_tire) if lagged else 1.0
            tire_sx[j] = s_tire * cos if lagged else sx[j]
            tire_vr[j] = t_tire * cos if lagged else vr[j]
        ax = ay = 0.0
        for _ in range(200):  # the load/force loop, by fixed-point iteration
            fz = np.maximum(fz0 + ca * ax + cb * ay, 0.0)
            if mf is None:
                forces = [tire(tire_sx[j], tire_vr[j], fz[j], side[j]) for j in range(4)]
            else:
                forces = [mf_tire(*slips[j], fz[j], side[j], j % 2 == 1) for j in range(4)]
            new_ax = sum(f[0] for f in forces) / pp.mass_kg
            new_ay = sum(f[1] for f in forces) / pp.mass_kg
            done = abs(new_ax - ax) + abs(new_ay - ay) < 1e-12
            ax, ay = new_ax, new_ay
            if done:
                break
        mz = sum(xs[j] * forces[j][1] - ys[j] * forces[j][0] for j in range(4))
        dy[0] = ax + vy * r
        dy[1] = ay - vx * r
        dy[2] = mz / pp.yaw_inertia_kg_m2
        dy[3] = vx * math.cos(psi) - vy * math.sin(psi)
        dy[4] = vx * math.sin(psi) + vy * math.cos(psi)
        dy[5] = r
        for j in range(4):
            w, q, qr, z, xf = wheel[j]
            e = road.surfaces[side[j]].slip_opt - min(max(sx[j], 0.0), 1.0)
            if fuzzy:
                g = gains
                surface_lookup(table, g[0] * e, g[1] * nf * (e - xf), out)
                kp, ki, kd = g[5] + g[2] * out[0], g[6] + g[3] * out[1], g[7] + g[4] * out[2]
            else:
                kp, ki, kd = gains
            axle_share = pp.front_brake_share if j < 2 else 1.0 - pp.front_brake_share
            tb = 2.0 * axle_share * pp.brake_gain * q
            dw = (-pp.wheel_radius_m * forces[j][0] - tb) / pp.wheel_inertia_kg_m2
            u_cmd = kp * e + ki * z + kd * nf * (e - xf)
            hi, lo = q >= pp.q_max, q <= 0.0
            dy[6 + 5 * j : 11 + 5 * j] = (
                0.0 if (w <= 0.0 and dw < 0.0) else dw,
                0.0 if (hi and qr > 0.0) or (lo and qr < 0.0) else qr,
                (pp.actuator_gain * u_cmd - qr) / pp.actuator_tau_s,
                0.0 if (hi and e > 0.0) or (lo and e < 0.0) else e,
                nf * (e - xf),
            )
        dy[26] = math.hypot(vx, vy)
        return dy

    return rhs


def lagged_states(scenario: AbsVehicleScenario) -> int:
    """The reference's lagged-slip states: 8 with a relaxation length, else none."""
    return 8 if scenario.lagged else 0


def reference_solution(scenario: AbsVehicleScenario, gains: np.ndarray, **options: float) -> object:
    """scipy `solve_ivp` (RK45, max_step 1e-3 unless `options` say otherwise) of the reference
    right-hand side from the kernel's initial state, to v_stop or t_max."""
    from scipy.integrate import solve_ivp

    pp = scenario.plant_params
    y0 = np.zeros(27 + lagged_states(scenario))  # the lagged slips start at the kinematic 0
    y0[0] = pp.v0_m_s
    road = scenario.road_spec
    for j in range(4):
        y0[6 + 5 * j] = pp.v0_m_s / pp.wheel_radius_m
        y0[10 + 5 * j] = road.surfaces[1 if road.kind == 2 and j % 2 else 0].slip_opt  # e(0)

    def stopped(t: float, y: np.ndarray) -> float:
        return math.hypot(y[0], y[1]) - pp.v_stop_m_s

    stopped.terminal = True  # type: ignore[attr-defined]
    return solve_ivp(
        reference_rhs(scenario, gains),
        (0.0, pp.t_max_s),
        y0,
        method="RK45",
        events=stopped,
        **{"max_step": 1e-3, **options},
    )


def solve_ivp_run(scenario: AbsVehicleScenario, gains: np.ndarray) -> tuple[float, float]:
    """(stop distance, stop time) of one run with scipy's RK45, the baseline."""
    sol = reference_solution(scenario, gains)
    return float(sol.y[26, -1]), float(sol.t[-1])  # type: ignore[attr-defined]


def figures(quick: bool = False) -> dict[str, float]:
    """Measure the vehicle figures in this run."""
    sc = PLANT.scenario("paper-deffao", "dry-concrete", "fuzzy-pid")
    gains = bench_population(sc)
    sims = sims_per_s(sc, 3 if quick else 5)
    general = {
        name: sims_per_s(PLANT.scenario("paper-deffao", "split-mu", "pid", overrides), 3)
        for name, overrides in SPLIT_MU_CASES.items()
    }
    subset = gains[: 1 if quick else 3]
    t_ivp = best_time(lambda: [solve_ivp_run(sc, g) for g in subset], 1) / len(subset)
    return {
        "vehicle_sims_per_s": sims,
        "vehicle_speedup_vs_solve_ivp": sims * t_ivp,
        "vehicle_solve_ivp_sims_per_s": 1.0 / t_ivp,
        **general,
    }
