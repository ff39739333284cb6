"""How the cost grows (`chassistune bench`'s last area, alone with `--only scaling`).

- Thread CPU ns per candidate-step on one core against the population (1, 10, 50, 200, 1000):
  the single-wheel PID (the bench population of `perf.abs`, paper-derlsp-ao, dry concrete),
  the 7-DOF vehicle (the fuzzy PID and
  population of `perf.vehicle`, paper-deffao) on its straight path (dry concrete) and on its
  general path (split-mu with the steering fixed, and with the counter-steering driver), and the
  quarter car (the PID of `perf.suspension`, paper-iabc, iso-b, 10 s at 1 ms). Steps: stop time /
  dt per candidate for the ABS models, duration / dt for the quarter car. Best of 7 timed runs
  below a population of 200 and of 3 from 200 (`quick`: 3 and 1); the general path once from
  200 (each run takes seconds).
- A tuning run (DERLSP-AO on the wheel's PID, dry concrete, seed 0, both cores) against the
  population at 100 iterations and against the iterations at population 50: wall time and the
  process's CPU time (both threads).
`plot` draws both curves from the figures.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable

import numpy as np

from chassistune.perf import abs as abs_perf
from chassistune.perf import suspension, vehicle
from chassistune.perf.timing import best_cpu_time
from chassistune.scenarios.abs_vehicle import PLANT as VEHICLE
from chassistune.scenarios.abs_vehicle import AbsVehicleScenario
from chassistune.scenarios.abs_wheel import PLANT as WHEEL
from chassistune.scenarios.abs_wheel import AbsWheelScenario
from chassistune.scenarios.quarter_car import PLANT as QUARTER_CAR
from chassistune.sim import abs_vehicle_kernel as VK
from chassistune.sim import abs_wheel_layout as KL
from chassistune.tuning.tune import tune

POPULATIONS = (1, 10, 50, 200, 1000)
TUNE_POPULATIONS = (10, 50, 200, 1000)
TUNE_ITERATIONS = (50, 100, 200, 500)
VEHICLE_PATHS = {
    "vehicle_straight": ("dry-concrete", {}),
    "vehicle_split_mu": ("split-mu", {"steering": "fixed"}),
    "vehicle_split_mu_driver": ("split-mu", {"steering": "driver"}),
}
"""The vehicle's curves: road and overrides (the last two run on the kernel's general path)."""
MODELS = ("abs_wheel", *VEHICLE_PATHS, "quarter_car")
NAME = re.compile(r"scaling_(\w+?)_ns_per_candidate_step_pop_(\d+)")
TUNE_NAME = re.compile(r"scaling_tune_(wall|cpu)_s_pop_(\d+)_iter_(\d+)")


def _repeats(n: int, quick: bool, slow: bool = False) -> int:
    """Timed runs at population n (see the module docstring; `slow`: the general path)."""
    if n >= 200:
        return 1 if quick or slow else 3
    return 3 if quick else 7


def _ns_per_step(
    run: Callable[[np.ndarray], object], gains: np.ndarray, steps: float, repeats: int
) -> float:
    """Best thread CPU ns per candidate-step of run(gains) that takes `steps` steps in all."""
    run(gains[:1])  # compile / load the cache outside the timing
    return 1e9 * best_cpu_time(lambda: run(gains), repeats) / steps


def _stop_costs(
    sc: AbsWheelScenario | AbsVehicleScenario,
    base: np.ndarray,
    stop_col: int,
    quick: bool,
    slow: bool = False,
) -> dict[int, float]:
    """ns per candidate-step of an ABS scenario run to v_stop on the `base` gain rows tiled to
    each population."""
    out = {}
    for n in POPULATIONS:
        gains = np.resize(base, (n, base.shape[1]))
        t_stop = sc.raw(gains, workers=1)[:, stop_col]
        out[n] = _ns_per_step(
            lambda g: sc.raw(g, workers=1),
            gains,
            float(np.sum(t_stop)) / sc.plant_params.dt_s,
            _repeats(n, quick, slow),
        )
    return out


def wheel_costs(quick: bool) -> dict[int, float]:
    """ns per candidate-step of the single wheel's PID against the population."""
    sc = WHEEL.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    return _stop_costs(sc, abs_perf.bench_population(), KL.METRICS["stop_time_s"], quick)


