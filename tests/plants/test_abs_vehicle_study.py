"""The Table 5 study configs of deffao-vehicle-abs: valid, planned on the vehicle, and the quick
one runs."""

from __future__ import annotations

import json
import sqlite3
from importlib import resources

import pytest

from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import load_config, plan_study, quick_config

STUDIES = resources.files("chassistune") / "data" / "studies"


CONFIG = str(STUDIES / "deffao-vehicle-abs.toml")


@pytest.mark.parametrize("quick", [False, True])
def test_the_table_5_configs_plan_runs_of_the_vehicle_fuzzy_pid(quick):
    config = load_config(CONFIG)
    plan = plan_study(quick_config(config) if quick else config)
    assert {r.optimizer_name for r in plan.runs} == {"ao", "deffao"}
    for run in plan.runs:
        assert run.plant == "abs-vehicle" and run.controller == "fuzzy-pid"
        assert run.roads == ("dry-concrete", "mu-jump", "split-mu")
        assert run.test_roads == run.roads and run.params == {"steering": "driver"}


def test_the_quick_table_5_study_runs_and_records_every_road(tmp_path):
    plan = plan_study(quick_config(load_config(CONFIG)))
    outcome = run_study(plan, tmp_path, SerialExecutor())
    assert outcome.completed == len(plan.runs) and outcome.failed == 0
    with sqlite3.connect(outcome.store) as con:
        rows = con.execute("select metrics, test_costs from runs").fetchall()
    for metrics, test_costs in rows:
        per_road = json.loads(metrics)
        assert set(per_road) == {"dry-concrete", "mu-jump", "split-mu"}
        for m in per_road.values():
            assert m["stopped"] and m["stop_distance_m"] >= m["bound_distance_m"]
            assert not m["spun"]  # the driver holds the car on split-mu
        assert all(v < 1e9 for v in json.loads(test_costs).values())
