"""quarter-car plant: presets, controllers, parameters, metrics, penalties, bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from chassistune.controllers.catalogue import for_plant
from chassistune.errors import InputError
from chassistune.plots.registry import plot_trace
from chassistune.scenarios.base import PENALTY
from chassistune.scenarios.quarter_car import PLANT, QuarterCarTrace
from chassistune.scenarios.registry import get_plant

METRICS = {
    "body_acc_rms",
    "susp_travel_rms",
    "tire_defl_rms",
    "objective",
    "passive_body_acc_rms",
    "passive_susp_travel_rms",
    "passive_tire_defl_rms",
    "damping_ratio",
    "travel_3sigma_m",
    "dynamic_tire_load_ratio",
}
PLANT_NAMES = {
    "sprung_mass_kg",
    "unsprung_mass_kg",
    "spring_n_m",
    "damper_n_s_m",
    "tire_stiffness_n_m",
    "speed_m_s",
    "cutoff_hz",
    "duration_s",
    "dt_s",
    "gq_m3",
}


def test_registered_with_presets_roads_and_controllers() -> None:
    assert get_plant("quarter-car") is PLANT
    assert list(PLANT.presets()) == ["paper-iabc", "typical"]
    assert PLANT.presets()["paper-iabc"].roads[0] == "iso-b"
    assert list(PLANT.roads()) == [f"iso-{c}" for c in "abcdefgh"]
    specs = {s.name: s for s in for_plant("quarter-car")}
    assert list(specs) == ["passive", "pid", "skyhook"]
    assert specs["passive"].gain_names == ()
    assert specs["pid"].gain_names == ("kp", "ki", "kd")
    assert [g.unit for g in specs["pid"].gains] == ["N s/m", "N/m", "N s^2/m"]
    assert specs["pid"].bounds() == [(0.0, 1e4), (0.0, 1e5), (0.0, 1e3)]
    assert specs["pid"].param_names == ("feedback", "n_filter")
    assert specs["skyhook"].gain_names == ("c_sky",)
    assert PLANT.scenario(controller="none").controller.name == "passive"


@pytest.mark.parametrize(
    ("preset", "cs", "zeta"), [("paper-iabc", 12000.0, 2.57), ("typical", 1200.0, 0.257)]
)
def test_presets_and_params_echo(preset: str, cs: float, zeta: float) -> None:
    sc = PLANT.scenario(preset, controller="pid", seed=3)
    p = sc.params()
    assert set(p) >= PLANT_NAMES
    assert p["damper_n_s_m"] == cs
    assert p["damping_ratio"] == pytest.approx(zeta, abs=0.005)
    assert (p["sprung_mass_kg"], p["unsprung_mass_kg"]) == (320.0, 45.0)
    assert (p["spring_n_m"], p["tire_stiffness_n_m"]) == (17000.0, 200000.0)
    assert (p["gq_m3"], p["speed_m_s"], p["cutoff_hz"]) == (64e-6, 20.0, 0.1)
    assert (p["duration_s"], p["dt_s"], p["seed"]) == (10.0, 1e-3, 3)
    assert p["feedback"] == "body_velocity"
    json.dumps(p)


def test_params_override_road_class_and_controller() -> None:
    sc = PLANT.scenario(
        "typical",
        "iso-d",
        "pid",
        {"speed_m_s": "25", "feedback": "suspension_travel", "n_filter": 50},
    )
    p = sc.params()
    assert (p["gq_m3"], p["speed_m_s"], p["feedback"], p["n_filter"]) == (
        1024e-6,
        25.0,
        "suspension_travel",
        50.0,
    )
    assert "feedback" not in PLANT.scenario("typical", controller="skyhook").params()


def test_metrics_of_a_batch() -> None:
    sc = PLANT.scenario("typical", controller="pid", seed=1)
    gains = np.array([[0.0, 0.0, 0.0], [500.0, 500.0, 100.0], [1656.0, 1452.0, 0.0]])
    m = sc.metrics(gains)
    assert set(m) >= METRICS
    for v in m.values():
        assert np.shape(v) == (3,)
    # zero gains reproduce the passive run on the same road exactly
    assert m["objective"][0] == 3.0
    assert m["objective_exact"][0] == pytest.approx(3.0, rel=1e-12)
    assert m["body_acc_rms"][0] == m["passive_body_acc_rms"][0]
    assert np.all(m["objective_exact"][1:] < 3.0)
    q = (
        m["body_acc_rms"] / m["passive_body_acc_rms"]
        + m["susp_travel_rms"] / m["passive_susp_travel_rms"]
        + m["tire_defl_rms"] / m["passive_tire_defl_rms"]
    )
    np.testing.assert_allclose(m["objective"], q, rtol=1e-12)
    np.testing.assert_allclose(m["travel_3sigma_m"], 3 * m["susp_travel_rms"])
    load = 200000.0 * m["tire_defl_rms"] / (365.0 * 9.80665)
    np.testing.assert_allclose(m["dynamic_tire_load_ratio"], load)
    np.testing.assert_allclose(m["damping_ratio"], 1200 / (2 * math.sqrt(17000 * 320)))
    np.testing.assert_allclose(sc.cost(gains, "rms-ratio"), m["objective"])
    np.testing.assert_allclose(sc.cost(gains), m["objective_exact"])


def test_skyhook_is_velocity_damping_and_passive_has_no_gains() -> None:
    sky = PLANT.scenario("typical", controller="skyhook")
    pid = PLANT.scenario("typical", controller="pid")
    np.testing.assert_array_equal(
        sky.cost(np.array([[2000.0]])), pid.cost(np.array([[2000.0, 0.0, 0.0]]))
    )
    passive = PLANT.scenario("typical", controller="passive")
    assert passive.cost(np.zeros((2, 0))).tolist() == pytest.approx([3.0, 3.0])
    assert passive.metrics(np.zeros((1, 0)))["objective"].tolist() == [3.0]


def test_same_seed_same_road_other_seed_other_road() -> None:
    a = PLANT.scenario("paper-iabc", controller="pid", seed=5).passive_sim
    b = PLANT.scenario("paper-iabc", controller="pid", seed=5).passive_sim
    c = PLANT.scenario("paper-iabc", controller="pid", seed=6).passive_sim
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


@pytest.mark.parametrize("preset", ["paper-iabc", "typical"])
@pytest.mark.parametrize(
    "feedback", ["body_velocity", "body_displacement", "body_acceleration", "suspension_travel"]
)
def test_destabilizing_gains_cost_the_penalty_never_nan(preset: str, feedback: str) -> None:
    sc = PLANT.scenario(preset, controller="pid", params={"feedback": feedback})
    gains = np.array(
        [
            [-2e4, 0.0, 0.0],
            [0.0, -1e6, 0.0],
            [0.0, 0.0, -400.0],
            [-1e5, -1e5, -1e3],
            [np.nan, 0.0, 0.0],
            [np.inf, 0.0, 0.0],
        ]
    )
    for objective in ("rms-ratio-exact", "rms-ratio"):
        cost = sc.cost(gains, objective)
        assert cost.shape == (6,)
        assert np.all(np.isfinite(cost))
        assert np.all(cost <= PENALTY)
        assert cost[3:].tolist() == [PENALTY] * 3
    assert sc.metrics(gains)["objective"][3:].tolist() == [PENALTY] * 3


def test_velocity_feedback_destabilized_by_negative_gains() -> None:
    sc = PLANT.scenario("paper-iabc", controller="pid")
    gains = np.array([[-2e4, 0.0, 0.0], [0.0, -1e6, 0.0], [0.0, 0.0, -400.0]])
    for objective in ("rms-ratio-exact", "rms-ratio"):
        assert sc.cost(gains, objective).tolist() == [PENALTY] * 3


def test_trace_and_frequency_response() -> None:
    sc = PLANT.scenario("typical", controller="pid", params={"duration_s": 2})
    tr = sc.trace(np.array([500.0, 500.0, 100.0]))
    assert isinstance(tr, QuarterCarTrace)
    lengths = {len(v) for v in tr.signals.values()}
    assert lengths == {2001}
    assert tr.signals["time_s"][-1] == pytest.approx(2.0)
    assert {
        "road_m",
        "body_acc_m_s2",
        "susp_travel_m",
        "tire_defl_m",
        "force_n",
        "passive_body_acc_m_s2",
    } <= set(tr.signals)
    assert set(tr.units) == set(tr.signals)
    assert tr.metrics["objective"] == pytest.approx(
        float(sc.metrics(np.array([[500.0, 500.0, 100.0]]))["objective"][0])
    )
    json.dumps(tr.metrics)
    fr = sc.frequency_response(tr.gains, np.geomspace(0.1, 50, 200))
    assert fr["active"].shape == fr["passive"].shape == (200,)
    # body-mode resonance near sqrt(ks kt / (ks + kt) / ms) / (2 pi) = 1.2 Hz for cs = 1200
    peak = fr["freq_hz"][np.argmax(fr["passive"][fr["freq_hz"] < 5])]
    assert 0.9 < peak < 1.5
    passive = PLANT.scenario("typical", controller="passive", params={"duration_s": 1})
    tp = passive.trace(np.zeros(0))
    np.testing.assert_array_equal(tp.signals["body_acc_m_s2"], tp.signals["passive_body_acc_m_s2"])


def test_long_traces_are_decimated() -> None:
    sc = PLANT.scenario("typical", controller="passive", params={"duration_s": 2500})
    tr = sc.trace(np.zeros(0))
    n = len(tr.signals["time_s"])
    assert n <= 1_000_001
    assert tr.signals["time_s"][-1] == pytest.approx(2500.0, rel=1e-3)


@pytest.mark.parametrize(
    ("kwargs", "field", "problem"),
    [
        ({"params": {"sprung_mass_kg": "-320"}}, "params.sprung_mass_kg", "must be positive"),
        ({"params": {"unsprung_mass_kg": 0}}, "params.unsprung_mass_kg", "must be positive"),
        ({"params": {"spring_n_m": -1}}, "params.spring_n_m", "must be positive"),
        (
            {"params": {"tire_stiffness_n_m": "-2e5"}},
            "params.tire_stiffness_n_m",
            "must be positive",
        ),
        ({"params": {"damper_n_s_m": "abc"}}, "params.damper_n_s_m", "not a number"),
        ({"params": {"speed_m_s": 0}}, "params.speed_m_s", "must be positive"),
        ({"params": {"duration_s": 0}}, "params.duration_s", "must be positive"),
        ({"params": {"duration_s": -5}}, "params.duration_s", "must be positive"),
        ({"params": {"dt_s": 0.1}}, "params.dt_s", "at most 0.01"),
        ({"params": {"duration_s": 1e5, "dt_s": 1e-4}}, "params.duration_s", "too many steps"),
        ({"params": {"mass_kg": 3}}, "params.mass_kg", "unknown parameter"),
        (
            {"params": {"feedback": "wheel_speed"}, "controller": "pid"},
            "params.feedback",
            "unknown feedback",
        ),
        (
            {"params": {"feedback": "body_velocity"}, "controller": "passive"},
            "params.feedback",
            "unknown parameter",
        ),
        ({"params": {"n_filter": 0}, "controller": "pid"}, "params.n_filter", "must be positive"),
        ({"road": "iso-z"}, "road", "unknown road"),
        ({"road": "dry-concrete"}, "road", "unknown road"),
        ({"preset": "sports"}, "preset", "unknown preset"),
        ({"controller": "lqr"}, "controller", "unknown controller"),
        ({"seed": -1}, "seed", "non-negative"),
    ],
)
def test_bad_input_is_a_one_line_input_error(kwargs: dict, field: str, problem: str) -> None:
    with pytest.raises(InputError) as err:
        PLANT.scenario(**kwargs)
    assert err.value.field == field
    assert problem in err.value.problem
    assert "\n" not in str(err.value)


def test_bad_objective_and_gain_shape() -> None:
    sc = PLANT.scenario(controller="pid")
    with pytest.raises(InputError, match="unknown objective"):
        sc.cost(np.zeros((1, 3)), "itae")
    with pytest.raises(InputError, match=r"expected shape \(n, 3\)"):
        sc.cost(np.zeros((1, 2)))
    with pytest.raises(InputError, match="unknown gain"):
        sc.gains_array({"kq": 1.0})


@pytest.mark.parametrize(("controller", "gains"), [("pid", [500.0, 500.0, 100.0]), ("passive", [])])
def test_plot_writes_a_png(tmp_path: Path, controller: str, gains: list[float]) -> None:
    sc = PLANT.scenario("paper-iabc", controller=controller, params={"duration_s": 8})
    path = tmp_path / "qc.png"
    plot_trace(sc, sc.trace(np.array(gains)), str(path))
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
