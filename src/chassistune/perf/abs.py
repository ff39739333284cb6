"""ABS figures (design.md 8): speed, accuracy over presets and the tuning box, speed of the fuzzy
controllers (the cost per candidate-step against the population size: `perf.scaling`).

Population (`bench_population`): 50 gain triples 10 ** U(log10 lo, log10 hi) with (lo, hi) =
(10, 3162), (1, 1000), (0.01, 10) for kp, ki, kd from make_rng(12345); preset
paper-derlsp-ao, PID, dry concrete, simulated to v_stop on one core. Speeds are best-of-n wall
times (`*_sims_per_s`) and, since the machine is shared, also thread CPU times (`*_cpu`); every
ratio is measured in the same run. Baseline: scipy `solve_ivp` RK45 (max_step 1e-3, terminal
event at v_stop), what a Python user writes today.

Accuracy: relative error of stop distance and slip ITAE against the same run at dt/100, over the
runs that stop at both steps (`abs_max_rel_err`: the population above; `_presets`: the PID with
its default gains and the population on every paper preset and road at the preset's default
step, not the car wheels, whose step docs/cars.md checks against dt/4; `_box`: 200 gain
vectors uniform in the PID's tuning bounds on each preset's first road).

Conditioning. Some chattering candidates are chaotic: their slip ITAE is not determined by the
inputs to the accuracy asked for (gains perturbed by 1e-14 relative move it by 2.3 % for the
default PID on paper-derlsp-ao/ice and 37 % for kp, ki, kd = 1551, 5145, 92 on sldemo at 1 ms,
still 1 % and 20 % at 0.1 ms, and the fixed-step values wander without converging down to
2e-6 s). No step makes such a figure accurate, so each reference run is repeated twice: with the
gains scaled by 1 + 1e-12, and at twice its step (dt/50). A candidate whose reference moves by
more than COND_TOL under either is ill-conditioned: its reference is not determined, so its
error cannot be measured (on sldemo, five box candidates that pass the first test keep a 1-5 %
error against dt/100 at every step from dt down to dt/25, without converging); `*_conditioned`
is the worst error over the others and `abs_ill_conditioned_*` counts them (the plain
`abs_max_rel_err_*` keeps every stopped run).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable

import numpy as np

from chassistune._rng import make_rng
from chassistune.params import ImplausibleValue
from chassistune.perf.timing import best_cpu_time, best_time
from chassistune.plants.abs_wheel import PRESETS
from chassistune.plants.cars import CARS
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario
from chassistune.scenarios.refine import refined_scenario
from chassistune.sim import abs_wheel_layout as KL

ERROR_COLUMNS = ("stop_distance_m", "slip_itae")
COND_TOL = 1e-4
"""Largest relative move of a reference figure under a 1e-12 relative gain perturbation for the
candidate to count as well-conditioned (a tenth of the tightest accuracy target)."""
PERTURBATION = 1e-12


def bench_population() -> np.ndarray:
    """The 50 (kp, ki, kd) rows of design.md 8."""
    rng = make_rng(12345)
    lo = np.log10([10.0, 1.0, 0.01])
    hi = np.log10([3162.0, 1000.0, 10.0])
    return np.asarray(10 ** rng.uniform(lo, hi, (50, 3)))


def box_population(scenario: AbsWheelScenario, n: int, seed: int) -> np.ndarray:
    """n gain rows uniform in the controller's tuning bounds."""
    lo, hi = np.array([(g.lo, g.hi) for g in scenario.controller.gains]).T
    return lo + (hi - lo) * make_rng(seed).random((n, lo.size))


