"""The tire laws' cost in the single wheel's kernel (`chassistune bench --only tires`).

Thread CPU ns per candidate-step on one core of the PID with the bench population of `perf.abs`
(50 rows, paper-derlsp-ao, dry concrete) run to v_stop, per tire law on the same road: the
bilinear curve, Burckhardt's dry concrete, and the Magic Formula of the Chrono 185/80 R14 sample
file scaled to the road's peak (`--tire`, docs/tires.md); in the ideal kernel and in the
realistic ECU's (`tire_ecu_*`: the default `EcuParams`), and each kernel's bilinear tire with the
lagged slip (`*_lagged_bilinear_*`: relaxation length 0.3 m, docs/tires.md, transient slip);
steps are stop time / dt summed over the candidates. Best of 7 timed runs (`quick`: 3); the ratio
of the Magic Formula to the bilinear tire is measured in the same run, per kernel.

The vehicle (`tire_vehicle_*`): the PID's first VEHICLE_ROWS rows of `perf.vehicle`'s population
on paper-deffao from 15 m/s at dt 0.2 ms (the step the Chrono file needs there), on dry concrete
and on split-mu with the steering fixed, bilinear against the Magic Formula (`--tire`, docs/tires.md
"On the vehicle") and the bilinear tire with both lagged slips (`tire_vehicle_lagged_bilinear_*`:
relaxation lengths 0.3 m, docs/tires.md "Transient slip on the vehicle"), each candidate-step the
four wheels; best of 3.
"""

from __future__ import annotations

import warnings
from importlib.resources import files

import numpy as np

from chassistune.perf import abs as abs_perf
from chassistune.perf import vehicle as vehicle_perf
from chassistune.perf.timing import best_cpu_time
from chassistune.plants.tir import TirWarning
from chassistune.scenarios.abs_vehicle import PLANT as VEHICLE
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario
from chassistune.sim import abs_vehicle_layout as VL
from chassistune.sim import abs_wheel_layout as KL

SAMPLE_TIR = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")
LAWS: dict[str, tuple[str, dict[str, object]]] = {
    "bilinear": ("dry-concrete", {}),
    "burckhardt": ("burckhardt-dry-concrete", {}),
    "magic_formula": ("dry-concrete", {"tire": SAMPLE_TIR}),
    "lagged_bilinear": ("dry-concrete", {"relaxation_length_m": 0.3}),
}
"""Tire law -> (road, parameters) of its scenario."""
KERNELS: dict[str, dict[str, object]] = {"": {}, "ecu_": {"ecu": "realistic"}}
"""Figure prefix -> the kernel's parameters: the ideal single wheel, the realistic ECU."""


def ns_per_candidate_step(sc: AbsWheelScenario, gains: np.ndarray, repeats: int) -> float:
    """Best thread CPU ns per candidate-step of the population `gains` run to v_stop."""
    steps = float(np.sum(sc.raw(gains, workers=1)[:, KL.METRICS["stop_time_s"]]))
    steps /= sc.plant_params.dt_s
    return 1e9 * best_cpu_time(lambda: sc.raw(gains, workers=1), repeats) / steps


VEHICLE_ROWS = 8
"""Rows of the vehicle's population (a Magic Formula run costs about 10 us a step)."""
VEHICLE_CASES: dict[str, tuple[str, dict[str, object]]] = {
    "dry_concrete": ("dry-concrete", {}),
    "split_mu": ("split-mu", {"steering": "fixed"}),
}
"""Vehicle figure -> (road, overrides)."""
VEHICLE_LAWS: dict[str, dict[str, object]] = {
    "bilinear": {},
    "magic_formula": {"tire": SAMPLE_TIR},
    "lagged_bilinear": {"relaxation_length_m": 0.3, "lateral_relaxation_length_m": 0.3},
}
"""Vehicle tire -> its parameters."""


def vehicle_figures() -> dict[str, float]:
    """The vehicle's ns per candidate-step per tire and road (module docstring), and the Magic
    Formula's over the bilinear's per road."""
    out = {}
    for case, (road, overrides) in VEHICLE_CASES.items():
        for law, extra in VEHICLE_LAWS.items():
            params = {"dt_s": 2e-4, "v0_m_s": 15.0, **overrides, **extra}
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", TirWarning)
                sc = VEHICLE.scenario("paper-deffao", road, "pid", params)
            gains = vehicle_perf.bench_population(sc)[:VEHICLE_ROWS]
            steps = float(np.sum(sc.raw(gains, workers=1)[:, VL.M_TIME])) / sc.plant_params.dt_s
            ns = 1e9 * best_cpu_time(lambda: sc.raw(gains, workers=1), 3) / steps  # noqa: B023
            out[f"tire_vehicle_{law}_{case}_ns_per_candidate_step"] = ns
        out[f"tire_vehicle_magic_formula_over_bilinear_{case}"] = (
            out[f"tire_vehicle_magic_formula_{case}_ns_per_candidate_step"]
            / out[f"tire_vehicle_bilinear_{case}_ns_per_candidate_step"]
        )
    return out


def figures(quick: bool = False) -> dict[str, float]:
    """ns per candidate-step per tire law, and the Magic Formula's over the bilinear's."""
    gains = abs_perf.bench_population()
    out = {}
    for kernel, kernel_params in KERNELS.items():
        for law, (road, params) in LAWS.items():
            if kernel and law == "burckhardt":
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", TirWarning)
                sc = PLANT.scenario("paper-derlsp-ao", road, "pid", {**params, **kernel_params})
            out[f"tire_{kernel}{law}_ns_per_candidate_step"] = ns_per_candidate_step(
                sc, gains, 3 if quick else 7
            )
        out[f"tire_{kernel}magic_formula_over_bilinear"] = (
            out[f"tire_{kernel}magic_formula_ns_per_candidate_step"]
            / out[f"tire_{kernel}bilinear_ns_per_candidate_step"]
        )
    return out | vehicle_figures()
