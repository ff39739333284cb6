"""Robust-tuning figures: the throughput of n candidates x K scenarios.

Population: the first n = 30 rows of the ABS bench population (`perf.abs.bench_population`),
PID on dry concrete, preset paper-derlsp-ao; K = 16 Sobol scenarios of mass 80-120 kg, mu_scale
0.85-1.15, v0 20-35 m/s and actuator tau 7-13 ms (the robust study of docs/robust.md).

- `robust_sims_per_s`: candidate-scenario simulations per second of today's path (one kernel call
  of n rows per scenario, K calls), all cores;
- `robust_one_call_speedup`: on ONE scenario, one call of n K rows against K calls of n rows (the
  same simulations): what per-row plant parameters (one call for the whole n x K batch) would
  save, at one thread and at all cores;
- `robust_validation_sims_per_s`: validation, one scenario built and simulated per draw (N = 300).
"""

from __future__ import annotations

import numpy as np

from chassistune.perf.abs import bench_population
from chassistune.perf.timing import best_time
from chassistune.scenarios.abs_wheel import PLANT
from chassistune.sim.batch import default_workers
from chassistune.tuning.problem import build_problem
from chassistune.tuning.robust.aggregate import Aggregate
from chassistune.tuning.robust.problem import known_for, robust_problem, validation_set
from chassistune.tuning.robust.spec import UncertaintySpec, parse_vary

VARY = ("mass_kg=80:120", "mu_scale=0.85:1.15", "v0_m_s=20:35", "actuator_tau_s=0.007:0.013")
N_CANDIDATES, K_SCENARIOS = 30, 16


def figures(quick: bool = False) -> dict[str, float]:
    """Measure the robust-tuning figures in this run."""
    repeats = 2 if quick else 5
    nominal = build_problem("abs-wheel", "pid", roads=["dry-concrete"])
    spec = UncertaintySpec(
        parse_vary(list(VARY), known_for(nominal)),
        K_SCENARIOS,
        "sobol",
        Aggregate("max"),
        validate=300,
    )
    rp = robust_problem(nominal, spec, seed=0)
    gains = bench_population()[:N_CANDIDATES]
    rp(gains[:2])  # compile / load the cache outside the timing
    n_k = N_CANDIDATES * K_SCENARIOS
    out = {"robust_sims_per_s": n_k / best_time(lambda: rp(gains), repeats)}
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    tiled = np.tile(gains, (K_SCENARIOS, 1))
    for workers, tag in ((1, "1t"), (default_workers(), "all")):

        def k_calls(w: int = workers) -> None:
            for _ in range(K_SCENARIOS):
                sc.raw(gains, w)

        def one_call(w: int = workers) -> None:
            sc.raw(tiled, w)

        t_calls = best_time(k_calls, repeats)
        t_one = best_time(one_call, repeats)
        out[f"robust_k_calls_sims_per_s_{tag}"] = n_k / t_calls
        out[f"robust_one_call_sims_per_s_{tag}"] = n_k / t_one
        out[f"robust_one_call_speedup_{tag}"] = t_calls / t_one
    draws = validation_set(spec, 0)
    best = gains[int(np.argmin(rp(gains)))]
    out["robust_validation_sims_per_s"] = len(draws) / best_time(
        lambda: rp.validate(best, draws), 1
    )
    return out