def _rel_change(a: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Per row, the larger relative difference of ERROR_COLUMNS between two metrics matrices."""
    out = np.zeros(len(a))
    for name in ERROR_COLUMNS:
        c = KL.METRICS[name]
        out = np.maximum(out, np.abs(a[:, c] - ref[:, c]) / np.abs(ref[:, c]))
    return out


def rel_errors(
    scenario: AbsWheelScenario, gains: np.ndarray, refine: int = 100, conditioning: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Per candidate, the larger relative error of ERROR_COLUMNS against dt / refine (NaN where
    a run does not stop at both steps) and whether it is ill-conditioned (`conditioning`: the
    reference moves by more than COND_TOL when the gains are scaled by 1 + PERTURBATION or the
    step is doubled: dt / (refine / 2))."""
    with warnings.catch_warnings():  # dt / 100 may lie below the plausible range
        warnings.simplefilter("ignore", ImplausibleValue)
        fine = refined_scenario(scenario, refine, {})
        half = refined_scenario(scenario, refine // 2, {})
    ours, ref = scenario.raw(gains), fine.raw(gains)
    stopped = KL.STATUS_NAMES.index("stopped")
    both = (ours[:, KL.METRICS["status"]] == stopped) & (ref[:, KL.METRICS["status"]] == stopped)
    ill = np.zeros(len(gains), dtype=bool)
    if conditioning:
        moved = np.maximum(
            _rel_change(fine.raw(gains * (1.0 + PERTURBATION)), ref),
            _rel_change(half.raw(gains), ref),
        )
        ill = ~(moved <= COND_TOL)
    return np.where(both, _rel_change(ours, ref), np.nan), ill & both


def preset_errors(box: bool = False) -> dict[str, tuple[float, float, int]]:
    """Per 'preset/road' (see the module docstring): the worst relative error, the worst over
    the well-conditioned candidates and how many are ill-conditioned; box: the tuning-box
    population on each preset's first road."""
    out: dict[str, tuple[float, float, int]] = {}
    for name, preset in PRESETS.items():
        if name in CARS:
            continue
        for road in preset.info.roads[:1] if box else preset.info.roads:
            sc = PLANT.scenario(name, road, "pid")
            if box:
                gains = box_population(sc, 200, 7)
            else:
                default = [[g.default for g in sc.controller.gains]]
                gains = np.vstack([default, bench_population()])
            err, ill = rel_errors(sc, gains, conditioning=True)
            out[f"{name}/{road}"] = (
                float(np.nanmax(err)),
                float(np.nanmax(np.where(ill, np.nan, err))),
                int(ill.sum()),
            )
    return out


def accuracy_figures(box: bool) -> dict[str, float]:
    """abs_max_rel_err_{presets,box}, its `_conditioned` twin and the ill-conditioned count."""
    per = preset_errors(box).values()
    key = "box" if box else "presets"
    return {
        f"abs_max_rel_err_{key}": max(e for e, _, _ in per),
        f"abs_max_rel_err_{key}_conditioned": max(c for _, c, _ in per),
        f"abs_ill_conditioned_{key}": float(sum(n for _, _, n in per)),
    }


def _controller_speed(
    controller: str, repeats: int, params: dict[str, object] | None = None
) -> tuple[float, float]:
    """(wall, cpu) sims/s of 50 gain rows uniform in the controller's bounds (dry concrete),
    with the controller's parameters `params`."""
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", controller, params or {})
    gains = box_population(sc, 50, 12345)
    sc.raw(gains[:2], workers=1)
    wall = best_time(lambda: sc.raw(gains, workers=1), repeats)
    cpu = best_cpu_time(lambda: sc.raw(gains, workers=1), repeats)
    return len(gains) / wall, len(gains) / cpu


def pid_closed_loop(
    scenario: AbsWheelScenario,
    gains: np.ndarray,
    mu_of_slip: Callable[[float], float] | None = None,
) -> tuple[Callable[[float, np.ndarray], list[float]], list[float], Callable[..., float]]:
    """(rhs, y0, stop event) of the single wheel's PID closed loop (design.md 3.1) for scipy's
    solve_ivp, states (v, w, q, r, z, xf, distance, slip ITAE); `mu_of_slip` the tire's mu(S)
    (default: the scenario's curve)."""
    pp = scenario.plant_params
    kp, ki, kd = (float(g) for g in gains)
    mu = scenario.tire.mu if mu_of_slip is None else mu_of_slip
    target = scenario.target_slip
    nf = scenario.controller_params["n_filter"]

    def rhs(t: float, y: np.ndarray) -> list[float]:
        v, w, q, r, z, xf, _x, _itae = y
        s = min(max((v - w * pp.wheel_radius_m) / v, 0.0), 1.0)
        e = target - s
        fx = float(mu(s)) * pp.load_fraction * pp.mass_kg * pp.g_m_s2
        dw = (pp.wheel_radius_m * fx - pp.brake_gain * q) / pp.wheel_inertia_kg_m2
        if w <= 0.0 and dw < 0.0:
            dw = 0.0
        u = kp * e + ki * z + kd * nf * (e - xf)
        dq = 0.0 if (q >= pp.q_max and r > 0) or (q <= 0 and r < 0) else r
        dz = 0.0 if (q >= pp.q_max and e > 0) or (q <= 0 and e < 0) else e
        return [
            -fx / pp.mass_kg,
            dw,
            dq,
            (pp.actuator_gain * u - r) / pp.actuator_tau_s,
            dz,
            nf * (e - xf),
            v,
            t * abs(e),
        ]

    def stopped(t: float, y: np.ndarray) -> float:
        return float(y[0] - pp.v_stop_m_s)

    stopped.terminal = True  # type: ignore[attr-defined]
    y0 = [pp.v0_m_s, pp.v0_m_s / pp.wheel_radius_m, 0.0, 0.0, 0.0, target, 0.0, 0.0]
    return rhs, y0, stopped


def solve_ivp_run(scenario: AbsWheelScenario, gains: np.ndarray) -> tuple[float, float]:
    """(stop distance, slip ITAE) of one PID run with scipy's RK45, the baseline."""
    from scipy.integrate import solve_ivp

    rhs, y0, stopped = pid_closed_loop(scenario, gains)
    t_end = scenario.plant_params.t_max_s
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="RK45", max_step=1e-3, events=stopped)
    return float(sol.y[6, -1]), float(sol.y[7, -1])


def figures(quick: bool = False) -> dict[str, float]:
    """Measure the ABS figures in this run."""
    repeats = 3 if quick else 7
    gains = bench_population()
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    sc.raw(gains[:2], workers=1)  # compile / load the cache outside the timing
    sims_per_s = len(gains) / best_time(lambda: sc.raw(gains, workers=1), repeats)
    cpu = len(gains) / best_cpu_time(lambda: sc.raw(gains, workers=1), repeats)
    subset = gains[: 2 if quick else 5]
    t_ivp = best_time(lambda: [solve_ivp_run(sc, g) for g in subset], 1) / len(subset)
    fuzzy_wall, fuzzy_cpu = _controller_speed("fuzzy-pid", repeats)
    immune_wall, immune_cpu = _controller_speed("fuzzy-immune-pid", repeats)
    mpc_wall, mpc_cpu = _controller_speed("mpc", repeats)
    mpc3_wall, mpc3_cpu = _controller_speed("mpc", repeats, {"horizon": 3})
    return {
        "abs_sims_per_s": sims_per_s,
        "abs_sims_per_s_cpu": cpu,
        "abs_max_rel_err": float(np.nanmax(rel_errors(sc, gains)[0])),
        **accuracy_figures(box=False),
        **accuracy_figures(box=True),
        "abs_speedup_vs_solve_ivp": sims_per_s * t_ivp,
        "abs_solve_ivp_sims_per_s": 1.0 / t_ivp,
        "abs_fuzzy_pid_sims_per_s": fuzzy_wall,
        "abs_fuzzy_pid_sims_per_s_cpu": fuzzy_cpu,
        "abs_immune_sims_per_s": immune_wall,
        "abs_immune_sims_per_s_cpu": immune_cpu,
        "abs_mpc_sims_per_s": mpc_wall,
        "abs_mpc_sims_per_s_cpu": mpc_cpu,
        "abs_mpc_horizon3_sims_per_s": mpc3_wall,
        "abs_mpc_horizon3_sims_per_s_cpu": mpc3_cpu,
    }
