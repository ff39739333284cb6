"""Road knowledge (`scenarios.road_knowledge`): `fixed` tunes one target slip for every road as the
law's last gain; at the road's own peak it is the oracle's run bit for bit, each row of a batch
keeps its own target (batch equals single), the target reaches the law (another target, another
stop); a choice that does not fit the law is refused in one line naming the field."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.errors import InputError
from chassistune.scenarios.registry import get_plant

WHEEL = get_plant("abs-wheel")
VEHICLE = get_plant("abs-vehicle")
MODES = ({}, {"ecu": "realistic"})


def _pair(law: str, mode: dict[str, str], road: str = "dry-concrete"):  # type: ignore[no-untyped-def]
    oracle = WHEEL.scenario(None, road, law, dict(mode), 0)
    fixed = WHEEL.scenario(None, road, law, {**mode, "road_knowledge": "fixed"}, 0)
    return oracle, fixed


@pytest.mark.parametrize("mode", MODES, ids=("ideal", "realistic"))
@pytest.mark.parametrize("law", ("pid", "threshold", "fuzzy-pid"))
def test_fixed_at_the_roads_peak_is_the_oracle_bit_for_bit(law: str, mode: dict) -> None:
    oracle, fixed = _pair(law, mode)
    assert fixed.gain_names == (*oracle.gain_names, "target_slip")
    g = oracle.gains_array(None)
    assert np.array_equal(
        oracle.raw(g[None, :]), fixed.raw(np.r_[g, oracle.target_slip][None, :]), equal_nan=True
    )


@pytest.mark.parametrize("mode", MODES, ids=("ideal", "realistic"))
def test_each_row_keeps_its_own_target(mode: dict) -> None:
    _, fixed = _pair("pid", mode)
    base = fixed.gains_array(None)
    rows = np.repeat(base[None, :], 4, axis=0)
    rows[:, -1] = (0.08, 0.12, 0.2, 0.3)
    batch = fixed.raw(rows, workers=1)
    single = np.concatenate([fixed.raw(r[None, :], workers=1) for r in rows])
    assert np.array_equal(batch, single, equal_nan=True)
    d = fixed.metrics(rows)["stop_distance_m"]
    assert len(set(np.round(d, 9))) == 4  # the target reaches the law


def test_the_trace_shows_the_rows_target() -> None:
    _, fixed = _pair("pid", {})
    g = fixed.gains_array({"target_slip": 0.13})
    assert np.all(fixed.trace(g).signals["target_slip"] == 0.13)


def test_the_fixed_target_is_tuned_within_its_bounds() -> None:
    _, fixed = _pair("threshold", {})
    ((lo, hi),) = fixed.controller.bounds()
    assert 0.0 < lo < 0.05 and 0.3 < hi < 1.0


@pytest.mark.parametrize(
    ("plant", "law", "values", "field"),
    [
        ("abs-wheel", "pid", {"road_knowledge": "none"}, "params.road_knowledge"),
        ("abs-wheel", "none", {"road_knowledge": "fixed"}, "params.road_knowledge"),
        ("abs-wheel", "pid", {"road_knowledge": "psychic"}, "params.road_knowledge"),
        ("abs-wheel", "pid", {"road_knowledge": "fixed", "target_slip": 0.1}, "params.target_slip"),
        ("abs-vehicle", "none", {"road_knowledge": "oracle"}, "params.road_knowledge"),
    ],
)
def test_a_choice_that_does_not_fit_is_refused(plant, law, values, field) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InputError) as err:
        get_plant(plant).scenario(None, "dry-concrete", law, values, 0)
    assert err.value.field == field


def test_the_scenario_says_what_it_knows() -> None:
    oracle, fixed = _pair("pid", {})
    assert oracle.params()["road_knowledge"] == "oracle"
    assert fixed.params()["road_knowledge"] == "fixed" and "target_slip" not in fixed.params()
    none = WHEEL.scenario(None, "dry-concrete", "none", {}, 0)
    assert none.params()["road_knowledge"] == "none"


def test_on_the_command_line(cli) -> None:  # type: ignore[no-untyped-def]
    ok = cli(
        "simulate",
        "abs-wheel",
        "--controller",
        "pid",
        "--param",
        "road_knowledge=fixed",
        "--gains",
        "target_slip=0.15",
        "--json",
    )
    assert ok.code == 0, ok.err
    bad = cli("simulate", "abs-wheel", "--controller", "pid", "--param", "road_knowledge=none")
    assert bad.code == 2 and bad.out == "" and len(bad.err.splitlines()) == 1
    assert "road_knowledge" in bad.err


def test_on_the_vehicle_fixed_at_the_peak_is_the_oracle_and_rows_keep_their_target() -> None:
    oracle = VEHICLE.scenario(None, "dry-concrete", "pid", {}, 0)
    fixed = VEHICLE.scenario(None, "dry-concrete", "pid", {"road_knowledge": "fixed"}, 0)
    g = oracle.gains_array(None)
    (peak, _) = oracle.target_slips
    assert np.array_equal(
        oracle.raw(g[None, :]), fixed.raw(np.r_[g, peak][None, :]), equal_nan=True
    )
    rows = np.stack([np.r_[g, t] for t in (0.1, 0.15, 0.25)])
    batch = fixed.raw(rows, workers=1)
    assert np.array_equal(
        batch, np.concatenate([fixed.raw(r[None, :], workers=1) for r in rows]), equal_nan=True
    )


def test_on_a_mu_jump_the_fixed_target_holds_on_both_surfaces() -> None:
    values = {"road_knowledge": "fixed", "axle_gains": "per-axle"}
    fixed = VEHICLE.scenario(None, "mu-jump", "pid", values, 0)
    assert fixed.gain_names[-1] == "target_slip" and fixed.gain_names.count("target_slip") == 1
    g = fixed.gains_array({"target_slip": 0.12})
    tr = fixed.trace(g)
    for wheel in ("fl", "fr", "rl", "rr"):
        assert np.all(tr.signals[f"target_slip_{wheel}"] == 0.12)
    assert len(set(tr.signals["surface_fl"])) == 2  # the wheel met both surfaces
