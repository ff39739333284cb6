"""MATLAB and JSON exports: every number round-trips; the .m script runs in Octave; the JSON
scenario re-runs the source scenario."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import scipy.io
from helpers import LAWS, case

import chassistune
from chassistune.export import json_export
from chassistune.export.write import files


def _write(controller: str, fmt: str, folder: Path) -> dict[str, Path]:
    out = {}
    for name, data in files(case(controller).ec, fmt).items():
        (folder / name).write_bytes(data)
        out[name] = folder / name
    return out


@pytest.mark.parametrize("controller", LAWS)
def test_mat_file_round_trips_every_number(controller: str, tmp_path: Path) -> None:
    c = case(controller)
    ec = c.ec
    written = _write(controller, "mat", tmp_path)
    ct = scipy.io.loadmat(written[f"{ec.model_name}.mat"], simplify_cells=True)["ct"]
    assert ct["Ts"] == ec.ts_s and ct["controller"] == controller
    assert {k: float(v) for k, v in ct["params"].items()} == ec.param_dict()
    assert {k: float(v) for k, v in ct.get("gains", {}).items()} == ec.gains
    assert np.atleast_1d(ct["inputs"]).tolist() == list(ec.law.inputs)
    assert np.array_equal(np.atleast_2d(ct["test_inputs"]).reshape(c.inputs.shape), c.inputs)
    assert np.array_equal(ct["test_u"], c.u)
    pid = ec.pid_form()
    if pid is None:
        assert "pid" not in ct
    else:
        for key in ("P", "I", "D"):
            assert ct["pid"][key] == pid[key]
        assert ct["pid"]["N"] == (np.inf if pid["N"] is None else pid["N"])
        assert ct["pid"]["IntegratorMethod"] == pid["IntegratorMethod"]
    if ec.table_outputs:
        for k, out in enumerate(ec.table_outputs):
            assert np.array_equal(ct["table"][out], ec.table[k])
        for name, bp in zip(ec.table_inputs, ec.breakpoints, strict=True):
            assert np.array_equal(ct["table"][f"bp_{name}"], bp)


@pytest.mark.skipif(shutil.which("octave") is None, reason="Octave is not installed")
@pytest.mark.parametrize("controller", ["fuzzy-pid", "pid"])
def test_m_script_loads_simulink_style_variables_in_octave(controller: str, tmp_path: Path) -> None:
    ec = case(controller).ec
    written = _write(controller, "mat", tmp_path)
    script = written[f"{ec.model_name}.m"]
    names = ["Ts", "P", "I", "D", "N", *(f"ct_{n}" for n in ec.law.params)]
    if ec.table_outputs:
        names += [f"ct_table_{ec.table_outputs[0]}(3,5)", f"ct_bp_{ec.table_inputs[1]}(7)"]
    printf = "; ".join(f"printf('%.17g\\n', {n})" for n in names)
    proc = subprocess.run(
        ["octave", "--no-gui", "--norc", "--quiet", "--eval", f"run('{script}'); {printf}"],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    values = [float(v) for v in proc.stdout.split()]
    pid = ec.pid_form()
    assert pid is not None
    expected = [ec.ts_s, pid["P"], pid["I"], pid["D"], pid["N"], *ec.params.tolist()]
    if ec.table_outputs:
        expected += [ec.table[0][2, 4], ec.breakpoints[1][6]]
    assert values == expected


@pytest.mark.parametrize("controller", LAWS)
def test_json_holds_everything_and_reruns_the_source_scenario(
    controller: str, tmp_path: Path
) -> None:
    c = case(controller)
    ec = c.ec
    path = _write(controller, "json", tmp_path)[f"{ec.model_name}.json"]
    doc = json.loads(path.read_text())
    assert doc["schema"] == json_export.SCHEMA and doc["schema_version"] == 1
    assert doc["params"] == ec.param_dict() and doc["sample_time_s"] == ec.ts_s
    assert [i["name"] for i in doc["inputs"]] == list(ec.law.inputs)
    rows = np.array(doc["test_vectors"]["rows"])
    assert np.array_equal(rows[:, :-1], c.inputs) and np.array_equal(rows[:, -1], c.u)
    if ec.table_outputs:
        for k, out in enumerate(ec.table_outputs):
            assert np.array_equal(np.array(doc["table"]["values"][out]), ec.table[k])
    else:
        assert doc["table"] is None
    args = json_export.scenario_arguments(path)
    again = chassistune.simulate(**args)
    original = ec.scenario.trace(np.array(list(ec.gains.values())))
    assert again.metrics["stop_distance_m"] == original.metrics["stop_distance_m"]


def test_json_loader_refuses_other_files(tmp_path: Path) -> None:
    other = tmp_path / "x.json"
    other.write_text('{"schema": "something-else"}')
    with pytest.raises(chassistune.errors.InputError, match="not a chassistune export"):
        json_export.scenario_arguments(other)
