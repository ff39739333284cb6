"""Measured roads: a mu-slip table read from a CSV file."""

from __future__ import annotations

import json

import numpy as np
import pytest

from chassistune.errors import InputError
from chassistune.plants.roads import read_mu_slip_csv, tire_for_road
from chassistune.plants.tires import MAX_TABLE_NODES, SLDEMO_TABLE, TableTire


def _write(path, rows, header="slip,mu"):
    path.write_text(header + "\n" + "".join(f"{s},{m}\n" for s, m in rows))
    return str(path)


def test_a_csv_of_the_sldemo_table_simulates_bit_identically(tmp_path):
    from chassistune.simulate import simulate

    nodes = zip(SLDEMO_TABLE.slips, SLDEMO_TABLE.mus, strict=True)
    path = _write(tmp_path / "sldemo.csv", [(repr(float(s)), repr(float(m))) for s, m in nodes])
    assert read_mu_slip_csv(path) == SLDEMO_TABLE
    ours = simulate("abs-wheel", "sldemo", path, "pid", {"mu_scale": 0.8})
    theirs = simulate("abs-wheel", "sldemo", "sldemo-table", "pid", {"mu_scale": 0.8})
    assert json.dumps(ours.metrics) == json.dumps(theirs.metrics)
    for name, signal in theirs.trace.signals.items():
        assert np.array_equal(ours.trace.signals[name], signal, equal_nan=True), name
    assert ours.scenario.road == path


def test_columns_are_found_by_name_and_other_columns_ignored(tmp_path):
    path = tmp_path / "m.csv"
    path.write_text("note,MU , Slip\na,0,0\nb,0.9,0.15\n\nc,0.6,1\n")
    tire = read_mu_slip_csv(str(path))
    assert tire == TableTire((0.0, 0.15, 1.0), (0.0, 0.9, 0.6))
    assert tire.peak() == (0.9, 0.15, 0.15)
    scaled, used = tire_for_road(str(path), {"mu_scale": 0.5, "mass_kg": 1.0})
    assert used == {"mu_scale"} and scaled.peak()[0] == pytest.approx(0.45)


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        ([(0, 0), (0.2, "x"), (1, 0.5)], "row 3, column mu: expected a finite number, got 'x'"),
        ([(0, 0), ("", 0.8), (1, 0.5)], "row 3, column slip: expected a finite number, got ''"),
        ([(0, 0), (0.2, "nan"), (1, 0.5)], "row 3, column mu: expected a finite number"),
        (
            [(0, 0), (0.3, 0.8), (0.2, 0.9), (1, 0.5)],
            "row 4, column slip: slips must increase strictly, got 0.2 after 0.3",
        ),
        ([(0, 0), (0.2, 0.8), (0.2, 0.9), (1, 0.5)], "row 4, column slip: slips must increase"),
        ([(0, 0), (0.2, -0.1), (1, 0.5)], "row 3, column mu: must be a finite number >= 0"),
        ([(0.05, 0), (0.2, 0.8), (1, 0.5)], "row 2, column slip: the first slip must be 0"),
        ([(0, 0.1), (0.2, 0.8), (1, 0.5)], "row 2, column mu: mu at slip 0 must be 0"),
        ([(0, 0), (0.2, 0.8), (0.9, 0.5)], "row 4, column slip: the last slip must be 1"),
        ([(0, 0)], "rows: needs 2 to 32 (slip, mu) nodes, got 1"),
        (
            [
                (k / (MAX_TABLE_NODES), 0.5 * k / MAX_TABLE_NODES)
                for k in range(MAX_TABLE_NODES + 1)
            ],
            f"rows: needs 2 to 32 (slip, mu) nodes, got {MAX_TABLE_NODES + 1}",
        ),
    ],
)
def test_a_bad_table_names_its_row_and_column(tmp_path, rows, message):
    path = _write(tmp_path / "bad.csv", rows)
    with pytest.raises(InputError) as exc:
        tire_for_road(path, {})
    assert exc.value.field == "road"
    assert exc.value.problem.startswith(f"{path} {message}")


def test_thirty_two_nodes_are_accepted(tmp_path):
    n = MAX_TABLE_NODES
    rows = [(repr(k / (n - 1)), repr(min(1.0, 5.0 * k / (n - 1)))) for k in range(n)]
    tire = read_mu_slip_csv(_write(tmp_path / "full.csv", rows))
    assert len(tire.slips) == n and tire.peak()[0] == 1.0


def test_a_header_without_slip_or_mu_and_a_missing_file_are_bad_input(tmp_path):
    path = _write(tmp_path / "h.csv", [(0, 0), (1, 0.5)], header="s,mu")
    with pytest.raises(
        InputError,
        match=r"row 1: the header needs the columns slip and mu "
        r"\(missing: slip\)",
    ):
        read_mu_slip_csv(path)
    with pytest.raises(InputError, match=r"cannot read .*nope\.csv.*No such file"):
        tire_for_road(str(tmp_path / "nope.csv"), {})


def test_the_python_table_refuses_what_the_file_refuses():
    with pytest.raises(InputError, match=r"node 2 \(slip\): slips must increase strictly"):
        TableTire((0.0, 0.0, 1.0), (0.0, 0.5, 0.4))


def test_the_cli_takes_a_csv_road_and_names_the_row(cli, tmp_path):
    good = _write(tmp_path / "m.csv", [(0, 0), (0.12, 0.85), (1, 0.55)])
    r = cli("simulate", "abs-wheel", "--road", good, "--json")
    assert r.code == 0, r.err
    assert json.loads(r.out)["road"] == good
    bad = _write(tmp_path / "b.csv", [(0, 0), (0.12, "high"), (1, 0.55)])
    r = cli("simulate", "abs-wheel", "--road", bad)
    assert r.code == 2
    assert r.err == (
        f"chassistune: error: --road: {bad} row 3, column mu: expected a finite "
        "number, got 'high'\n"
    )
