"""What a new user hit in `simulate` and `tune`, one test per fault (output preflight and Ctrl-C
have their own files), and the loading back and comparing they expected."""

from __future__ import annotations

import json

import numpy as np
import pytest

TUNE = (
    "tune",
    "abs-wheel",
    "--controller",
    "pid",
    "--optimizer",
    "pso",
    "--pop",
    "6",
    "--iters",
    "2",
)


def test_history_csv_holds_plain_numbers(cli, tmp_path):
    """history.csv holds numbers, not reprs such as `np.float64(0.0041...)`."""
    r = cli(*TUNE, "--out", str(tmp_path / "t"))
    assert r.code == 0, r.err
    lines = (tmp_path / "t" / "history.csv").read_text().splitlines()
    assert lines[0] == "iteration,nfev,best_cost" and len(lines) == 3
    for line in lines[1:]:
        it, nfev, cost = line.split(",")
        assert int(it) >= 1 and int(nfev) >= 6 and float(cost) > 0
        assert "np." not in line


def test_a_folder_tuned_into_twice_holds_one_set_of_files(cli, tmp_path):
    """A previous tune's response plots do not stay beside the new result."""
    out = tmp_path / "t"
    assert cli(*TUNE, "--road", "ice", "--road", "wet-asphalt", "--out", str(out)).code == 0
    assert (out / "response-ice.png").exists()
    assert cli(*TUNE, "--road", "dry-concrete", "--out", str(out)).code == 0
    assert sorted(p.name for p in out.glob("response-*.png")) == ["response-dry-concrete.png"]
    assert json.loads((out / "tune.json").read_text())["roads"] == ["dry-concrete"]


def test_a_run_that_did_not_stop_has_null_stop_metrics_and_says_why(cli):
    """`t_max_s=1` reports no stop distance or ratio (not 26 m and 0.51)."""
    r = cli("simulate", "abs-wheel", "--param", "t_max_s=1", "--json")
    m = json.loads(r.out)["metrics"]
    assert m["stopped"] is False and m["status"] == "timeout"
    assert m["stop_distance_m"] is None and m["distance_ratio"] is None
    assert m["stop_time_s"] is None
    r = cli("simulate", "abs-wheel", "--param", "t_max_s=1")
    assert r.code == 0 and "did not stop (timeout): t_max_s was reached" in r.out


def test_a_penalty_only_tune_says_so_and_exits_1(cli):
    """A tune whose every candidate is penalized does not print "best gains" and exit 0."""
    r = cli(*TUNE, "--param", "t_max_s=1")
    assert r.code == 1
    assert r.err.count("\n") == 1 and "no candidate of 18 could be scored" in r.err
    assert "dry-concrete: timeout" in r.err


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["--param", "t_max_s=1e9"], "--param t_max_s"),
        (["--param", "dt_s=1e-8"], "--param dt_s"),
        (["--param", "v_stop_m_s=40"], "--param v_stop_m_s"),
        (["--param", "v0_m_s=0.3"], "--param v0_m_s"),
        (["--controller", "none", "--gains", "kp=1"], "--gains"),
    ],
)
def test_errors_name_the_field_the_user_set(cli, args, field):
    """t_max_s=1e9 blames t_max_s (not dt_s), v_stop_m_s=40 blames v_stop_m_s (not v0_m_s), and
    `none` is not listed as "known: none"."""
    r = cli("simulate", "abs-wheel", *args)
    assert r.code == 2 and r.err.count("\n") == 1
    assert r.err.startswith(f"chassistune: error: {field}: "), r.err
    assert "known: none" not in r.err


def test_tune_pop_1_names_the_option_on_one_line(cli):
    """`--pop 1` names `--pop` on one line (not pop_size after an empty line)."""
    r = cli(*TUNE[:-4], "--pop", "1", "--iters", "2")
    assert r.code == 2 and r.err.count("\n") == 1 and r.err.startswith("chassistune: error: --pop")


def test_mu_lock_above_mu_peak_is_bad_input(cli):
    """mu_lock = 2 above mu_peak = 0.9 is refused (the bound would use mu 2)."""
    r = cli("simulate", "abs-wheel", "--param", "mu_lock=2")
    assert r.code == 2 and r.err.startswith(
        "chassistune: error: --param mu_lock: must not exceed mu_peak"
    )


