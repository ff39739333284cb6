"""The vehicle ABS kernel: batch rows equal single runs bit for bit, options, costs, bad input."""

from __future__ import annotations

import re

import numpy as np
import pytest

from chassistune.errors import InputError
from chassistune.scenarios.abs_vehicle import PLANT
from chassistune.scenarios.base import PENALTY
from chassistune.sim import abs_vehicle_layout as VL


def population(sc, n: int = 50) -> np.ndarray:
    b = np.array(sc.controller.bounds())
    return np.random.default_rng(12345).uniform(b[:, 0], b[:, 1], (n, len(b)))


@pytest.mark.parametrize(
    "road,controller,params",
    [
        ("dry-concrete", "pid", {}),
        ("split-mu", "fuzzy-pid", {"rear": "select-low"}),
        ("mu-jump", "pid", {"steering": "driver", "axle_gains": "per-axle"}),
    ],
)
def test_batch_row_equals_single_run_bit_for_bit(road, controller, params):
    sc = PLANT.scenario(None, road, controller, params)
    gains = population(sc)
    batch = sc.raw(gains, workers=1)
    threaded = sc.raw(gains, workers=3)
    np.testing.assert_array_equal(batch, threaded)
    for i in range(gains.shape[0]):
        np.testing.assert_array_equal(sc.raw(gains[i : i + 1], workers=1)[0], batch[i])
    # the traced run (trace mode of the same kernel) gives the same metrics
    tr = sc.trace(gains[7])
    assert tr.metrics["stop_distance_m"] == batch[7, VL.M_DIST]
    assert tr.metrics["slip_itae"] == batch[7, VL.M_ITAE]


def test_per_axle_gains_equal_to_shared_gains_give_the_shared_run():
    shared = PLANT.scenario(None, "mu-jump", "pid")
    axle = PLANT.scenario(None, "mu-jump", "pid", {"axle_gains": "per-axle"})
    assert axle.gain_names == ("kp_f", "ki_f", "kd_f", "kp_r", "ki_r", "kd_r")
    g = shared.gains_array(None)
    np.testing.assert_array_equal(axle.raw(np.concatenate([g, g])[None, :]), shared.raw(g))
    soft_rear = axle.raw(np.concatenate([g, g * 0.5])[None, :])
    assert soft_rear[0, VL.M_DIST] != shared.raw(g)[0, VL.M_DIST]


def test_costs_are_finite_and_bad_runs_get_the_penalty():
    sc = PLANT.scenario(None, "dry-concrete", "pid", {"t_max_s": 2.0})  # too short to stop
    gains = np.array([[1200.0, 0.0, 20.0], [np.nan, 0.0, 20.0]])
    cost = sc.cost(gains)
    assert np.all(cost == PENALTY)
    ok = PLANT.scenario(None, "dry-concrete", "pid").cost(gains)
    assert np.isfinite(ok[0]) and ok[0] < PENALTY and ok[1] == PENALTY
    fuzzy = PLANT.scenario(None, "mu-jump", "fuzzy-pid")
    box = population(fuzzy, 8)
    for objective in fuzzy.objectives:
        cost = fuzzy.cost(box, objective)
        assert np.all(np.isfinite(cost)) and np.all(cost <= PENALTY)


def test_layouts_declare_every_kernel_slot_once():
    assert len(VL.METRIC_LAYOUT) == VL.N_METRICS and len(VL.TRACE_LAYOUT) == VL.N_TRACE
    assert VL.S_XF + 4 == VL.N_STATE
    # a lane's rows start with the state (`state_of` reads them in place), then its k4
    assert VL.LANE_LAYOUT.names[: VL.N_STATE] == VL.STATE_LAYOUT.names
    assert VL.R_K4 == VL.N_STATE and VL.R_KP == 2 * VL.N_STATE
    assert VL.R_WS - VL.R_MEM == 4 * VL.MEMORY and len(VL.LANE_LAYOUT) == VL.N_ROWS
    sc = PLANT.scenario(None, "dry-concrete", "pid")
    tr = sc.trace(sc.gains_array(None))
    assert set(tr.signals) == set(VL.TRACE_LAYOUT.names)
    assert tr.units["load_fl_n"] == "N"


