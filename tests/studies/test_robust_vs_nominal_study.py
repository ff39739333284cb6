"""The shipped robust study (examples/studies/robust-vs-nominal.toml) at a small budget: the
robust PID's worst validation distance ratio beats the nominal PID's on the same draws."""

from __future__ import annotations

import tomllib
from pathlib import Path

from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import parse_config, plan_study
from chassistune.studies.store import open_study

CONFIG = Path(__file__).parents[2] / "examples" / "studies" / "robust-vs-nominal.toml"


def test_the_robust_pid_has_a_better_worst_validation_distance_than_the_nominal(tmp_path):
    data = tomllib.loads(CONFIG.read_text())
    data["scenarios"] = [s for s in data["scenarios"] if s["name"].startswith("abs-pid-")]
    for sc in data["scenarios"]:
        sc["uncertainty"]["validate"] = 100
    data["budget"] = {"pop_size": 12, "iterations": 15}
    plan = plan_study(parse_config(data))
    run_study(plan, tmp_path, SerialExecutor())
    with open_study(tmp_path) as store:
        v = {r.spec.group: r.robust["validation"] for r in store.records() if r.robust}
    nominal, robust = v["abs-pid-nominal"], v["abs-pid-robust"]
    assert nominal["n"] == robust["n"] == 100
    assert robust["worst_distance_ratio"] < nominal["worst_distance_ratio"], (robust, nominal)
    assert robust["failures"] == 0 and robust["certificate"] is not None
