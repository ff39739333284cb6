"""The study store keeps each winner's step check by road."""

from __future__ import annotations

import numpy as np
from studies_helpers import write_plan

from chassistune.scenarios.abs_wheel import PLANT
from chassistune.scenarios.refine import step_refinement
from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.store import open_study

ABS = """
[study]
name = "abs-step"
seeds = 1
seed = 4

[[scenarios]]
name = "abs"
plant = "abs-wheel"
roads = ["dry-concrete", "wet-asphalt"]
controller = "pid"
params = { v0_m_s = 20.0 }

[[optimizers]]
name = "de"

[budget]
pop_size = 6
iterations = 2
"""


def test_each_run_records_the_step_check_of_its_winner_on_every_road(tmp_path):
    _, plan = write_plan(tmp_path, ABS)
    run_study(plan, tmp_path / "out", SerialExecutor())
    with open_study(tmp_path / "out") as store:
        records = list(store.records())
    assert len(records) == 2  # one run per road
    for record in records:
        (road,) = record.spec.roads
        assert record.completed and set(record.step_check or {}) == {road}
        stored = (record.step_check or {})[road]
        sc = PLANT.scenario(None, road, "pid", {"v0_m_s": 20.0})
        gains = np.array(list(record.best_gains.values()))
        again = step_refinement(sc, gains, {"v0_m_s": 20.0}, "itae").as_dict()
        assert stored["cost"] == again["cost"] == record.best_cost
        assert stored["cost_refined"] == again["cost_refined"]
        assert stored["metrics_rel_change"] == again["metrics_rel_change"]
