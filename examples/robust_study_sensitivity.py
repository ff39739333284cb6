"""Sobol indices of every tuned controller of a robust study (docs/robust.md), from its store.

For each completed run with an `[uncertainty]` table: first-order and total Sobol indices of the
winner's distance ratio (abs-wheel) or exact RMS objective (quarter car) with respect to each
uncertain parameter, n (d + 2) simulations drawn from the run's sensitivity stream.

    PYTHONPATH=src python examples/robust_study_sensitivity.py STUDY_DIR [--n 256] [--plot DIR]
"""

from __future__ import annotations

import argparse

import numpy as np

from chassistune.studies.problems import problem_for
from chassistune.studies.store import open_study
from chassistune.tuning.robust.problem import RobustProblem, controller_sensitivity

METRIC = {"abs-wheel": "distance_ratio", "quarter-car": "objective_exact"}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("study")
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--plot", default="")
    a = ap.parse_args()
    with open_study(a.study) as store:
        records = [r for r in store.records() if r.completed and r.robust is not None]
    print("| run | metric | " + " | ".join(["parameter", "S1", "ST"]) + " |")
    print("| --- | --- | --- | --- | --- |")
    for rec in records:
        s = rec.spec
        problem = problem_for(s.model_dump(), s.scenario_seed, s.seed_sequence())
        assert isinstance(problem, RobustProblem)
        gains = np.array([rec.best_gains[g] for g in problem.gain_names])
        metric = METRIC[s.plant]
        sens = controller_sensitivity(
            problem.builders[0], problem.spec, gains, a.n, s.seed_sequence(), metric
        )
        for name, s1, st in zip(sens.names, sens.first_order, sens.total, strict=True):
            print(f"| {s.scenario} | {metric} | {name} | {s1:.3f} | {st:.3f} |")
        if a.plot:
            from chassistune.plots.sensitivity import plot_sobol_indices

            plot_sobol_indices(
                sens.names,
                sens.first_order,
                sens.total,
                f"{a.plot}/sobol_{s.group}.png",
                f"{s.group}: {metric}",
            )


if __name__ == "__main__":
    main()