def test_a_warning_is_shown_once_per_command(capsys):
    """The same warning raised again (a file read for every case of a study) is one stderr line;
    the next command shows it again."""
    import warnings

    from chassistune.cli.main import _warning_printer

    for _ in range(2):
        show = _warning_printer()
        for _ in range(3):
            show(UserWarning("tire.tir: 17 coefficients absent"), UserWarning, "x.py", 1)
        show(UserWarning("another"), UserWarning, "x.py", 2)
        assert capsys.readouterr().err.splitlines() == [
            "chassistune: warning: tire.tir: 17 coefficients absent",
            "chassistune: warning: another",
        ]
    assert warnings.showwarning is not show


@pytest.mark.parametrize(
    "assignment", ["mass_kg=1e30", "wheel_radius_m=500", "v0_m_s=108", "wheel_inertia_kg_m2=400"]
)
def test_implausible_values_warn_on_one_line_and_run(cli, assignment):
    """Absurd values run, with a one-line warning."""
    r = cli("simulate", "abs-wheel", "--controller", "none", "--param", assignment, "--json")
    assert r.code == 0 and json.loads(r.out)["plant"] == "abs-wheel"
    name = assignment.split("=")[0]
    assert r.err.startswith(f"chassistune: warning: --param {name}: ")
    assert r.err.count("\n") == 1 and "plausible range" in r.err


def test_bad_input_prints_only_the_error_line(cli):
    r = cli("simulate", "abs-wheel", "--param", "v0_m_s=108", "--param", "mu_lock=2")
    assert r.code == 2 and r.err.count("\n") == 1 and "warning" not in r.err


def test_every_preset_is_inside_its_plausible_ranges(recwarn):
    from chassistune.params import ImplausibleValue
    from chassistune.scenarios.registry import get_plant

    plant = get_plant("abs-wheel")
    for name, info in plant.presets().items():
        for road in info.roads:
            plant.scenario(name, road, "pid")
    assert not [w for w in recwarn if issubclass(w.category, ImplausibleValue)]


def test_a_numerical_blow_up_is_named_diverged(cli):
    """Gains of 1e300 give status `diverged`, not `hopeless`."""
    r = cli("simulate", "abs-wheel", "--gains", "kp=1e300,kd=1e300", "--json")
    m = json.loads(r.out)["metrics"]
    assert m["status"] == "diverged" and m["stopped"] is False


def test_the_default_time_limit_follows_the_bound_time(cli):
    """On burckhardt-ice (bound time 60.14 s) a flat 60 s limit would stop no controller."""
    doc = json.loads(cli("simulate", "abs-wheel", "--road", "burckhardt-ice", "--json").out)
    bound = doc["metrics"]["bound_time_s"]
    assert bound > 60 and doc["params"]["t_max_s"] == pytest.approx(3 * bound)
    assert doc["metrics"]["stopped"] is True
    dry = json.loads(cli("simulate", "abs-wheel", "--json").out)
    assert dry["params"]["t_max_s"] == 60.0  # short bound times keep the 60 s floor
    explicit = json.loads(
        cli(
            "simulate", "abs-wheel", "--road", "burckhardt-ice", "--param", "t_max_s=60", "--json"
        ).out
    )
    assert explicit["params"]["t_max_s"] == 60.0 and explicit["metrics"]["stopped"] is False


def test_a_budget_below_one_population_is_refused(cli):
    """`--evals 5` with pop 30 (zero iterations) is refused."""
    r = cli("tune", "abs-wheel", "--controller", "pid", "--optimizer", "pso", "--evals", "5")
    assert r.code == 2 and r.err.startswith("chassistune: error: --evals: 5 evaluations")
    r = cli("tune", "--help")
    assert "whichever comes first" in " ".join(r.out.split())


def test_a_tune_result_loads_back_and_compares(cli, tmp_path):
    """`simulate --from`, `--gains @file`, `--compare`: the tuned gains in full precision."""
    out = tmp_path / "t"
    assert cli(*TUNE, "--road", "wet-asphalt", "--param", "v0_m_s=25", "--out", str(out)).code == 0
    tuned = json.loads((out / "tune.json").read_text())
    again = json.loads(cli("simulate", "--from", str(out), "--json").out)
    assert again["road"] == "wet-asphalt" and again["params"]["v0_m_s"] == 25.0
    assert again["gains"] == tuned["best_gains"]
    assert again["metrics"]["slip_itae"] == tuned["metrics"]["slip_itae"]
    via_file = json.loads(
        cli(
            "simulate",
            "abs-wheel",
            "--road",
            "wet-asphalt",
            "--param",
            "v0_m_s=25",
            "--gains",
            f"@{out / 'best_gains.json'}",
            "--json",
        ).out
    )
    assert via_file["metrics"] == again["metrics"]
    png = tmp_path / "cmp.png"
    r = cli(
        "simulate",
        "--from",
        str(out / "tune.json"),
        "--compare",
        "none,pid",
        "--plot",
        str(png),
        "--json",
    )
    runs = json.loads(r.out)["runs"]
    assert list(runs) == ["tuned", "none", "pid"] and png.stat().st_size > 0
    assert runs["tuned"]["gains"] == tuned["best_gains"]
    assert runs["pid"]["gains"] != tuned["best_gains"]  # the registry's defaults
    assert runs["none"]["metrics"]["stop_distance_m"] > runs["tuned"]["metrics"]["stop_distance_m"]


