"""`--tire FILE.tir` on `simulate` and `tune` of abs-wheel: the Magic Formula tire on its own
surface or scaled to a road, with the ideal or the realistic ECU; refused in one line (exit 2)
for a bad file and where it does not run yet (the vehicle, `--vary`)."""

from __future__ import annotations

import json
from importlib.resources import files
from pathlib import Path

import pytest

from chassistune.plants.mf_peak import braking_friction_peak
from chassistune.plants.tir import read_tir_file

CHRONO = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")
GAINS = "kp=5000,kd=230"


def _json(cli, *args: str) -> dict:  # type: ignore[no-untyped-def]
    r = cli("simulate", "abs-wheel", "--tire", CHRONO, "--gains", GAINS, "--json", *args)
    assert r.code == 0, r.err
    return json.loads(r.out)


def test_without_a_road_the_tire_runs_on_its_own_surface(cli) -> None:
    doc = _json(cli)
    assert doc["road"] == "tire-surface"
    assert doc["params"]["tire"] == CHRONO
    m = doc["metrics"]
    assert m["status"] == "stopped" and m["stop_distance_m"] >= m["bound_distance_m"]
    p = doc["params"]
    fz_n = p["load_fraction"] * p["mass_kg"] * p["g_m_s2"]
    mu_peak = braking_friction_peak(read_tir_file(CHRONO).tire, fz_n)
    decel = mu_peak * p["g_m_s2"] * p["load_fraction"]
    bound = (p["v0_m_s"] ** 2 - p["v_stop_m_s"] ** 2) / (2.0 * decel)
    assert m["bound_distance_m"] == pytest.approx(bound, rel=1e-12)


def test_a_road_scales_the_tire_to_its_peak(cli) -> None:
    own = _json(cli)["metrics"]
    ice = _json(cli, "--road", "ice")
    assert ice["road"] == "ice" and ice["params"]["tire"] == CHRONO
    ratio = ice["metrics"]["bound_distance_m"] / own["bound_distance_m"]
    mu_own = ratio * 0.1028  # the bounds scale as 1 / mu_peak
    assert 1.0 < mu_own < 1.2  # Chrono's tire peaks at 1.09-1.15 over these loads


def test_a_bad_file_is_one_line_naming_its_line(cli, tmp_path: Path) -> None:
    text = Path(CHRONO).read_text(encoding="utf-8").replace("PDX1", "PDX1 = x\nPDX1_", 1)
    path = tmp_path / "bad.tir"
    path.write_text(text, encoding="utf-8")
    r = cli("simulate", "abs-wheel", "--tire", str(path))
    assert r.code == 2 and r.out == ""
    line = next(i for i, ln in enumerate(text.splitlines(), 1) if ln.startswith("PDX1 = x"))
    assert r.err.startswith(f"chassistune: error: {path}:{line}: ")
    assert len(r.err.splitlines()) == 1


@pytest.mark.parametrize(
    "args",
    [
        ("simulate", "quarter-car"),
        ("tune", "abs-wheel", "--optimizer", "de", "--vary", "mass_kg=300:400"),
    ],
)
def test_where_it_does_not_run_yet_it_is_refused_naming_tire(cli, args: tuple[str, ...]) -> None:
    r = cli(*args, "--tire", CHRONO)
    assert r.code == 2 and r.out == ""
    assert r.err.startswith("chassistune: error: --tire: ")
    assert len(r.err.splitlines()) == 1


def test_the_realistic_ecu_runs_on_the_tire(cli) -> None:
    r = cli("simulate", "abs-wheel", "--ecu", "realistic", "--tire", CHRONO, "--json")
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["params"]["tire"] == CHRONO and doc["params"]["ecu"] == "realistic"
    assert doc["metrics"]["status"] == "stopped"


def test_tune_on_the_tire(cli) -> None:
    r = cli(
        "tune", "abs-wheel", "--tire", CHRONO, "--optimizer", "de", "--pop", "6", "--iters",
        "2", "--json",
    )  # fmt: skip
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["roads"] == ["tire-surface"] and doc["params"]["tire"] == CHRONO


def test_a_tune_on_the_tire_replays_with_from(cli, tmp_path: Path) -> None:
    out = tmp_path / "run"
    r = cli(
        "tune", "abs-wheel", "--tire", CHRONO, "--optimizer", "de", "--pop", "6", "--iters",
        "2", "--out", str(out),
    )  # fmt: skip
    assert r.code == 0, r.err
    again = cli("simulate", "--from", str(out), "--json")
    assert again.code == 0, again.err
    doc = json.loads(again.out)
    assert doc["road"] == "tire-surface" and doc["params"]["tire"] == CHRONO


def test_export_refuses_the_tire_in_one_line(cli, tmp_path: Path) -> None:
    """The export's closed loop and C test vectors have no Magic Formula tire: refused, exit 2,
    before any file is written."""
    out = tmp_path / "ecu"
    r = cli(
        "export", "--plant", "abs-wheel", "--controller", "pid", "--param", f"tire={CHRONO}",
        "--format", "json", "--out", str(out),
    )  # fmt: skip
    assert r.code == 2 and r.out == ""
    assert r.err.startswith("chassistune: error: --param tire: ")
    assert len(r.err.splitlines()) == 1
    assert not any(out.glob("*")) if out.exists() else True


def test_the_vehicle_runs_on_the_tire_at_the_step_it_needs(cli) -> None:
    """The paper preset's 1 ms is past RK4's limit with the file's stiffness: refused in one line
    naming the step that passes (no warning about the file before it); at that step it runs."""
    r = cli("simulate", "abs-vehicle", "--tire", CHRONO)
    assert r.code == 2 and r.out == ""
    assert r.err.startswith("chassistune: error: --param dt_s: ") and len(r.err.splitlines()) == 1
    assert "dt_s = 0.0002 (the step divided by 5) passes" in r.err
    r = cli(
        "simulate", "abs-vehicle", "--tire", CHRONO, "--json",
        "--param", "dt_s=0.0002", "--param", "v0_m_s=15",
    )  # fmt: skip
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["params"]["tire"] == CHRONO and doc["road"] == "tire-surface"
    assert doc["metrics"]["status"] == "stopped"
    assert doc["metrics"]["stop_distance_m"] >= doc["metrics"]["bound_distance_m"]
