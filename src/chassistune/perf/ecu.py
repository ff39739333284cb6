"""ECU figures: `abs_ecu_sims_per_s`, the realistic ECU on the `abs_sims_per_s`
population (`perf.abs.bench_population`: 50 PID gain triples, paper-derlsp-ao, dry concrete, one
core) with the default `EcuParams` (48-tooth sensor, 5 ms, one sample of delay, accelerometer
reference, three-state valves, cut-out 2 m/s), and `abs_ecu_ratio_to_ideal`, its ratio to the
ideal kernel's simulations per second measured in the same run; best-of-n wall times, and
(`*_cpu`) thread CPU times, which a shared machine's descheduling does not inflate.
"""

from __future__ import annotations

from functools import partial

from chassistune.perf.abs import bench_population
from chassistune.perf.timing import best_cpu_time, best_time
from chassistune.scenarios.abs_wheel import PLANT


def figures(quick: bool = False) -> dict[str, float]:
    """Measure the ECU figures in this run."""
    gains = bench_population()
    repeats = 3 if quick else 7
    wall, cpu = {}, {}
    for mode in ("ideal", "realistic"):
        sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid", {"ecu": mode})
        sc.raw(gains[:2], workers=1)  # compile / load the cache outside the timing
        run = partial(sc.raw, gains, workers=1)
        wall[mode] = len(gains) / best_time(run, repeats)
        cpu[mode] = len(gains) / best_cpu_time(run, repeats)
    return {
        "abs_ecu_sims_per_s": wall["realistic"],
        "abs_ecu_ratio_to_ideal": wall["realistic"] / wall["ideal"],
        "abs_ecu_sims_per_s_cpu": cpu["realistic"],
        "abs_ecu_ratio_to_ideal_cpu": cpu["realistic"] / cpu["ideal"],
    }
