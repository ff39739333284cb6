"""Suspension figure `suspension_exact_speedup_vs_sim` (design.md 8).

The exact objective (`rms-ratio-exact`: Lyapunov equation per candidate) against the simulated one
(`rms-ratio`: the default 10 s run at dt = 1 ms, exact discretization), same candidates, same
scenario (preset paper-iabc, PID, iso-b), both on one core and measured in the same run.
Candidates: rows uniform over the PID's registry bounds from make_rng(12345).
"""

from __future__ import annotations

import numpy as np

from chassistune._rng import make_rng
from chassistune.perf.timing import best_time
from chassistune.scenarios.quarter_car import PLANT


def bench_population(n: int) -> np.ndarray:
    """n (kp, ki, kd) rows uniform over the registry bounds of the quarter-car PID."""
    sc = PLANT.scenario("paper-iabc", controller="pid")
    lo, hi = np.array(sc.controller.bounds()).T
    return np.asarray(make_rng(12345).uniform(lo, hi, (n, len(lo))))


def figures(quick: bool = False) -> dict[str, float]:
    """Measure exact and simulated objective throughput on the same candidates."""
    gains = bench_population(128 if quick else 512)
    sc = PLANT.scenario("paper-iabc", "iso-b", "pid", {"duration_s": 10.0})
    for objective in ("rms-ratio-exact", "rms-ratio"):  # compile / load caches, passive refs
        sc.cost(gains[:2], objective, workers=1)
    repeats = 3 if quick else 5
    t_exact = best_time(lambda: sc.cost(gains, "rms-ratio-exact"), repeats)
    t_sim = best_time(lambda: sc.cost(gains, "rms-ratio", workers=1), repeats)
    return {
        "suspension_exact_speedup_vs_sim": t_sim / t_exact,
        "suspension_exact_evals_per_s": len(gains) / t_exact,
        "suspension_sims_per_s": len(gains) / t_sim,
    }
