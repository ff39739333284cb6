"""Results loaded back into Python: a tune's folder as its document and as a new
simulation of the tuned controller (what `simulate --from` gives); a study folder as objects in
tests/studies/test_study_loads_back.py."""

from __future__ import annotations

import json

import pytest

import chassistune
from chassistune.errors import InputError

TUNE = (
    "tune",
    "abs-wheel",
    "--controller",
    "pid",
    "--optimizer",
    "pso",
    "--pop",
    "6",
    "--iters",
    "2",
    "--road",
    "wet-asphalt",
    "--param",
    "v0_m_s=25",
    "--seed",
    "4",
)


def test_a_tune_folder_loads_back_and_simulates_as_simulate_from(cli, tmp_path):
    out = tmp_path / "t"
    assert cli(*TUNE, "--out", str(out)).code == 0
    saved = json.loads((out / "tune.json").read_text())
    assert chassistune.load_tune(out) == saved == chassistune.load_tune(out / "tune.json")
    again = chassistune.simulate_tuned(out)
    assert again.gains == saved["best_gains"]
    assert again.scenario.road == "wet-asphalt" and again.scenario.params()["v0_m_s"] == 25.0
    assert again.metrics["slip_itae"] == saved["metrics"]["slip_itae"]
    on_ice = chassistune.simulate_tuned(out, road="ice", params={"v0_m_s": 20})
    via_cli = json.loads(
        cli("simulate", "--from", str(out), "--road", "ice", "--param", "v0_m_s=20", "--json").out
    )
    assert on_ice.as_dict() == via_cli


def test_what_is_not_a_tune_result_names_the_path(tmp_path):
    (tmp_path / "x.json").write_text('{"plant": "abs-wheel"}')
    with pytest.raises(InputError) as exc:
        chassistune.load_tune(tmp_path / "x.json")
    assert exc.value.field == "path" and "is not a tune result" in exc.value.problem
    with pytest.raises(InputError) as exc:
        chassistune.load_study(tmp_path)
    assert exc.value.field == "path" and "not a study folder" in exc.value.problem