def test_the_constants_tuple_holds_what_its_layout_names():
    """Each slot of the kernel's constants: a plant slot of its name, the inverse of one
    (`inv_`), a wheel's brake gain (`brake_gain_<wheel>`: 2 s kq in front, 2 (1 - s) kq
    behind), a geometry row at a wheel (`<row>_<wheel>`) or the step's derived values."""
    from chassistune.sim.abs_vehicle_lane import constants

    p = 1.0 + np.arange(len(VL.PLANT_LAYOUT), dtype=float)  # distinct values
    p[VL.P_DT], p[VL.P_TMAX] = 1e-3, 2.5
    geo = 100.0 + np.arange(4 * len(VL.GEOMETRY_LAYOUT), dtype=float).reshape(-1, 4)
    kc = constants.py_func(p, geo)
    derived = {"half_step_s": 5e-4, "sixth_step_s": 1e-3 / 6, "n_steps": 2500, "t_timeout_s": 2.5}
    assert len(kc) == len(VL.CONSTANTS_LAYOUT)
    for i, name in enumerate(VL.CONSTANTS_LAYOUT.names):
        row, _, wheel = name.rpartition("_")
        if name in VL.PLANT_LAYOUT:
            expected = p[VL.PLANT_LAYOUT[name]]
        elif name.startswith("inv_"):
            expected = 1.0 / p[VL.PLANT_LAYOUT[name.removeprefix("inv_")]]
        elif row == "brake_gain":
            s = p[VL.P_FRONT_SHARE]
            expected = 2.0 * (s if wheel in ("fl", "fr") else 1.0 - s) * p[VL.P_KQ]
        elif wheel in VL.WHEELS:
            expected = geo[VL.GEOMETRY_LAYOUT[row], VL.WHEELS.index(wheel)]
        else:
            expected = derived[name]
        assert kc[i] == pytest.approx(expected, rel=1e-15), name


@pytest.mark.parametrize(
    "params,field",
    [
        ({"dt_s": "0.002"}, "params.dt_s"),
        ({"v_stop_m_s": "0.5"}, "params.dt_s"),
        ({"steering": "wheel"}, "params.steering"),
        ({"rear": "select-high"}, "params.rear"),
        ({"first_surface": "mud"}, "params.first_surface"),
        ({"mass_kg": "-1"}, "params.mass_kg"),
        ({"bogus": "1"}, "params.bogus"),
        ({"max_steer_rad": str(np.pi / 2)}, "params.max_steer_rad"),
        ({"hopeless_factor": "1"}, "params.hopeless_factor"),
        ({"min_speed_m_s": "2"}, "params.min_speed_m_s"),
    ],
)
def test_bad_parameters_are_refused_naming_the_field(params, field):
    road = "mu-jump" if "first_surface" in params else "dry-concrete"
    with pytest.raises(InputError) as err:
        PLANT.scenario(None, road, "pid", params)
    assert field in str(err.value)


def test_the_stability_limit_follows_dt_and_v_stop():
    PLANT.scenario(None, "dry-concrete", "pid", {"v_stop_m_s": 0.5, "dt_s": 2.5e-4})
    PLANT.scenario(None, "ice", "pid", {"v_stop_m_s": 0.5})  # ice: a 4.4x softer wheel mode
    with pytest.raises(InputError, match="stability"):
        PLANT.scenario(None, "mu-jump", "pid", {"v_stop_m_s": 0.5})


@pytest.mark.parametrize(
    "params",
    [{"mass_kg": 1500}, {"mass_kg": 3000}, {"v_stop_m_s": 0.5}, {"dt_s": 0.0015}],
)
def test_the_stability_refusal_names_steps_that_pass(params):
    """The refusal's proposals, as printed, each pass: the step divided by a whole k, the largest
    step and the least v_stop_m_s."""
    with pytest.raises(InputError) as err:
        PLANT.scenario(None, "dry-concrete", "pid", params)
    msg = str(err.value)
    divided = re.search(r"dt_s = (\S+) \(the step divided by (\d+)\) passes", msg)
    largest = re.search(r"any dt_s <= (\S+),", msg)
    v_stop = re.search(r"v_stop_m_s >= (\S+)$", msg)
    assert divided and largest and v_stop, msg
    dt_s = float(params.get("dt_s", 1e-3))
    assert float(divided[1]) == pytest.approx(dt_s / int(divided[2]), rel=1e-6)
    for change in ({"dt_s": divided[1]}, {"dt_s": largest[1]}, {"v_stop_m_s": v_stop[1]}):
        PLANT.scenario(None, "dry-concrete", "pid", {**params, **change})


