"""The ECU gap, small version (docs/ecu.md; the full grid: examples/studies/ecu-gap.toml).

Every ABS controller of the papers (PID, fuzzy PID, fuzzy immune PID) tuned per road with the
ideal controller, evaluated with the realistic ECU, and tuned with the realistic ECU; the threshold
ABS with its registry defaults; the reference estimators compared; the ECU period swept from 1 to
20 ms. "Realistic" is the default ECU (accelerometer reference; the slew-limited one lets every
controller lock the wheel: its column shows that). Prints the markdown tables of docs/ecu.md.
Cells: distance over the adhesion bound, r13h_epsilon (k_M of the ABS-off search, which no ECU
touches), true-slip ITAE (s^2, up to the cut-out in realistic mode).

With `--study DIR` (a finished `chassistune study run examples/studies/ecu-gap.toml --out DIR`)
the gains are the study's: per scenario and road, those of the seed with the lowest cost; the
reference and period tables then also show the PID tuned with that reference or period.
Without it, a small tuning here (derlsp-ao, `--pop`, `--iters`, `--seed`).

    PYTHONPATH=src python examples/ecu_gap.py [--study DIR] [--pop 8] [--iters 8] [--seed 0]
"""

from __future__ import annotations

import argparse
from collections.abc import Mapping

import numpy as np

from chassistune.scenarios.abs_wheel import PLANT
from chassistune.scenarios.r13h import adhesion_coefficient, r13h_epsilon
from chassistune.studies.store import open_study
from chassistune.tuning.tune import tune

PRESET = "paper-derlsp-ao"
ROADS = ("dry-concrete", "wet-asphalt", "ice")
TUNED = ("pid", "fuzzy-pid", "fuzzy-immune-pid")
REALISTIC = {"ecu": "realistic"}
SLEW = {"ecu": "realistic", "vref": "slew-limited"}


def _period(ts_s: float) -> dict[str, object]:
    """The realistic ECU at period ts_s (dead time and minimum on-time at most ts / 2)."""
    short = min(2e-3, ts_s / 2)
    return {
        **REALISTIC,
        "ecu_ts_s": ts_s,
        "valve_dead_time_s": min(2e-3, short),
        "valve_min_on_s": short,
    }


def evaluate(
    controller: str,
    road: str,
    gains: Mapping[str, float],
    params: Mapping[str, object],
    adhesion: object,
) -> tuple[float, float, float]:
    """(distance ratio, r13h_epsilon, true-slip ITAE) of one controller and ECU."""
    sc = PLANT.scenario(PRESET, road, controller, params)
    g = sc.gains_array(dict(gains))[None, :]
    m = sc.metrics(g)
    eps = r13h_epsilon(controller, PRESET, road, dict(gains), params, adhesion=adhesion).epsilon  # type: ignore[arg-type]
    ok = m["status"][0] == "stopped"
    return (
        float(m["distance_ratio"][0]) if ok else float("inf"),
        eps,
        float(m["slip_itae"][0]) if ok else float("inf"),
    )


def study_gains(study_dir: str) -> dict[tuple[str, str], dict[str, float]]:
    """Per (scenario, road): the best gains of the completed seed with the lowest cost."""
    best: dict[tuple[str, str], tuple[float, dict[str, float]]] = {}
    with open_study(study_dir) as store:
        for rec in store.records():
            if not rec.completed or rec.best_cost is None:
                continue
            key = (rec.spec.group, rec.spec.roads[0])
            if key not in best or rec.best_cost < best[key][0]:
                best[key] = (rec.best_cost, rec.best_gains)
    return {k: g for k, (_, g) in best.items()}


