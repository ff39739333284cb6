"""`--ecu ideal|realistic` on simulate and tune."""

from __future__ import annotations

import json


def test_simulate_realistic_echoes_the_ecu_and_its_metrics(cli, tmp_path):
    csv = tmp_path / "run.csv"
    r = cli(
        "simulate",
        "abs-wheel",
        "--ecu",
        "realistic",
        "--param",
        "vref=accel",
        "--csv",
        str(csv),
        "--json",
    )
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["params"]["ecu"] == "realistic" and doc["params"]["vref"] == "accel"
    assert doc["params"]["sensor_teeth"] == 48
    assert doc["metrics"]["stopped"] and doc["metrics"]["vref_gap_max_m_s"] < 0.5
    assert "vref_m_s [m/s]" in csv.read_text().splitlines()[0]


def test_ecu_bad_input_is_one_line_naming_the_field(cli):
    for args, field in (
        (["--ecu", "realistic", "--param", "sensor_teeth=many"], "--param sensor_teeth"),
        (["--param", "sensor_teeth=60"], "--param sensor_teeth"),
        (["--ecu", "fancy"], "--ecu"),
    ):
        r = cli("simulate", "abs-wheel", *args)
        assert r.code == 2, (args, r.err)
        assert field in r.err and "Traceback" not in r.err


def test_tune_realistic(cli):
    r = cli(
        "tune",
        "abs-wheel",
        "--controller",
        "pid",
        "--optimizer",
        "de",
        "--ecu",
        "realistic",
        "--param",
        "vref=accel",
        "--pop",
        "4",
        "--iters",
        "2",
        "--json",
    )
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["params"]["ecu"] == "realistic"
