"""`chassistune export`: every source kind, and bad input (one line, exit 2, nothing written)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from helpers import case

import chassistune
from chassistune._io import write_json
from chassistune.controllers import laws
from chassistune.export import vectors, write
from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import load_plan
from chassistune.studies.store import open_study

STUDY = """
[study]
name = "export-source"
seeds = 1

[[scenarios]]
name = "abs"
plant = "abs-wheel"
roads = ["wet-asphalt"]
controller = "pid"
objective = "itae"

[[optimizers]]
name = "pso"

[budget]
pop_size = 4
iterations = 1
"""


def _files(folder: Path) -> set[str]:
    return {p.name for p in folder.iterdir()} if folder.exists() else set()


def test_export_from_registry_defaults_writes_c_and_vectors(
    cli: Callable[..., object], tmp_path: Path
) -> None:
    out = tmp_path / "new" / "ecu"
    res = cli("export", "--controller", "fuzzy-pid", "--format", "c", "--out", str(out))
    assert res.code == 0, res.err
    assert _files(out) == {"controller.h", "controller.c", "ct_check.c", "test_vectors.csv"}
    assert _files(tmp_path / "new") == {"ecu"}  # no temporary file left anywhere
    _, data = vectors.read_csv(str(out / "test_vectors.csv"))
    c = case("fuzzy-pid")
    assert np.array_equal(data[:, :-1], c.inputs) and np.array_equal(data[:, -1], c.u)


def test_export_from_a_tune_result_uses_its_gains_road_and_params(
    cli: Callable[..., object], tmp_path: Path
) -> None:
    result = chassistune.tune(
        "abs-wheel", "pid", "pso", roads="ice", pop_size=4, max_iter=1, params={"dt_s": 2e-3}
    )
    source = tmp_path / "tune.json"
    write_json(source, result.as_dict())  # as `tune --out` writes tune.json
    res = cli(
        "export",
        str(source),
        "--param",
        "ecu_ts_s=0.01",
        "--format",
        "json",
        "--out",
        str(tmp_path / "out"),
    )
    assert res.code == 0, res.err
    doc = json.loads((tmp_path / "out" / "chassistune_pid.json").read_text())
    assert doc["scenario"]["road"] == "ice"
    assert doc["scenario"]["params"]["dt_s"] == 2e-3
    assert doc["sample_time_s"] == 0.01
    assert {k: doc["params"][k] for k in result.best_gains} == result.best_gains
    res = cli(
        "export",
        str(source),
        "--road",
        "wet-asphalt",
        "--format",
        "json",
        "--out",
        str(tmp_path / "wet"),
    )
    assert res.code == 0, res.err
    doc = json.loads((tmp_path / "wet" / "chassistune_pid.json").read_text())
    # the default 5 ms, rounded to whole steps of dt = 2 ms (as the kernel rounds ts_s)
    assert doc["scenario"]["road"] == "wet-asphalt" and doc["sample_time_s"] == 0.004


def test_export_from_a_study_run(cli: Callable[..., object], tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text(STUDY)
    study = tmp_path / "study"
    run_study(load_plan(config), study, SerialExecutor())
    with open_study(study) as store:
        (rec,) = list(store.records())
    res = cli(
        "export", f"{study}#{rec.spec.key}", "--format", "mat", "--out", str(tmp_path / "mat")
    )
    assert res.code == 0, res.err
    import scipy.io

    ct = scipy.io.loadmat(tmp_path / "mat" / "chassistune_pid.mat", simplify_cells=True)["ct"]
    assert {k: float(v) for k, v in ct["gains"].items()} == rec.best_gains
    assert ct["road"] == "wet-asphalt"


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["nosuch/tune.json"], "SOURCE"),
        (["{study}#abs/wet-asphalt|pso|7"], "SOURCE"),
        (["{study}"], "SOURCE"),
        (["{bang_bang}"], "SOURCE"),
        (["--controller", "none"], "--controller"),
        (["--controller", "bang-bang"], "--controller"),
        (["--plant", "quarter-car", "--controller", "pid"], "--plant"),
        (["--plant", "abs-vehicle", "--controller", "pid"], "--plant"),
        (["{vehicle}"], "SOURCE"),
        (["--controller", "pid", "--param", "sensor=toothed"], "--param sensor"),
        (["--controller", "pid", "--param", "ecu=realistic"], "--param ecu"),
        (["{scheduled}"], "--param gain_schedule"),
        (["--controller", "pid", "--gains", "kq=3"], "--gains"),
        (["--controller", "pid", "--gains", "kp=abc"], "--gains kp"),
        (
            ["--controller", "fuzzy-pid", "--param", "fuzzy_table_points=1"],
            "--param fuzzy_table_points",
        ),
        (["--controller", "pid", "--param", "ecu_ts_s=-1"], "--param ecu_ts_s"),
        (["--controller", "pid", "--param", "fuzzy_table_points=33"], "--param fuzzy_table_points"),
        (["--controller", "fuzzy-pid", "--param", "rulebase=nosuch"], "--param rulebase"),
        (["--controller", "pid", "--road", "mars"], "--road"),
        ([], "--controller"),
    ],
)
def test_bad_input_is_one_line_exit_2_and_nothing_written(
    args: list[str], field: str, cli: Callable[..., object], tmp_path: Path
) -> None:
    study = tmp_path / "emptystudy"
    study.mkdir()
    bang_bang = study / "bang-bang.json"  # a tune result of a law without a discrete form
    bang_bang.write_text(
        json.dumps(
            {
                "plant": "abs-wheel",
                "preset": None,
                "roads": ["ice"],
                "controller": "bang-bang",
                "best_gains": {},
                "params": {},
            }
        )
    )
    vehicle = study / "vehicle.json"  # a vehicle tune: no discrete form to export
    vehicle.write_text(
        json.dumps(
            {
                "plant": "abs-vehicle",
                "preset": None,
                "roads": ["mu-jump"],
                "controller": "pid",
                "best_gains": {"kp": 1.0, "ki": 0.0, "kd": 0.0},
                "params": {},
            }
        )
    )
    scheduled = study / "scheduled.json"  # tuned with a speed schedule the C cannot run
    scheduled.write_text(
        json.dumps(
            {
                "plant": "abs-wheel",
                "preset": None,
                "roads": ["ice"],
                "controller": "pid",
                "best_gains": {"kp": 1.0, "ki": 0.0, "kd": 0.0},
                "params": {"ecu": "realistic", "gain_schedule": "speed"},
            }
        )
    )
    out = tmp_path / "out"
    res = cli(
        "export",
        *(
            a.format(study=study, bang_bang=bang_bang, vehicle=vehicle, scheduled=scheduled)
            for a in args
        ),
        "--format",
        "c",
        "--out",
        str(out),
    )
    assert res.code == 2
    assert len(res.err.strip().splitlines()) == 1
    assert res.err.startswith(f"chassistune: error: {field}: "), res.err
    assert not out.exists()
    assert _files(tmp_path) == {"emptystudy"}
    assert _files(study) == {"bang-bang.json", "vehicle.json", "scheduled.json"}


def test_abs_vehicle_refusal_says_why(cli: Callable[..., object], tmp_path: Path) -> None:
    res = cli(
        "export",
        "--plant",
        "abs-vehicle",
        "--controller",
        "fuzzy-pid",
        "--format",
        "c",
        "--out",
        str(tmp_path / "out"),
    )
    assert res.code == 2
    wheel_laws = [
        n for n in laws.names() if laws.get(n).discrete and laws.get(n).spec(laws.ABS_VEHICLE)
    ]
    assert wheel_laws[:3] == ["pid", "threshold", "fuzzy-pid"]
    assert f"({', '.join(wheel_laws)})" in res.err and "no discrete closed loop" in res.err
    assert "abs-wheel" in res.err


def test_a_realistic_source_keeps_its_sample_time_and_gets_the_ideal_ecu(
    cli: Callable[..., object], tmp_path: Path
) -> None:
    """A tune in the realistic ECU mode: its ecu_ts_s is the sample time; its sensor and valve
    models are not part of the exported controller (the export's scenario has the ideal ECU)."""
    source = tmp_path / "tune.json"
    source.write_text(
        json.dumps(
            {
                "plant": "abs-wheel",
                "preset": None,
                "roads": ["ice"],
                "controller": "pid",
                "best_gains": {"kp": 3000.0, "ki": 10.0, "kd": 100.0},
                "params": {
                    "ecu": "realistic",
                    "ecu_ts_s": 0.01,
                    "sensor": "toothed",
                    "valves": "three-state",
                },
            }
        )
    )
    res = cli("export", str(source), "--format", "json", "--out", str(tmp_path / "out"))
    assert res.code == 0, res.err
    doc = json.loads((tmp_path / "out" / "chassistune_pid.json").read_text())
    params = doc["scenario"]["params"]
    assert doc["sample_time_s"] == 0.01 and params["ecu_ts_s"] == 0.01
    assert (params["sensor"], params["valves"], params["ecu_delay_samples"]) == (
        "ideal",
        "continuous",
        0,
    )
    assert doc["params"]["kp"] == 3000.0


def test_simulate_from_an_export_reruns_the_loop_of_its_test_vectors(
    cli: Callable[..., object], tmp_path: Path
) -> None:
    """`simulate --from EXPORT.json` runs the kernel on the exported scenario: the stop of the
    closed loop that recorded the test vectors (and that the C reproduces)."""
    out = tmp_path / "out"
    res = cli("export", "--controller", "fuzzy-pid", "--format", "json", "--out", str(out))
    assert res.code == 0, res.err
    res = cli("simulate", "--from", str(out / "chassistune_fuzzy_pid.json"), "--json")
    assert res.code == 0, res.err
    metrics = json.loads(res.out)["metrics"]
    loop = vectors.stop(case("fuzzy-pid").ec)
    assert abs(metrics["stop_distance_m"] - loop.stop_distance_m) <= 1e-12
    assert json.loads(res.out)["params"]["ecu"] == "realistic"
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps({"schema": "chassistune.export", "schema_version": 99}))
    res = cli("simulate", "--from", str(broken))
    assert res.code == 2 and res.err.startswith("chassistune: error: --from: ")


def test_unwritable_folder_is_refused_before_any_work(
    cli: Callable[..., object], tmp_path: Path
) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    for out in (blocker, blocker / "sub"):
        res = cli("export", "--controller", "pid", "--format", "c", "--out", str(out))
        assert res.code == 2 and len(res.err.strip().splitlines()) == 1 and "--out" in res.err
    assert _files(tmp_path) == {"a-file"} and blocker.read_text() == "not a folder"


def test_a_failed_write_leaves_no_file_and_no_new_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """All files or none: the second file cannot be written, so the first is not either; an
    existing folder keeps its files as they were, a folder the call created is removed."""
    ec = case("pid").ec
    monkeypatch.setattr(
        write, "files", lambda ec, fmt: {"controller.h": b"new", "no/such/folder.c": b"x"}
    )
    old = tmp_path / "old"
    old.mkdir()
    (old / "controller.h").write_text("old")
    for out in (old, tmp_path / "new" / "deeper"):
        with pytest.raises(FileNotFoundError):
            write.write(ec, "c", str(out))
    assert _files(tmp_path) == {"old"}
    assert _files(old) == {"controller.h"} and (old / "controller.h").read_text() == "old"