def _fmt(row: tuple[float, float, float]) -> str:
    return f"{row[0]:.3f} / {row[1]:.3f} / {row[2]:.3g}"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--pop", type=int, default=8)
    ap.add_argument("--iters", type=int, default=8)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--study", help="gains from this finished ecu-gap study folder")
    a = ap.parse_args()
    adhesion = {road: adhesion_coefficient(PRESET, road) for road in ROADS}
    from_study = study_gains(a.study) if a.study else {}
    best: dict[tuple[str, str, str], dict[str, float]] = {}

    def tuned(
        controller: str, road: str, params: Mapping[str, object], key: str
    ) -> dict[str, float]:
        """Gains of `controller` tuned on `road` with `params`; `key` names the study scenario's
        suffix (ideal, realistic, vref-true, vref-slew, ts-1ms, ...)."""
        if a.study:
            return from_study[f"{controller}-{key}", road]
        if (controller, road, key) not in best:
            best[controller, road, key] = tune(
                "abs-wheel",
                controller,
                "derlsp-ao",
                PRESET,
                road,
                "itae",
                pop_size=a.pop,
                max_iter=a.iters,
                seed=a.seed,
                params=params,
            ).best_gains
        return best[controller, road, key]

    print(
        "| controller, road | ideal-tuned, ideal | ideal-tuned, realistic slew vref | "
        "ideal-tuned, realistic | realistic-tuned, realistic |"
    )
    print("|---|---|---|---|---|")
    for controller in TUNED:
        for road in ROADS:
            gi = tuned(controller, road, {}, "ideal")
            gr = tuned(controller, road, REALISTIC, "realistic")
            cells = [
                evaluate(controller, road, gi, {}, adhesion[road]),
                evaluate(controller, road, gi, SLEW, adhesion[road]),
                evaluate(controller, road, gi, REALISTIC, adhesion[road]),
                evaluate(controller, road, gr, REALISTIC, adhesion[road]),
            ]
            print(f"| {controller}, {road} | " + " | ".join(_fmt(c) for c in cells) + " |")
    for road in ROADS:
        cells = [evaluate("threshold", road, {}, p, adhesion[road]) for p in ({}, SLEW, REALISTIC)]
        print(f"| threshold (defaults), {road} | " + " | ".join(_fmt(c) for c in cells) + " | - |")

    vref_keys = {"true": "vref-true", "slew-limited": "vref-slew", "accel": "realistic"}
    print("\n| reference, controller | " + " | ".join(ROADS) + " |")
    print("|---|---|---|---|")
    for vref in ("true", "slew-limited", "accel"):
        params = {**REALISTIC, "vref": vref}
        rows = [("pid tuned with accel", "pid", "realistic"), ("threshold", "threshold", "")]
        if a.study:
            rows.insert(1, ("pid tuned with this reference", "pid", vref_keys[vref]))
        for label, controller, key in rows:
            texts = []
            for road in ROADS:
                g = tuned(controller, road, params, key) if key else {}
                sc = PLANT.scenario(PRESET, road, controller, params)
                m = sc.metrics(sc.gains_array(dict(g))[None, :])
                texts.append(
                    f"{m['distance_ratio'][0]:.3f} (gap {m['vref_gap_max_m_s'][0]:.2f} m/s)"
                )
            print(f"| {vref}, {label} | " + " | ".join(texts) + " |")

    print(
        "\n| ecu_ts_s | PID ideal-tuned | PID realistic-tuned (5 ms) | "
        + ("PID tuned at this period | " if a.study else "")
        + "threshold |"
    )
    print("|---|---|---|---|" + ("---|" if a.study else ""))
    road = "wet-asphalt"
    for ts in (1e-3, 2e-3, 5e-3, 10e-3, 20e-3):
        p = _period(ts)
        cells = [
            evaluate("pid", road, tuned("pid", road, {}, "ideal"), p, adhesion[road]),
            evaluate("pid", road, tuned("pid", road, REALISTIC, "realistic"), p, adhesion[road]),
        ]
        if a.study:
            key = "realistic" if ts == 5e-3 else f"ts-{ts * 1e3:g}ms"
            cells.append(evaluate("pid", road, tuned("pid", road, p, key), p, adhesion[road]))
        cells.append(evaluate("threshold", road, {}, p, adhesion[road]))
        print(f"| {ts * 1e3:g} ms | " + " | ".join(_fmt(c) for c in cells) + " |")
    if a.study:
        best = {(name, road, "study"): g for (name, road), g in from_study.items()}
    print(
        "\ngains:",
        {
            f"{k[0]}/{k[1]}/{k[2]}": {n: float(np.round(v, 4)) for n, v in g.items()}
            for k, g in best.items()
        },
    )


if __name__ == "__main__":
    main()
