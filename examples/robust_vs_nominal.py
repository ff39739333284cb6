"""Nominal against robust tuning (docs/robust.md), through the Python API.

Nominal: tuned on the preset's one scenario (abs-wheel: dry concrete, M = 100 kg, v0 = 30 m/s,
tau = 10 ms). Robust: the same optimizer, budget and seed on K Sobol scenarios (abs-wheel
default: mass +-20 %, mu_scale +-15 %, v0 20-35 m/s, actuator tau +-30 %), aggregated by
`--aggregate`. Both winners are validated on the SAME N fresh Monte Carlo draws (the validation
stream of --validation-seed), and the Sobol indices of each winner's `--metric` are computed.

    PYTHONPATH=src python examples/robust_vs_nominal.py [--plant abs-wheel] [--controller pid]
        [--vary NAME=LO:HI ...] [--aggregate max] [--scenarios 16] [--pop 20] [--iters 40]
        [--seed 0] [--validate 300] [--plot DIR]
    distance over the adhesion bound as the objective: --objective distance_ratio
    quarter car: --plant quarter-car --vary sprung_mass_kg=256:384
        --vary tire_stiffness_n_m=160000:240000 --metric objective_exact --max-cost 3
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from chassistune.tuning.problem import build_problem
from chassistune.tuning.robust.aggregate import parse_aggregate
from chassistune.tuning.robust.problem import (
    controller_sensitivity,
    known_for,
    robust_problem,
    validation_set,
)
from chassistune.tuning.robust.spec import PassCriterion, UncertaintySpec, parse_vary
from chassistune.tuning.run import run_optimizer

VARY = ["mass_kg=80:120", "mu_scale=0.85:1.15", "v0_m_s=20:35", "actuator_tau_s=0.007:0.013"]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--plant", default="abs-wheel")
    ap.add_argument("--controller", default="pid")
    ap.add_argument("--vary", action="append", default=[])
    ap.add_argument("--metric", default="distance_ratio")
    ap.add_argument("--objective", default=None)
    ap.add_argument(
        "--max-cost",
        type=float,
        default=0.0,
        help="pass test on the objective instead of stop/lock/distance (quarter car)",
    )
    ap.add_argument("--optimizer", default="derlsp-ao")
    ap.add_argument("--aggregate", default="max")
    ap.add_argument("--scenarios", type=int, default=16)
    ap.add_argument("--pop", type=int, default=20)
    ap.add_argument("--iters", type=int, default=40)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--validate", type=int, default=300)
    ap.add_argument("--validation-seed", type=int, default=12345)
    ap.add_argument("--sobol-n", type=int, default=256)
    ap.add_argument("--plot", default="")
    a = ap.parse_args()

    nominal = build_problem(a.plant, a.controller, objective=a.objective)
    criterion = PassCriterion(False, True, 0.0, a.max_cost) if a.max_cost > 0 else PassCriterion()
    spec = UncertaintySpec(
        parse_vary(a.vary or VARY, known_for(nominal)),
        a.scenarios,
        "sobol",
        parse_aggregate(a.aggregate),
        a.validate,
        criterion=criterion,
    )
    robust = robust_problem(nominal, spec, seed=a.seed)
    draws = validation_set(spec, a.validation_seed)
    out = {}
    for label, problem in (("nominal", nominal), ("robust", robust)):
        res = run_optimizer(problem, a.optimizer, a.pop, a.iters, None, a.seed)
        gains = np.array(list(res.best_gains.values()))
        train = robust.costs(gains[None, :])[0, :, 0]
        val = robust.validate(gains, draws)
        sens = controller_sensitivity(robust.builders[0], spec, gains, a.sobol_n, a.seed, a.metric)
        train_metrics = [sc.metrics(gains[None, :]) for (sc,) in robust.grid]
        out[label] = {
            "best_gains": res.best_gains,
            "best_cost": res.best_cost,
            "nfev": res.nfev,
            "wall_time_s": res.wall_time_s,
            f"nominal_{a.metric}": res.metrics[nominal.roads[0]][a.metric],
            "training_cost_mean": float(train.mean()),
            "training_cost_max": float(train.max()),
            f"training_worst_{a.metric}": max(float(m[a.metric][0]) for m in train_metrics),
            **(
                {"training_worst_peak_slip": max(float(m["peak_slip"][0]) for m in train_metrics)}
                if a.plant == "abs-wheel"
                else {}
            ),
            "validation": val.as_dict(),
            "sobol": sens.rows(),
        }
        if a.plot:
            from chassistune.plots.sensitivity import plot_sobol_indices

            plot_sobol_indices(
                sens.names,
                sens.first_order,
                sens.total,
                f"{a.plot}/sobol_{a.plant}_{a.controller}_{label}.png",
                f"{a.plant} {a.controller} {label}: {a.metric}",
            )
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
