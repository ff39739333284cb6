"""`chassistune simulate abs-vehicle` with the lagged slips (docs/tires.md, "Transient slip on the
vehicle"): a run, its echo and trace columns; bad lengths get one line naming the field, exit 2."""

from __future__ import annotations

import json

import pytest


def test_simulate_runs_with_a_relaxation_length_and_echoes_it(cli, tmp_path):
    csv = tmp_path / "trace.csv"
    r = cli(
        "simulate",
        "abs-vehicle",
        "--param",
        "relaxation_length_m=0.3",
        "--param",
        "lateral_relaxation_length_m=0.2",
        "--csv",
        str(csv),
        "--json",
    )
    assert r.code == 0, r.err
    out = json.loads(r.out)
    assert out["params"]["relaxation_length_m"] == 0.3
    assert out["params"]["lateral_relaxation_length_m"] == 0.2
    header = csv.read_text().splitlines()[0].split(",")
    assert "lagged_slip_fl [-]" in header and "lagged_tan_alpha_rr [-]" in header


@pytest.mark.parametrize(
    ("value", "field"),
    [
        ("relaxation_length_m=-0.3", "--param relaxation_length_m"),
        ("relaxation_length_m=short", "--param relaxation_length_m"),
        ("lateral_relaxation_length_m=-1", "--param lateral_relaxation_length_m"),
        ("lateral_relaxation_length_m=inf", "--param lateral_relaxation_length_m"),
        ("relaxation_length_m=tire", "--param relaxation_length_m"),
    ],
)
def test_bad_lengths_get_one_line_and_exit_2(cli, value, field):
    r = cli("simulate", "abs-vehicle", "--param", value)
    assert r.code == 2, (r.out, r.err)
    lines = r.err.strip().splitlines()
    assert len(lines) == 1, r.err
    assert lines[0].startswith("chassistune: error: ") and field in lines[0]
