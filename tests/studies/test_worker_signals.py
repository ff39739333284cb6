"""Workers and the command line's signal policy."""

from __future__ import annotations

import sys
from pathlib import Path

import raising_plant
from studies_helpers import tiny_config, write_plan

from chassistune.scenarios import registry
from chassistune.studies.executors import ProcessExecutor
from chassistune.studies.runner import run_study


def test_a_worker_killed_by_sigterm_does_not_print_interrupted(capfd, tmp_path, monkeypatch):
    """Spawned workers re-run the driver's main module with its argv: under the console script
    they must not take its Ctrl-C policy (a killed worker printed "chassistune: interrupted")."""
    monkeypatch.setattr(sys, "argv", [str(Path(sys.executable).parent / "chassistune")])
    raising_plant.register()
    try:
        text = tiny_config(seeds=1).replace('"rms-ratio-exact"', '"terminated"')
        text = text.replace('plant = "quarter-car"', f'plant = "{raising_plant.NAME}"')
        _, plan = write_plan(tmp_path, text)
        with ProcessExecutor(1, initializer=raising_plant.register) as ex:
            outcome = run_study(plan, tmp_path / "st", ex)
    finally:
        registry.unregister(raising_plant.NAME)
    assert outcome.failed == 2
    assert "interrupted" not in capfd.readouterr().err