def test_compare_in_the_python_api(tmp_path):
    import chassistune

    cmp = chassistune.compare("abs-wheel", ["none", "threshold"], road="ice")
    rows = cmp.table()
    assert [r["label"] for r in rows] == ["none", "threshold"]
    assert np.isfinite(rows[0]["stop_distance_m"])
    cmp.plot(str(tmp_path / "c.png"))
    cmp.results["threshold"].plot(str(tmp_path / "one.png"))
    assert (tmp_path / "c.png").exists() and (tmp_path / "one.png").exists()


def test_list_params_gives_unit_default_valid_and_plausible_range(cli):
    doc = json.loads(cli("list", "params", "abs-wheel", "--json").out)["params"]
    plant = {f["name"]: f for f in doc["plant"]}
    assert plant["wheel_inertia_kg_m2"]["unit"] == "kg m^2"
    assert plant["wheel_inertia_kg_m2"]["default"] == 12.0
    lo, hi = plant["wheel_inertia_kg_m2"]["plausible"]
    assert lo <= 12.0 <= hi and lo <= 25.0 <= hi  # both papers' wheel inertias
    assert plant["mass_kg"]["valid"] == "> 0"
    scoring = {f["name"]: f for f in doc["scoring"]}
    assert scoring["lock_penalty_per_s"]["unit"] == "1/s"
    sldemo = json.loads(cli("list", "params", "abs-wheel", "--preset", "sldemo", "--json").out)[
        "params"
    ]
    assert {f["name"]: f for f in sldemo["plant"]}["load_fraction"]["default"] == 0.25
    r = cli("list", "params")
    assert r.code == 2 and r.err.startswith("chassistune: error: PLANT")
    r = cli("list", "params", "abs-wheel")
    assert r.code == 0 and "plausible [0.1, 50]" in r.out


def test_the_first_use_announces_compiling_and_bad_input_does_not(cli):
    r = cli("tune", "abs-wheel", "--controller", "pid", "--optimizer", "pso", "--pop", "1")
    assert r.code == 2 and r.err.count("\n") == 1  # bad input: only the error line


def test_a_compilation_is_announced_as_it_starts_and_only_then() -> None:
    """The notice comes from numba's compile event (after a cache miss, for the very function
    and argument types): once per compiled signature, naming the function, with an estimate;
    nothing for a call that is already compiled."""
    from numba import njit

    from chassistune._compile_notice import announcing

    @njit(cache=False)
    def twice(x):  # type: ignore[no-untyped-def]
        return 2 * x

    lines: list[str] = []
    with announcing(lines.append):
        twice(1.0)
        twice(2.0)
        twice(3)
    assert len(lines) == 2 and all("compiling test_new_user_cli.twice" in x for x in lines)
    assert all("about 3 s on an idle core" in x for x in lines)
    twice(4j)
    assert len(lines) == 2  # outside: silent


def test_tune_reports_test_roads_and_warns_of_gains_at_their_bounds(cli):
    r = cli(*TUNE, "--test-road", "ice", "--test-road", "wet-asphalt", "--json")
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert set(doc["test_metrics"]) == {"ice", "wet-asphalt"}
    assert doc["test_metrics"]["ice"]["bound_distance_m"] > doc["metrics"]["bound_distance_m"]
    r = cli(*TUNE, "--test-road", "moon")
    assert r.code == 2 and r.err.startswith("chassistune: error: --test-road: unknown road")


def test_gains_the_box_cuts_off_are_found():
    from chassistune.tuning.tune import tune

    result = tune("abs-wheel", "pid", "pso", pop_size=6, max_iter=1, seed=3)
    lo_hi = dict(zip(result.problem.gain_names, result.problem.bounds, strict=True))
    for tolerance in (1.0, 0.01):
        for hit in result.gains_cut_off(tolerance=tolerance):
            lo, hi = lo_hi[hit.gain]
            assert hit.bound in (lo, hi) and hit.bound != 0.0
            assert abs(hit.value - hit.bound) <= tolerance * (hi - lo)
            assert not lo <= hit.probe <= hi and hit.probe_cost < result.best_cost
