"""The tire laws' cost in the single wheel's kernel (`chassistune bench --only tires`).

Thread CPU ns per candidate-step on one core of the PID with the bench population of `perf.abs`
(50 rows, paper-derlsp-ao, dry concrete) run to v_stop, per tire law on the same road: the
bilinear curve, Burckhardt's dry concrete, and the Magic Formula of the Chrono 185/80 R14 sample
file scaled to the road's peak (`--tire`, docs/tires.md); steps are stop time / dt summed over
the candidates. Best of 7 timed runs (`quick`: 3); the ratio of the Magic Formula to the bilinear
tire is measured in the same run.
"""

from __future__ import annotations

import warnings
from importlib.resources import files

import numpy as np

from chassistune.perf import abs as abs_perf
from chassistune.perf.timing import best_cpu_time
from chassistune.plants.tir import TirWarning
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario
from chassistune.sim import abs_wheel_layout as KL

SAMPLE_TIR = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")
LAWS = {
    "bilinear": ("dry-concrete", {}),
    "burckhardt": ("burckhardt-dry-concrete", {}),
    "magic_formula": ("dry-concrete", {"tire": SAMPLE_TIR}),
}
"""Tire law -> (road, parameters) of its scenario."""


def ns_per_candidate_step(sc: AbsWheelScenario, gains: np.ndarray, repeats: int) -> float:
    """Best thread CPU ns per candidate-step of the population `gains` run to v_stop."""
    steps = float(np.sum(sc.raw(gains, workers=1)[:, KL.METRICS["stop_time_s"]]))
    steps /= sc.plant_params.dt_s
    return 1e9 * best_cpu_time(lambda: sc.raw(gains, workers=1), repeats) / steps


def figures(quick: bool = False) -> dict[str, float]:
    """ns per candidate-step per tire law, and the Magic Formula's over the bilinear's."""
    gains = abs_perf.bench_population()
    out = {}
    for law, (road, params) in LAWS.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TirWarning)
            sc = PLANT.scenario("paper-derlsp-ao", road, "pid", params)
        out[f"tire_{law}_ns_per_candidate_step"] = ns_per_candidate_step(
            sc, gains, 3 if quick else 7
        )
    out["tire_magic_formula_over_bilinear"] = (
        out["tire_magic_formula_ns_per_candidate_step"] / out["tire_bilinear_ns_per_candidate_step"]
    )
    return out