@pytest.mark.parametrize(
    "args,field",
    [
        (("--param", "v_stop_m_s=0.5"), "dt_s"),
        (("--road", "split-mu", "--param", "split_by=diagonal"), "split_by"),
        (("--gains", "kp=1,kz=2"), "--gains"),
        (("--param", "steering=driver", "--param", "max_steer_rad=1.6"), "max_steer_rad"),
        (("--param", "hopeless_factor=1"), "hopeless_factor"),
        (("--param", "hopeless_factor=0.5"), "hopeless_factor"),
        (("--param", "min_speed_m_s=2.5"), "min_speed_m_s"),
        (("--road", "mu-jump", "--param", "mu_scale=0"), "mu_scale"),
        (("--param", "mu_scale=-1"), "mu_scale"),
    ],
)
def test_cli_bad_input_is_one_line_and_exit_2(cli, args, field):
    r = cli("simulate", "abs-vehicle", "--controller", "pid", *args)
    assert r.code == 2
    lines = r.err.strip().splitlines()
    assert len(lines) == 1 and field in lines[0] and "Traceback" not in r.err
    assert r.out == ""


def test_cli_simulate_json_and_plot(cli, tmp_path):
    import json

    png = tmp_path / "car.png"
    r = cli(
        "simulate",
        "abs-vehicle",
        "--road",
        "split-mu",
        "--controller",
        "pid",
        "--param",
        "steering=driver",
        "--json",
        "--plot",
        str(png),
    )
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["plant"] == "abs-vehicle" and doc["preset"] == "paper-deffao"
    assert doc["params"]["steering"] == "driver" and doc["params"]["left_surface"] == "dry-concrete"
    assert doc["metrics"]["stopped"] and not doc["metrics"]["spun"]
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_general_path_agrees_with_an_independent_scipy_integration():
    """Split-mu (yaw, lateral slip, Newton loads): the kernel's RK4 at 1 ms against scipy's RK45
    at rtol 1e-8 on the plain-Python right-hand side of perf/vehicle.py (loads by fixed-point
    iteration, the tire written out separately)."""
    from chassistune.perf.vehicle import reference_solution

    sc = PLANT.scenario(None, "split-mu", "pid", {"t_max_s": 0.6, "steering": "fixed"})
    g = sc.gains_array(None)
    sol = reference_solution(sc, g, rtol=1e-8, atol=1e-9)
    s = sc.trace(g).signals
    assert sol.t[-1] == pytest.approx(s["time_s"][-1], abs=1e-12)
    for row, name in (
        (0, "vx_m_s"),
        (1, "vy_m_s"),
        (2, "yaw_rate_rad_s"),
        (3, "x_m"),
        (4, "y_m"),
        (5, "heading_rad"),
        (26, "distance_m"),
    ):
        assert s[name][-1] == pytest.approx(sol.y[row, -1], rel=1e-5), name
    assert abs(s["yaw_rate_rad_s"][-1]) > 0.3  # a real yaw, not a trivial agreement


def test_plausible_values_pass_and_implausible_ones_are_warned_about():
    import warnings

    from chassistune.params import ImplausibleValue

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        PLANT.scenario(
            None, "dry-concrete", "pid", {"max_steer_rad": "0.5", "hopeless_factor": "1.5"}
        )
    with pytest.warns(ImplausibleValue, match="params.max_steer_rad"):
        PLANT.scenario(None, "dry-concrete", "pid", {"max_steer_rad": "1.2"})
    with pytest.warns(ImplausibleValue, match="params.yaw_inertia_kg_m2"):
        PLANT.scenario(None, "dry-concrete", "pid", {"yaw_inertia_kg_m2": "50000"})
