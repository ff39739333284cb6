"""`chassistune simulate`, `list`, `demo`: outputs and the bad-input contract (design.md 7)."""

from __future__ import annotations

import json

import pytest


def test_simulate_json_has_the_contract_keys_and_echoes_every_parameter(cli):
    r = cli(
        "simulate",
        "abs-wheel",
        "--road",
        "wet-asphalt",
        "--gains",
        "kp=4000,kd=200",
        "--param",
        "v0_m_s=25",
        "--seed",
        "3",
        "--json",
    )
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert set(doc) >= {"plant", "preset", "road", "controller", "gains", "params", "metrics"}
    assert doc["gains"] == {"kp": 4000.0, "ki": 0.0, "kd": 200.0}
    assert doc["params"]["v0_m_s"] == 25.0 and doc["params"]["seed"] == 3
    assert doc["params"]["mu_peak"] == 0.78
    m = doc["metrics"]
    for key in (
        "stopped",
        "stop_time_s",
        "stop_distance_m",
        "wheel_lock_time_s",
        "slip_iae",
        "slip_itae",
        "mean_slip",
        "peak_slip",
        "bound_distance_m",
        "bound_time_s",
    ):
        assert key in m
    assert m["bound_distance_m"] == pytest.approx((25**2 - 0.5**2) / (2 * 0.78 * 9.81))


def test_simulate_writes_plot_and_csv(cli, tmp_path):
    png, csv = tmp_path / "run.png", tmp_path / "run.csv"
    r = cli(
        "simulate", "abs-wheel", "--controller", "threshold", "--plot", str(png), "--csv", str(csv)
    )
    assert r.code == 0, r.err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    header = csv.read_text().splitlines()[0]
    assert header.startswith("time_s [s],vehicle_speed_m_s [m/s]")
    assert len(csv.read_text().splitlines()) > 1000


def test_list_controllers_json_groups_by_plant_with_bounds(cli):
    r = cli("list", "controllers", "--json")
    assert r.code == 0, r.err
    abs_ctrl = {c["name"]: c for c in json.loads(r.out)["controllers"]["abs-wheel"]}
    assert set(abs_ctrl) >= {"none", "pid", "bang-bang", "threshold"}
    pid = {g["name"]: g for g in abs_ctrl["pid"]["gains"]}
    assert pid["kp"]["bounds"] == [0.0, 1e4] and pid["kd"]["bounds"] == [0.0, 1e3]


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["simulate", "no-such-plant"], "plant"),
        (["simulate", "abs-wheel", "--road", "moon"], "road"),
        (["simulate", "abs-wheel", "--controller", "magic"], "controller"),
        (["simulate", "abs-wheel", "--preset", "nope"], "preset"),
        (["simulate", "abs-wheel", "--param", "colour=3"], "--param colour"),
        (["simulate", "abs-wheel", "--param", "mass_kg=-5"], "--param mass_kg"),
        (["simulate", "abs-wheel", "--param", "mass_kg=heavy"], "--param mass_kg"),
        (["simulate", "abs-wheel", "--param", "mass_kg=nan"], "--param mass_kg"),
        (["simulate", "abs-wheel", "--param", "v0_m_s=0.4"], "--param v0_m_s"),
        (["simulate", "abs-wheel", "--param", "mass_kg"], "--param"),
        (["simulate", "abs-wheel", "--gains", "kx=3"], "--gains"),
        (["simulate", "abs-wheel", "--gains", "kp=inf"], "--gains kp"),
        (["simulate", "abs-wheel", "--seed", "many"], "--seed"),
        (["simulate"], "PLANT"),
        (["list", "things"], "kind"),
        (["frobnicate"], ""),
    ],
)
def test_bad_input_gets_one_line_and_exit_2_and_writes_nothing(cli, tmp_path, args, field):
    png = tmp_path / "x.png"
    r = cli(*args, "--plot", str(png)) if args[0] == "simulate" and len(args) > 1 else cli(*args)
    assert r.code == 2, (r.out, r.err)
    lines = r.err.strip().splitlines()
    assert len(lines) == 1, r.err
    assert lines[0].startswith("chassistune: error: ")
    assert field in lines[0]
    assert "Traceback" not in r.err
    assert not png.exists()


def test_plot_into_a_missing_folder_is_bad_input(cli, tmp_path):
    r = cli("simulate", "abs-wheel", "--plot", str(tmp_path / "nope" / "x.png"))
    assert r.code == 2 and "--plot" in r.err


def test_demo_prints_the_table_and_writes_three_plots(cli, tmp_path):
    r = cli("demo", "--out", str(tmp_path / "demo"), "--json")
    assert r.code == 0, r.err
    rows = json.loads(r.out)["rows"]
    assert {(x["road"], x["controller"]) for x in rows} == {
        (road, c) for road in ("dry-concrete", "wet-asphalt", "ice") for c in ("none", "pid")
    }
    for x in rows:
        assert x["distance_ratio"] >= 1.0
    assert len(list((tmp_path / "demo").glob("*.png"))) == 3
