"""Robust scenarios in a study: the `[uncertainty]` table, the training set shared by
every optimizer at a seed index on every executor, validation in the store, errors by path."""

from __future__ import annotations

import numpy as np
import pytest
from studies_helpers import tiny_config, write_plan

from chassistune.errors import InputError
from chassistune.studies.executors import ProcessExecutor, SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.store import open_study
from chassistune.tuning.robust.problem import validation_set
from chassistune.tuning.robust.spec import ParamRange, parse_table

UNCERTAINTY = """
[scenarios.uncertainty]
scenarios = 4
aggregate = "max"
validate = 6
[scenarios.uncertainty.vary]
sprung_mass_kg = "256:384"
tire_stiffness_n_m = [160000, 240000]
[scenarios.uncertainty.pass]
require_stop = false
allow_lock = true
max_distance_ratio = 0
max_cost = 3.0
"""


def _robust_records(folder):
    with open_study(folder) as store:
        return {r.spec.key: r for r in store.records()}


def test_the_training_set_is_the_same_for_every_optimizer_and_executor(tmp_path):
    _, plan = write_plan(tmp_path, tiny_config(seeds=2, extra=UNCERTAINTY))
    run_study(plan, tmp_path / "serial", SerialExecutor())
    with ProcessExecutor(2) as ex:
        run_study(plan, tmp_path / "process", ex)
    serial, process = _robust_records(tmp_path / "serial"), _robust_records(tmp_path / "process")
    assert len(serial) == 4 and set(serial) == set(process)
    by_seed: dict[int, list[list[float]]] = {}
    for key, rec in serial.items():
        assert rec.completed, rec.error
        rob, other = rec.robust, process[key].robust
        assert rob is not None and other is not None
        training = rob["training"]["values"]
        assert training == other["training"]["values"]  # the same K scenarios in any process
        assert rob == other and rec.best_gains == process[key].best_gains
        assert by_seed.setdefault(rec.spec.seed, training) == training  # every optimizer
        v = rob["validation"]
        assert v["n"] == 6 and 0 <= v["failures"] <= 6
        # the winner's tuned cost is the max of its K training costs
        assert rec.best_cost == max(rob["training"]["costs"])
    assert by_seed[0] != by_seed[1]  # another seed index, other scenarios
    # the validation draws of a seed index are its own Monte Carlo stream
    positive = ParamRange(0.0, np.inf, lo_open=True)
    spec = parse_table(
        plan.runs[0].uncertainty, {"sprung_mass_kg": positive, "tire_stiffness_n_m": positive}
    )
    assert len(validation_set(spec, plan.runs[0].seed_sequence())) == 6


@pytest.mark.parametrize(
    ("table", "field"),
    [
        (
            "[scenarios.uncertainty]\nscenarios = 6\n[scenarios.uncertainty.vary]\n"
            'sprung_mass_kg = "256:384"\n',
            "scenarios[0].uncertainty.scenarios",
        ),
        (
            '[scenarios.uncertainty]\n[scenarios.uncertainty.vary]\nfoo_kg = "1:2"\n',
            "scenarios[0].uncertainty.vary.foo_kg",
        ),
        (
            '[scenarios.uncertainty]\n[scenarios.uncertainty.vary]\nsprung_mass_kg = "384:256"\n',
            "scenarios[0].uncertainty.vary.sprung_mass_kg",
        ),
    ],
)
def test_bad_uncertainty_tables_name_their_config_path(tmp_path, table, field):
    with pytest.raises(InputError) as exc:
        write_plan(tmp_path, tiny_config(seeds=1, extra=table))
    assert exc.value.field == field
