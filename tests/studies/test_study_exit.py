"""`study run`'s exit status: a study in which every run failed is not a success."""

from __future__ import annotations

import raising_plant
from studies_helpers import tiny_config, write_plan

from chassistune.scenarios import registry


def test_a_study_whose_every_run_failed_exits_1(cli, tmp_path):
    raising_plant.register()
    try:
        text = tiny_config(seeds=1).replace('"rms-ratio-exact"', '"raises"')
        text = text.replace('plant = "quarter-car"', f'plant = "{raising_plant.NAME}"')
        config, _ = write_plan(tmp_path, text)
        r = cli("study", "run", str(config), "--out", str(tmp_path / "st"))
        again = cli("study", "run", str(config), "--out", str(tmp_path / "st"))
    finally:
        registry.unregister(raising_plant.NAME)
    for res in (r, again):
        assert res.code == 1, res.err
        assert "every run of study tiny failed" in res.err
