"""What went wrong in a new user's first hour: the tune's defaults and checks, `list params`,
output checks, units and `simulate --r13h`; one test (or more) per fault."""

from __future__ import annotations

import json
from pathlib import Path

import pytest


def test_tune_defaults_to_pid(cli):
    r = cli("tune", "abs-wheel", "--optimizer", "pso", "--pop", "4", "--iters", "1", "--json")
    assert r.code == 0, r.err
    assert json.loads(r.out)["controller"] == "pid"


def test_tune_checks_every_given_option_before_a_missing_one(cli):
    r = cli("tune", "abs-wheel", "--controller", "pidd")
    assert r.code == 2 and "--controller" in r.err and "pidd" in r.err, r.err
    r = cli("tune", "abs-wheel", "--controller", "pid")
    assert r.code == 2, r.err
    assert r.err.strip() == "chassistune: error: --optimizer: missing (chassistune list optimizers)"


def test_list_params_prints_a_table_road_as_plain_numbers(cli):
    r = cli("list", "params", "abs-wheel", "--preset", "sldemo")
    assert r.code == 0, r.err
    assert "np.float64" not in r.out
    assert "(0, 0.05, 0.1," in r.out


def _listed(cli, plant: str) -> dict[str, list[str]]:
    """`list params PLANT --json`: group -> names of its parameters."""
    r = cli("list", "params", plant, "--json")
    assert r.code == 0, r.err
    return {g: [f["name"] for f in fields] for g, fields in json.loads(r.out)["params"].items()}


def test_list_params_names_the_controller_parameters_param_sets(cli):
    from chassistune.cli.list_cmd import CONTROLLER_GROUP

    names = _listed(cli, "abs-wheel")[CONTROLLER_GROUP]
    for name in ("target_slip", "n_filter", "ts_s", "amplitude", "decel_threshold_m_s2"):
        assert name in names
    r = cli("list", "params", "abs-wheel", "--json")
    rows = json.loads(r.out)["params"][CONTROLLER_GROUP]
    assert {"name": "n_filter", "controllers": ["pid", "fuzzy-pid"]}.items() <= {
        k: v for row in rows if row["name"] == "n_filter" for k, v in row.items()
    }.items()
    assert "n_filter" in _listed(cli, "abs-vehicle")[CONTROLLER_GROUP]


def test_list_params_of_the_quarter_car_lists_its_parameters(cli):
    groups = _listed(cli, "quarter-car")
    names = [n for fields in groups.values() for n in fields]
    for name in ("sprung_mass_kg", "damper_n_s_m", "speed_m_s", "dt_s", "n_filter", "feedback"):
        assert name in names


def test_the_quarter_car_warns_about_an_implausible_value():
    from chassistune.params import ImplausibleValue
    from chassistune.scenarios.registry import get_plant

    with pytest.warns(ImplausibleValue, match="sprung_mass_kg: 5 kg is outside"):
        get_plant("quarter-car").scenario(None, None, "pid", {"sprung_mass_kg": "5"})
    with pytest.warns(ImplausibleValue, match="speed_m_s: 200 m/s"):
        get_plant("quarter-car").scenario(None, None, "pid", {"speed_m_s": "200"})


def _read_only(tmp_path):
    """A folder this process cannot write in: mode 0o555, or for root the read-only /sys."""
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    for candidate in (folder, Path("/sys")):
        try:
            (candidate / ".chassistune-probe").write_text("")
        except OSError:
            return candidate
        (candidate / ".chassistune-probe").unlink()
    pytest.skip("no read-only folder here")


@pytest.mark.parametrize(
    ("args", "option"),
    [(("reproduce", "all", "--quick", "--out"), "--out"), (("study", "report"), "DIR")],
)
def test_an_unwritable_output_is_refused_before_any_work(cli, tmp_path, monkeypatch, args, option):
    import chassistune.papers.reproduce
    import chassistune.reports.build

    def no_work(*a: object, **k: object) -> None:
        raise AssertionError("work started before the output was checked")

    monkeypatch.setattr(chassistune.papers.reproduce, "plan_reproduction", no_work)
    monkeypatch.setattr(chassistune.reports.build, "build_report", no_work)
    folder = _read_only(tmp_path)
    target = folder if option == "DIR" else folder / "rep"
    r = cli(*args, str(target))
    assert r.code == 2, r.err
    assert r.err.startswith(f"chassistune: error: {option}: cannot write in"), r.err
    assert r.err.count("\n") == 1
