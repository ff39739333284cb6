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


@pytest.fixture(scope="module")
def small_tune():
    """One small PID tune of abs-wheel on dry concrete (shared)."""
    from chassistune.tuning.tune import tune

    return tune("abs-wheel", "pid", "pso", pop_size=6, max_iter=2, seed=0)


def _at(result, gains: dict[str, float]):
    """`result` as if the optimizer had ended at `gains` (its cost scored on the problem)."""
    import dataclasses

    import numpy as np

    x = np.array([[gains[n] for n in result.problem.gain_names]])
    return dataclasses.replace(result, best_gains=gains, fun=float(result.problem(x)[0]))


def test_tune_json_gives_the_default_gains_and_their_cost(cli, small_tune):
    from chassistune.scenarios.registry import get_plant

    r = cli("tune", "abs-wheel", "--optimizer", "pso", "--pop", "4", "--iters", "1", "--json")
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["default_gains"] == {"kp": 5000.0, "ki": 0.0, "kd": 230.0}
    sc = get_plant("abs-wheel").scenario(None, None, "pid")
    assert doc["default_cost"] == float(sc.cost(sc.gains_array(None)[None, :])[0])
    assert small_tune.default_cost == doc["default_cost"]
    worse = doc["best_cost"] > doc["default_cost"]
    assert worse  # four random candidates do not beat the registry's defaults
    lines = [x for x in r.err.splitlines() if "worse than the default gains'" in x]
    assert len(lines) == 1 and f"budget ({doc['nfev']} evaluations)" in lines[0], r.err


def test_the_text_output_shows_the_default_cost_beside_the_tuned(cli, small_tune):
    from chassistune.cli.common import fmt

    r = cli("tune", "abs-wheel", "--optimizer", "pso", "--pop", "4", "--iters", "1")
    assert r.code == 0, r.err
    cost = fmt(small_tune.default_cost)
    assert f"default gains: cost {cost} with kp=5000, ki=0, kd=230" in r.out
    assert "--gains" not in r.err  # never passed: no warning names it


def test_a_gain_at_its_floor_of_zero_is_no_cut_off_optimum(small_tune):
    at_floor = _at(small_tune, {"kp": 5000.0, "ki": 0.0, "kd": 230.0})
    assert at_floor.gains_cut_off() == []


def test_a_gain_at_a_bound_the_cost_falls_past_is_a_cut_off_optimum(small_tune):
    at_top = _at(small_tune, {"kp": 3498.3319284180607, "ki": 10000.0, "kd": 137.98294966885962})
    hits = at_top.gains_cut_off()
    assert [(h.gain, h.bound, h.probe) for h in hits] == [("ki", 1e4, 11000.0)]
    assert hits[0].probe_cost < at_top.best_cost


def test_the_quarter_cars_small_integral_gain_is_not_called_cut_off():
    from chassistune.tuning.tune import tune

    result = tune("quarter-car", "pid", "pso", pop_size=4, max_iter=1, seed=0)
    tuned = _at(result, {"kp": 356.48, "ki": 452.98, "kd": 210.61})  # iabc 100 x 100's result
    assert tuned.gains_cut_off() == []


def test_the_step_check_warning_names_the_step_to_tune_at(small_tune):
    import dataclasses

    from chassistune.scenarios.refine import StepCheck

    failed = dataclasses.replace(small_tune, step_checks={"ice": StepCheck(4, 1e-3, 1.0, 0.5, 1.0)})
    (line,) = failed.step_warnings()
    assert "ranking of candidates on ice is not meaningful at dt_s = 0.001" in line
    assert line.endswith("tune again with --param dt_s=0.00025")


def _readme_tune_lines() -> list[list[str]]:
    """The README tour's `chassistune tune ...` commands (continuation lines joined), as
    argument lists without `--out`."""
    import shlex

    text = (Path(__file__).parents[2] / "README.md").read_text(encoding="utf-8")
    text = text.replace("\\\n", " ")
    out = []
    for line in text.splitlines():
        if line.startswith("chassistune tune "):
            args = shlex.split(line.partition("#")[0])[1:]
            if "--out" in args:
                i = args.index("--out")
                del args[i : i + 2]
            out.append(args)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("args", _readme_tune_lines(), ids=lambda a: " ".join(a[1:6]))
def test_the_readmes_tune_examples_improve_on_the_default_gains(cli, args):
    assert len(_readme_tune_lines()) == 4
    r = cli(*args, "--json")
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["best_cost"] <= doc["default_cost"], (doc["best_cost"], doc["default_cost"])
    assert "worse than the default gains'" not in r.err


@pytest.mark.parametrize("ecu", ["ideal", "realistic"])
def test_simulate_r13h_adds_the_adhesion_utilisation(cli, ecu):
    from chassistune.scenarios.r13h import r13h_epsilon

    r = cli("simulate", "abs-wheel", "--ecu", ecu, "--r13h", "--json")
    assert r.code == 0, r.err
    m = json.loads(r.out)["metrics"]
    want = r13h_epsilon("pid", None, None, None, {"ecu": ecu})
    assert m["r13h_epsilon"] == want.epsilon
    assert m["r13h_z_al"] == want.z_al and m["r13h_k_adhesion"] == want.adhesion.k_m
    text = cli("simulate", "abs-wheel", "--ecu", ecu, "--r13h").out
    assert "r13h_epsilon [-]" in text


def test_r13h_is_refused_on_another_plant(cli):
    r = cli("simulate", "quarter-car", "--r13h")
    assert r.code == 2 and r.err.startswith("chassistune: error: --r13h:"), r.err


def test_the_comparison_draws_the_distance_not_a_constant_target_and_tuned_on_top(monkeypatch):
    import chassistune.plots.overlay as overlay
    from chassistune.plots.overlay import plot_results
    from chassistune.simulate import simulate

    seen = {}

    def keep(fig, path):
        seen["labels"] = [ax.get_ylabel() for ax in fig.axes if ax.get_visible()]
        seen["z"] = {line.get_label(): line.get_zorder() for line in fig.axes[0].get_lines()}

    monkeypatch.setattr(overlay, "save", keep)
    pid = simulate("abs-wheel", controller="pid")
    plot_results({"tuned": pid, "pid": pid, "none": simulate("abs-wheel", controller="none")}, "x")
    assert "distance_m [m]" in seen["labels"]
    assert not any(label.startswith("target_slip") for label in seen["labels"])
    z = {label.split(" (")[0]: order for label, order in seen["z"].items()}
    assert z["tuned"] > z["pid"] > z["none"]  # the same curve as pid, drawn over it


def test_export_says_which_sample_time_it_took_and_how_to_change_it(cli, tmp_path):
    r = cli("export", "--controller", "pid", "--format", "json", "--out", str(tmp_path / "e"))
    assert r.code == 0, r.err
    assert "sample time 0.005 s (the realistic ECU's default" in r.out
    assert "--param ecu_ts_s=SECONDS sets another" in r.out


def test_the_docs_say_what_a_new_user_needs():
    import re

    root = Path(__file__).parents[2]
    studies = (root / "docs" / "studies.md").read_text(encoding="utf-8")
    assert "required" in next(x for x in studies.splitlines() if x.startswith("seeds ="))
    for path in (root / "examples").rglob("*"):
        if path.is_file():
            assert not re.search(r"issue \d", path.read_text(encoding="utf-8"), re.I), path
    readme = (root / "README.md").read_text(encoding="utf-8")
    assert "skips with one line where `octave` is\nnot installed" in readme
