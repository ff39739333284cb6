"""Study configs: validation (one line naming the field, exit 2, nothing written), grid, seeds."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from studies_helpers import tiny_config, write_plan

from chassistune.errors import InputError
from chassistune.studies.spec import load_plan

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "studies"

GOOD = tiny_config()

# (what is wrong, config text, field the error line must name)
BAD = [
    ("unknown top key", GOOD + "\n[extras]\nx = 1\n", "extras"),
    (
        "unknown study key",
        GOOD.replace('name = "tiny"', 'name = "tiny"\ncolour = "red"'),
        "study.colour",
    ),
    (
        "unknown scenario key",
        GOOD.replace('controller = "pid"', 'controller = "pid"\nroad = 1'),
        "scenarios[0].road",
    ),
    ("wrong type seeds", GOOD.replace("seeds = 2", 'seeds = "three"'), "study.seeds"),
    ("bool seeds", GOOD.replace("seeds = 2", "seeds = true"), "study.seeds"),
    ("repeated seed", GOOD.replace("seeds = 2", "seeds = [1, 1]"), "study.seeds"),
    ("wrong type pop", GOOD.replace("pop_size = 6", "pop_size = 6.5"), "budget.pop_size"),
    ("string iterations", GOOD.replace("iterations = 3", 'iterations = "3"'), "budget.iterations"),
    ("zero iterations", GOOD.replace("iterations = 3", "iterations = 0"), "budget.iterations"),
    ("missing plant", GOOD.replace('plant = "quarter-car"\n', ""), "scenarios[0].plant"),
    ("missing study", GOOD.replace("[study]", "[other]"), "study"),
    ("no optimizers", GOOD.split("[[optimizers]]")[0], "optimizers"),
    (
        "bounds lo > hi",
        GOOD.replace("kp = [0.0, 500.0]", "kp = [500.0, 0.0]"),
        "scenarios[0].bounds",
    ),
    (
        "bounds not a pair",
        GOOD.replace("kp = [0.0, 500.0]", "kp = [0.0]"),
        "scenarios[0].bounds: kp: expected [lo, hi]",
    ),
    (
        "bounds not numbers",
        GOOD.replace("kp = [0.0, 500.0]", 'kp = ["0", 5]'),
        "scenarios[0].bounds.kp[0]",
    ),
    (
        "bounds infinite",
        GOOD.replace("kp = [0.0, 500.0]", "kp = [0.0, inf]"),
        "scenarios[0].bounds.kp[1]",
    ),
    (
        "bounds of an unknown gain",
        GOOD.replace("kp = [0.0, 500.0]", "kq = [0.0, 5.0]"),
        "scenarios[0].bounds",
    ),
    ("unknown plant", GOOD.replace('"quarter-car"', '"half-car"'), "scenarios[0].plant"),
    ("unknown road", GOOD.replace('["iso-b"]', '["iso-z"]'), "scenarios[0].roads"),
    ("unknown controller", GOOD.replace('"pid"', '"lqr"'), "scenarios[0].controller"),
    ("unknown objective", GOOD.replace('"rms-ratio-exact"', '"itae"'), "scenarios[0].objective"),
    (
        "unknown preset",
        GOOD.replace('controller = "pid"', 'controller = "pid"\npreset = "x"'),
        "scenarios[0].preset",
    ),
    (
        "unknown param",
        GOOD.replace('controller = "pid"', 'controller = "pid"\nparams = { z = 1 }'),
        "scenarios[0].params.z",
    ),
    (
        "bad param value",
        GOOD.replace('controller = "pid"', 'controller = "pid"\nparams = { speed_m_s = -3 }'),
        "scenarios[0].params.speed_m_s",
    ),
    (
        "one tune road",
        GOOD.replace('controller = "pid"', 'controller = "pid"\ntune_roads = ["iso-b"]'),
        "scenarios[0].tune_roads",
    ),
    ("unknown optimizer", GOOD.replace('name = "pso"', 'name = "annealing"'), "optimizers[0].name"),
    (
        "unknown hyperparameter",
        GOOD.replace('name = "pso"', 'name = "pso"\nhyperparameters = { inertia = 0.5 }'),
        "optimizers[0].hyperparameters",
    ),
    ("duplicate label", GOOD.replace('name = "de"', 'name = "pso"'), "optimizers[1].label"),
    ("population too small", GOOD.replace("pop_size = 6", "pop_size = 3"), "budget.pop_size"),
    ("empty file", "", "CONFIG"),
    ("only a comment", "# nothing here\n", "CONFIG"),
    ("not TOML", "this is not = = TOML [\n", "CONFIG"),
]


@pytest.mark.parametrize(("case", "text", "field"), BAD, ids=[b[0] for b in BAD])
def test_a_bad_config_gives_one_line_naming_the_field_and_writes_nothing(
    cli, tmp_path, case, text, field
):
    config = tmp_path / "bad.toml"
    config.write_text(text)
    out = tmp_path / "out"
    r = cli("study", "run", str(config), "--out", str(out))
    assert r.code == 2, (case, r.err)
    lines = r.err.strip().splitlines()
    assert len(lines) == 1, r.err
    assert lines[0].startswith(f"chassistune: error: {field}"), (case, lines[0])
    assert not out.exists()


def test_missing_binary_and_folder_configs_are_refused(cli, tmp_path):
    (tmp_path / "binary.toml").write_bytes(bytes(range(256)))
    for name in ("absent.toml", "binary.toml", "."):
        r = cli("study", "run", str(tmp_path / name), "--out", str(tmp_path / "out"))
        assert r.code == 2 and r.err.startswith("chassistune: error: CONFIG")
        assert len(r.err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_bad_options_and_missing_dask_write_nothing(cli, tmp_path, monkeypatch):
    config = tmp_path / "good.toml"
    config.write_text(GOOD)
    out = tmp_path / "out"
    r = cli("study", "run", str(config), "--out", str(out), "--scheduler", "tcp://127.0.0.1:1")
    assert r.code == 2 and "--scheduler" in r.err
    r = cli("study", "run", str(config), "--out", str(tmp_path / "no" / "such"))
    assert r.code == 2 and "--out" in r.err
    monkeypatch.setitem(__import__("sys").modules, "distributed", None)
    r = cli("study", "run", str(config), "--out", str(out), "--executor", "dask")
    assert r.code == 2 and 'pip install "chassistune[dask]"' in r.err
    assert len(r.err.strip().splitlines()) == 1
    assert not out.exists()


def test_grid_roads_tune_roads_and_names(tmp_path):
    extra = 'tune_roads = ["iso-b", "iso-c"]\naggregate = "max"\n'
    text = tiny_config(seeds=3, roads='["iso-b", "iso-c"]').replace(
        'controller = "pid"', 'controller = "pid"\n' + extra
    )
    _, plan = write_plan(tmp_path, text)
    assert plan.scenarios == ["qc/iso-b", "qc/iso-c", "qc/iso-b+iso-c"]
    assert plan.optimizers == ["pso", "de"]
    assert len(plan.runs) == 3 * 2 * 3
    joint = [r for r in plan.runs if r.scenario == "qc/iso-b+iso-c"]
    assert all(r.roads == ("iso-b", "iso-c") and r.aggregate == "max" for r in joint)
    assert all(r.test_roads == ("iso-b", "iso-c") for r in plan.runs)
    assert plan.runs[0].preset == "paper-iabc" and plan.runs[0].bounds["kp"] == (0.0, 500.0)
    assert len({r.key for r in plan.runs}) == len(plan.runs)


def test_seed_indices_and_common_random_numbers(tmp_path):
    _, plan = write_plan(tmp_path, tiny_config(seeds="[3, 7]"))
    assert sorted({r.seed for r in plan.runs}) == [3, 7]
    by_seed: dict[int, set[tuple[float, int]]] = {}
    for r in plan.runs:
        ss = np.random.SeedSequence(11, spawn_key=(r.seed,))
        assert r.scenario_seed == int(ss.generate_state(1, np.uint32)[0])
        draw = (float(r.optimizer_rng().random()), r.scenario_seed)
        assert draw == (float(np.random.default_rng(ss).random()), r.scenario_seed)
        by_seed.setdefault(r.seed, set()).add(draw)
    # the same generator for every optimizer and scenario at a seed index
    assert all(len(draws) == 1 for draws in by_seed.values())
    _, counted = write_plan(tmp_path, tiny_config(seeds=8), "counted.toml")
    same = {r.key: r.spec_hash for r in counted.runs}
    assert all(same[r.key] == r.spec_hash for r in plan.runs)  # adding seeds changes no run


@pytest.mark.parametrize("name", ["abs-dry-pid.toml", "quarter-car-pid.toml", "abs-roads.toml"])
def test_the_example_configs_are_valid(name):
    plan = load_plan(EXAMPLES / name)
    assert plan.runs


def test_the_issue_example_expands_to_twelve_runs():
    plan = load_plan(EXAMPLES / "abs-dry-pid.toml")
    assert len(plan.runs) == 12
    assert {(r.plant, r.preset, r.road, r.controller, r.objective) for r in plan.runs} == {
        ("abs-wheel", "paper-derlsp-ao", "dry-concrete", "pid", "itae")
    }
    assert {r.optimizer for r in plan.runs} == {"ao", "pso"}
    assert sorted({r.seed for r in plan.runs}) == list(range(6))


def test_load_plan_raises_input_error_for_python_callers(tmp_path):
    with pytest.raises(InputError, match=r"scenarios\[0\]\.roads"):
        write_plan(tmp_path, tiny_config(roads='["iso-q"]'))
