"""A study folder loaded back into Python objects (`chassistune.load_study`)."""

from __future__ import annotations

from studies_helpers import tiny_config, write_plan

import chassistune


def test_a_study_folder_loads_into_objects(cli, tmp_path):
    from chassistune.reports.tables import runs_table

    config, _ = write_plan(
        tmp_path, tiny_config(seeds=1).replace("iterations = 3", "evaluations = 12")
    )
    assert cli("study", "run", str(config), "--out", str(tmp_path / "st")).code == 0
    data = chassistune.load_study(tmp_path / "st")
    assert data.name == "tiny" and data.optimizers == ("pso", "de")
    assert data.scenarios == ("qc/iso-b",)
    assert sorted(r.spec.optimizer for r in data.records) == ["de", "pso"]
    assert all(r.completed and r.nfev == 12 for r in data.records)
    table = runs_table(data.records)
    assert sorted(table["optimizer"]) == ["de", "pso"] and {"gain_kp", "best_cost"} <= set(table)