def vehicle_costs(path: str, quick: bool) -> dict[int, float]:
    """ns per candidate-step of the vehicle on one of VEHICLE_PATHS against the population."""
    road, overrides = VEHICLE_PATHS[path]
    sc = VEHICLE.scenario("paper-deffao", road, "fuzzy-pid", overrides)
    general = path != "vehicle_straight"
    stop_col = VK.METRIC_LAYOUT["stop_time_s"]
    return _stop_costs(sc, vehicle.bench_population(sc), stop_col, quick, general)


def quarter_car_costs(quick: bool) -> dict[int, float]:
    """ns per candidate-step of the quarter car's simulated objective against the population."""
    sc = QUARTER_CAR.scenario("paper-iabc", "iso-b", "pid", {"duration_s": 10.0})
    out = {}
    for n in POPULATIONS:
        gains = suspension.bench_population(n)
        out[n] = _ns_per_step(
            lambda g: sc.cost(g, "rms-ratio", workers=1),
            gains,
            n * sc.solver.n_steps,
            _repeats(n, quick),
        )
    return out


def tuning_times(pop_size: int, iterations: int) -> tuple[float, float]:
    """(wall s, process CPU s) of one DERLSP-AO tuning run of the wheel's PID."""
    cpu0 = time.process_time()
    res = tune(
        "abs-wheel",
        "pid",
        "derlsp-ao",
        roads="dry-concrete",
        pop_size=pop_size,
        max_iter=iterations,
        seed=0,
    )
    return res.wall_time_s, time.process_time() - cpu0


def figures(quick: bool = False) -> dict[str, float]:
    """The curves as flat figures (`quick`: the per-step costs only)."""
    costs = {
        "abs_wheel": wheel_costs(quick),
        **{path: vehicle_costs(path, quick) for path in VEHICLE_PATHS},
        "quarter_car": quarter_car_costs(quick),
    }
    out = {
        f"scaling_{model}_ns_per_candidate_step_pop_{n}": ns
        for model, curve in costs.items()
        for n, ns in curve.items()
    }
    if quick:
        return out
    tuning_times(10, 2)  # compile / load the caches outside the timing
    runs = {(p, 100) for p in TUNE_POPULATIONS} | {(50, i) for i in TUNE_ITERATIONS}
    for p, i in sorted(runs):
        wall, cpu = tuning_times(p, i)
        out[f"scaling_tune_wall_s_pop_{p}_iter_{i}"] = wall
        out[f"scaling_tune_cpu_s_pop_{p}_iter_{i}"] = cpu
    return out


def curves(
    figures: dict[str, float],
) -> tuple[dict[str, list[tuple[int, float]]], dict[str, list[tuple[int, float]]]]:
    """From the sweep's figures: ns per candidate-step against population, per model; and the
    tuning run's seconds against population x iterations, per series ('wall: population, 100
    iterations', 'cpu: iterations, N = 50', ...)."""
    per_step = {
        model.replace("_", " "): sorted(
            (int(m.group(2)), v)
            for k, v in figures.items()
            if (m := NAME.fullmatch(k)) and m.group(1) == model
        )
        for model in MODELS
    }
    runs = [
        (m.group(1), int(m.group(2)), int(m.group(3)), v)
        for k, v in figures.items()
        if (m := TUNE_NAME.fullmatch(k))
    ]
    tuning: dict[str, list[tuple[int, float]]] = {}
    for kind in ("wall", "cpu"):
        for label, iters in (("population, 100 iterations", 100), ("iterations, N = 50", None)):
            pts = sorted(
                (p * i, v)
                for c, p, i, v in runs
                if c == kind and (i == iters if iters is not None else p == 50)
            )
            if pts:
                tuning[f"{kind}: {label}"] = pts
    return per_step, tuning
