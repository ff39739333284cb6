"""Bad inputs a careful tester tried: road tables that cannot brake or are malformed, numbers with
digit separators, oversized input files, tampered tune results, budgets and sizes past what the
machine holds. Each is refused in one line naming the field, before any work."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest

from chassistune import memory
from chassistune.errors import InputError
from chassistune.params import ImplausibleValue, to_float
from chassistune.plants.roads import MAX_CSV_BYTES, read_mu_slip_csv, tire_for_road
from chassistune.plants.tires import TableTire


def _csv(path: Path, text: str) -> str:
    path.write_text(text, encoding="utf-8")
    return str(path)


# -- road tables -----------------------------------------------------------------------------------


def test_a_road_that_cannot_brake_is_refused_by_every_command(cli, tmp_path):
    road = _csv(tmp_path / "zero.csv", "slip,mu\n0,0\n0.5,0\n1,0\n")
    out = tmp_path / "x"
    with pytest.raises(InputError, match=r"cannot brake: its peak mu is 0"):
        tire_for_road(road, {})
    with pytest.raises(InputError, match=r"burckhardt-ice cannot brake: its peak mu is 0"):
        tire_for_road("burckhardt-ice", {"c3": "100"})  # falls from mu = 0 at zero slip
    for args in (
        ("simulate", "abs-wheel", "--road", road),
        ("tune", "abs-wheel", "--road", road, "--controller", "pid", "--optimizer", "pso"),
        ("export", "--controller", "pid", "--road", road, "--format", "c", "--out", str(out)),
    ):
        r = cli(*args)
        assert (r.code, r.out) == (2, ""), args
        assert (
            r.err == f"chassistune: error: --road: {road} cannot brake: its peak mu is 0 "
            "(must be > 0)\n"
        ), args
    assert not out.exists()


def test_only_an_implausible_peak_mu_is_warned_about(tmp_path):
    for mu, expected in (("50", "50"), ("1e308", "1e+308"), ("0.9", None)):
        road = _csv(tmp_path / "grippy.csv", f"slip,mu\n0,0\n0.2,{mu}\n1,0.5\n")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            tire_for_road(road, {})
        said = [(w.message.field, w.message.problem) for w in caught]  # type: ignore[union-attr]
        assert all(isinstance(w.message, ImplausibleValue) for w in caught)
        assert said == (
            [("road", f"{road}: peak mu {expected} is outside the plausible range [0.05, 1.5]")]
            if expected
            else []
        )


def test_a_byte_order_mark_is_accepted(tmp_path):
    path = tmp_path / "excel.csv"
    path.write_bytes(b"\xef\xbb\xbfslip,mu\r\n0,0\r\n0.2,0.9\r\n1,0.7\r\n")
    assert read_mu_slip_csv(str(path)) == TableTire((0.0, 0.2, 1.0), (0.0, 0.9, 0.7))


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        ("slip,mu\n0,0\n0.2,0_9\n1,0.7\n", "row 3, column mu: expected a finite number, got '0_9'"),
        ("slip,mu\n0,0\n0.2,0.9,5\n1,0.7\n", "row 3: 3 fields, more than the header's 2"),
        ("slip,mu,mu\n0,0,0\n0.2,0.9,0.9\n1,0.7,0.7\n", "row 1: the column mu is named twice"),
        ("Slip,slip,mu\n0,0,0\n0.2,0.2,0.9\n1,1,0.7\n", "row 1: the column slip is named twice"),
    ],
)
def test_a_malformed_table_names_its_row(tmp_path, text, problem):
    road = _csv(tmp_path / "bad.csv", text)
    with pytest.raises(InputError) as exc:
        read_mu_slip_csv(road)
    assert (exc.value.field, exc.value.problem) == ("road", f"{road} {problem}")


def test_a_road_file_past_the_size_cap_is_refused_without_reading_it_whole(tmp_path):
    big = tmp_path / "big.csv"
    big.write_text("slip,mu\n" + "0,0\n" * (MAX_CSV_BYTES // 4))
    with pytest.raises(InputError, match=r"is larger than 65,536 bytes"):
        read_mu_slip_csv(str(big))
    zero = tmp_path / "zero-device.csv"
    zero.symlink_to("/dev/zero")
    with pytest.raises(InputError, match=r"is larger than 65,536 bytes"):
        read_mu_slip_csv(str(zero))


@pytest.mark.parametrize("text", ["1_0", "1_000.5"])
def test_digit_separators_are_not_numbers(text):
    with pytest.raises(InputError, match="not a number"):
        to_float(text, "params.mass_kg")


def test_a_param_with_a_digit_separator_is_refused_on_the_command_line(cli):
    r = cli("simulate", "abs-wheel", "--param", "mass_kg=1_0")
    assert (r.code, r.err) == (2, "chassistune: error: --param mass_kg: not a number: '1_0'\n")


# -- tampered tune results -------------------------------------------------------------------------

TUNED = {
    "plant": "abs-wheel",
    "preset": "paper-derlsp-ao",
    "roads": ["dry-concrete"],
    "controller": "pid",
    "best_gains": {"kp": 4000.0, "ki": 10.0, "kd": 200.0},
    "params": {"seed": 0},
}
"""The keys of a tune.json that `simulate --from` and `export` read."""


def _tune_json(tmp_path: Path, **changes: object) -> str:
    doc = {**TUNED, **changes}
    path = tmp_path / "tune.json"
    path.write_text(json.dumps(doc))
    return str(path)


def test_a_tune_result_missing_a_gain_is_refused_where_the_whole_one_works(cli, tmp_path):
    source = _tune_json(tmp_path)
    r = cli("simulate", "--from", source, "--json")
    assert r.code == 0, r.err
    assert json.loads(r.out)["gains"] == TUNED["best_gains"]
    r = cli("export", source, "--format", "json", "--out", str(tmp_path / "ok"))
    assert r.code == 0, r.err
    source = _tune_json(tmp_path, best_gains={"kp": 4000.0, "ki": 10.0})
    for args in (("simulate", "--from", source), ("export", source, "--format", "c")):
        r = cli(*args, *(("--out", str(tmp_path / "c")) if args[0] == "export" else ()))
        assert r.code == 2 and r.err.endswith(
            f"{source}: best_gains.kd: missing (a tuned pid has kp, ki, kd)\n"
        ), args


@pytest.mark.parametrize(
    ("changes", "problem"),
    [
        ({"roads": []}, "roads: expected a non-empty list of road names, got []"),
        ({"roads": "ice"}, "roads: expected a non-empty list of road names, got 'ice'"),
        (
            {"best_gains": [1, 2, 3]},
            "best_gains: expected an object of name -> value, got [1, 2, 3]",
        ),
        (
            {"best_gains": {"kp": 4000.0, "ki": 10.0}},
            "best_gains.kd: missing (a tuned pid has kp, ki, kd)",
        ),
        (
            {"best_gains": {"kp": True, "ki": 10.0, "kd": 200.0}},
            "best_gains.kp: expected a number, got True",
        ),
        (
            {"best_gains": {"kp": "4000", "ki": 10.0, "kd": 200.0}},
            "best_gains.kp: expected a number, got '4000'",
        ),
        ({"params": None}, "params: expected an object of name -> value, got None"),
        ({"controller": 3}, "controller: expected a name, got 3"),
    ],
)
def test_a_tampered_tune_result_is_refused_naming_its_key(cli, tmp_path, changes, problem):
    source = _tune_json(tmp_path, **changes)
    r = cli("simulate", "--from", source)
    assert (r.code, r.out, r.err) == (2, "", f"chassistune: error: --from: {source}: {problem}\n")
    r = cli("export", source, "--format", "c", "--out", str(tmp_path / "c"))
    assert (r.code, r.out, r.err) == (2, "", f"chassistune: error: SOURCE: {source}: {problem}\n")
    assert not (tmp_path / "c").exists()


# -- study configs ---------------------------------------------------------------------------------

STUDY = """[study]
name = "t"
seeds = 1
[[scenarios]]
plant = "abs-wheel"
roads = ["dry-concrete"]
controller = "pid"
{scenario}
[[optimizers]]
name = "pso"
{optimizer}
[budget]
{budget}
"""


@pytest.mark.parametrize(
    ("parts", "message"),
    [
        (
            {"budget": "pop_size = 10\nevaluations = 5"},
            "budget.evaluations: 5 evaluations do not cover one population of 10: "
            "no iteration would run",
        ),
        (
            {"scenario": "[scenarios.budget]\npop_size = 8\nevaluations = 7"},
            "scenarios[0].budget.evaluations: 7 evaluations do not cover one population of 8: "
            "no iteration would run",
        ),
        (
            {"scenario": "[scenarios.bounds]\nkp = [-1e308, 1e308]"},
            "scenarios[0].bounds.kp: the range hi - lo of [-1e+308, 1e+308] overflows a float",
        ),
        (
            {"optimizer": 'hyperparameters = {w = "x"}'},
            "optimizers[0].hyperparameters.w: expected a number, got 'x'",
        ),
    ],
)
def test_a_bad_study_config_is_refused_before_any_work(cli, tmp_path, parts, message):
    config = tmp_path / "s.toml"
    text = {"scenario": "", "optimizer": "", "budget": "pop_size = 10\niterations = 2", **parts}
    config.write_text(STUDY.format(**text))
    out = tmp_path / "st"
    r = cli("study", "run", str(config), "--out", str(out))
    assert (r.code, r.out, r.err) == (2, "", f"chassistune: error: {message}\n")
    assert not out.exists()


# -- memory ----------------------------------------------------------------------------------------


@pytest.fixture
def one_gib(monkeypatch):
    """A machine with 1 GiB available: the estimates decide, nothing is allocated."""
    monkeypatch.setattr(memory, "available_bytes", lambda: memory.GIB)


def test_a_population_past_the_machine_is_refused_from_its_estimate(cli):
    r = cli("tune", "abs-wheel", "--controller", "pid", "--optimizer", "pso", "--pop", "10" * 6)
    assert (r.code, r.out) == (2, "")
    assert r.err.startswith(
        "chassistune: error: --pop: a population of 101,010,101,010 needs about "
    ) and r.err.endswith(" GiB available\n")


def test_the_estimate_counts_gains_and_scenarios():
    one = memory.tune_bytes(1000, 3, 1)
    assert memory.tune_bytes(2000, 3, 1) == 2 * one
    assert memory.tune_bytes(1000, 3, 4) > one and memory.tune_bytes(1000, 6, 1) > one


def test_tune_refuses_a_population_the_machine_cannot_hold(cli, one_gib):
    args = ("tune", "abs-wheel", "--controller", "pid", "--optimizer", "pso", "--pop")
    r = cli(*args, "2000000")
    assert (r.code, r.out) == (2, "")
    assert r.err == (
        "chassistune: error: --pop: a population of 2,000,000 needs about 1.67 GiB of "
        "memory, more than the 1 GiB available\n"
    )


@pytest.mark.parametrize(
    ("study", "budget", "message"),
    [
        (
            "",
            "pop_size = 2000000\niterations = 2",
            "budget.pop_size: a population of 2,000,000 needs about 1.67 GiB of memory",
        ),
        (
            "seeds = 100000",
            "pop_size = 10\niterations = 2",
            "study.seeds: a grid of 200,000 runs (2 scenario cells x 1 optimizers x 100000 "
            "seeds) needs about 1.53 GiB of memory",
        ),
    ],
)
def test_a_study_the_machine_cannot_hold_is_refused_before_planning(
    cli, tmp_path, one_gib, study, budget, message
):
    text = STUDY.format(scenario="", optimizer="", budget=budget)
    text = text.replace("seeds = 1\n", (study or "seeds = 1") + "\n")
    text = text.replace('roads = ["dry-concrete"]', 'roads = ["dry-concrete", "ice"]')
    config = tmp_path / "s.toml"
    config.write_text(text)
    r = cli("study", "run", str(config), "--out", str(tmp_path / "st"))
    assert (r.code, r.out) == (2, "")
    assert r.err.startswith(f"chassistune: error: {message}, more than the 1 GiB available")
    assert not (tmp_path / "st").exists()


def test_an_endless_input_file_is_refused_at_its_size_cap(cli, tmp_path):
    for name in ("config.toml", "tune.json"):
        (tmp_path / name).symlink_to("/dev/zero")
    r = cli("study", "run", str(tmp_path / "config.toml"), "--out", str(tmp_path / "st"))
    assert (r.code, r.err) == (
        2,
        f"chassistune: error: CONFIG: {str(tmp_path / 'config.toml')!r} is larger than "
        "1,048,576 bytes, the most read for this input\n",
    )
    r = cli("simulate", "--from", str(tmp_path / "tune.json"))
    assert r.code == 2 and r.err.endswith(
        "is larger than 67,108,864 bytes, the most read for this input\n"
    )
