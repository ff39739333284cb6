"""The lagged slips on the 7-DOF vehicle (docs/tires.md, "Transient slip on the vehicle"): the
kernel's lag on held wheels against the exponential, zero lengths as the pinned static kernel,
batch rows as single runs on 1 and 2 threads, the closed loop against scipy, convergence as the
step halves, the adhesion bound, and the command line."""

from __future__ import annotations

import json
import math
import sys
import warnings
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

import abs_vehicle_pins as pins

from chassistune.errors import InputError
from chassistune.scenarios.abs_vehicle import PLANT
from chassistune.sim import abs_vehicle_layout as VL

CHRONO = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")
MF = {"tire": CHRONO, "dt_s": 2e-4, "v0_m_s": 15.0}
"""The shipped PAC2002 file at the step its stiffness needs, from 15 m/s (shorter runs)."""
LAG = {"relaxation_length_m": 0.3, "lateral_relaxation_length_m": 0.4}
ZERO = {"relaxation_length_m": "0", "lateral_relaxation_length_m": "0"}


def scenario(road: str, controller: str = "pid", **params: object):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return PLANT.scenario(None, road, controller, params)


def population(sc, n: int) -> np.ndarray:
    b = np.array(sc.controller.bounds())
    return np.random.default_rng(2028).uniform(b[:, 0], b[:, 1], (n, len(b)))


def _held_lanes(speed: float, lateral: float, slips: tuple[float, ...], sigma: tuple[float, float]):
    """Lane rows with the body at (speed, lateral) and the wheels' spins at the given kinematic
    slips, every derivative but the lag's 0 (held), and the kernel's constants with the lengths."""
    from chassistune.sim.abs_vehicle_lane import constants, surfaces

    sc = scenario(
        "dry-concrete",
        relaxation_length_m=sigma[0],
        lateral_relaxation_length_m=sigma[1],
        t_max_s=1.0,
    )
    p, geo, surfs, _, _, _ = sc._kernel_args
    st = np.zeros(VL.N_ROWS * VL.LANES)

    def put(row: int, value: float) -> None:
        st[row * VL.LANES : (row + 1) * VL.LANES] = value

    put(VL.S_VX, speed)
    put(VL.S_VY, lateral)
    for j, s in enumerate(slips):
        put(VL.S_W + j, speed * (1.0 - s) / sc.plant_params.wheel_radius_m)
    put(VL.R_STEER_COS, 1.0)
    put(VL.R_GENERAL, 1.0)
    put(VL.R_SPEED, math.hypot(speed, lateral))
    return st, constants(p, geo), surfaces(surfs)


def _lag_steps(st, kc, srf, n: int) -> None:
    """n RK4 steps of the lag alone, by the general pass's own lag code: each stage's kinematics
    and lag (`lagged_stage_start`), then the update (`lag_end`)."""
    from chassistune.sim.abs_vehicle_general import lagged_stage_start
    from chassistune.sim.abs_vehicle_lag import lag_end

    blocks = VL.LANES // VL.VECTOR
    dt = kc[VL.KC_DT]
    for _ in range(n):
        for stage, c in enumerate((0.0, 0.5 * dt, 0.5 * dt, dt)):
            lagged_stage_start(st, blocks, c, stage == 0, 1.0 if stage == 3 else 2.0, kc, srf)
        lag_end(st, blocks, kc)


def _rk4_factor(z: float) -> float:
    """Classic RK4's step of dy/dt = lambda y, z = lambda dt."""
    return 1.0 + z + z * z / 2.0 + z**3 / 6.0 + z**4 / 24.0


@pytest.mark.parametrize("speed", [3.0, 10.0, 33.0])
def test_held_wheels_lag_to_their_kinematic_slips_with_time_constant_sigma_over_speed(speed):
    """Body and wheel spins held (no forces integrated): each lagged slip is RK4's solution of
    sigma ds'/dt = |u| (s - s') to 1e-12 and follows the exponential s (1 - exp(-|u| t / sigma))
    within 1e-5 of s, with its own length in each direction, the lateral one tending to
    tan(alpha) = v/|u|; the tire reads the lagged slips, the laws the kinematic one."""
    slips = (0.05, 0.1, 0.2, 1.0)
    lateral = 0.02 * speed
    sigma = (0.3, 0.6)
    st, kc, srf = _held_lanes(speed, lateral, slips, sigma)
    dt = kc[VL.KC_DT]
    lane = 5
    for n, total in ((10, 10), (40, 50), (250, 300)):
        _lag_steps(st, kc, srf, n)
        t = total * dt
        for j, s in enumerate(slips):
            s_lag = st[(VL.S_LAG_X + j) * VL.LANES + lane]
            t_lag = st[(VL.S_LAG_Y + j) * VL.LANES + lane]
            for lag, target, length in ((s_lag, s, sigma[0]), (t_lag, 0.02, sigma[1])):
                rk4 = target * (1.0 - _rk4_factor(-speed * dt / length) ** total)
                assert lag == pytest.approx(rk4, rel=1e-12)
                assert abs(lag - target * (1.0 - math.exp(-speed * t / length))) < 1e-5 * target
    j = 2  # the laws' slip: the kinematic (u - w R)/|V|
    kinematic = st[(VL.R_KSLIP + j) * VL.LANES + lane]
    assert kinematic == pytest.approx(slips[j] / math.hypot(1.0, 0.02), rel=1e-12)


def test_a_zero_length_reads_the_kinematic_slip_in_that_direction():
    st, kc, srf = _held_lanes(20.0, 0.4, (0.1, 0.1, 0.1, 0.1), (0.3, 0.0))
    _lag_steps(st, kc, srf, 20)
    lane = 0
    assert st[VL.S_LAG_Y * VL.LANES + lane] == 0.0  # no lateral lag state
    vr = st[VL.R_VR * VL.LANES + lane]
    assert vr == pytest.approx(0.4 / math.hypot(20.0, 0.4), rel=1e-14)  # the kinematic v/|V|


@pytest.mark.parametrize(
    "case",
    [
        ("dry-concrete", "pid", {}),
        ("split-mu", "pid", {"steering": "driver"}),
        ("mu-jump", "fuzzy-pid", {}),
        ("split-mu", "threshold", {"split_by": "road", "steering": "driver"}),
    ],
    ids=lambda c: pins._key(*c),
)
def test_zero_lengths_given_explicitly_reproduce_the_pinned_kernel(case):
    road, ctrl, params = case
    pinned = json.loads(pins.PINNED.read_text())[pins._key(road, ctrl, params)]
    sc = PLANT.scenario(None, road, ctrl, {**pins._pinned(params), **ZERO})
    g = sc.gains_array(None)
    got = {"raw": [pins._digest(row) for row in sc.raw(g[None, :], workers=1)]}
    got |= {f"trace.{k}": pins._digest(v) for k, v in sc.trace(g).signals.items()}
    assert got == pinned


@pytest.mark.parametrize("road", ["dry-concrete", "split-mu"])
def test_zero_lengths_are_the_magic_formula_tires_static_run(road):
    static, zero = scenario(road, **MF), scenario(road, **MF, **ZERO)
    gains = population(static, 2)
    np.testing.assert_array_equal(static.raw(gains, workers=1), zero.raw(gains, workers=1))
    a, b = static.trace(gains[0]).signals, zero.trace(gains[0]).signals
    assert a.keys() == b.keys() and not any(k.startswith("lagged") for k in a)
    for k in a:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)


@pytest.mark.parametrize(
    ("road", "params"),
    [
        ("dry-concrete", {"relaxation_length_m": 0.3}),
        ("split-mu", {**LAG, "steering": "driver"}),
        ("mu-jump", LAG),
        pytest.param(
            "split-mu",
            {**MF, "relaxation_length_m": "tire", "lateral_relaxation_length_m": "tire"},
            marks=pytest.mark.slow,  # about 20 s: the Magic Formula's Newton loads
        ),
    ],
)
def test_batch_row_equals_single_run_on_one_and_two_threads(road, params):
    sc = scenario(road, "fuzzy-pid" if road == "mu-jump" else "pid", **params)
    gains = population(sc, 4 if sc.tire else 6)
    batch = sc.raw(gains, workers=1)
    np.testing.assert_array_equal(batch, sc.raw(gains, workers=2))
    for i in (0, 3):
        np.testing.assert_array_equal(sc.raw(gains[i : i + 1], workers=1)[0], batch[i])
    trace = sc.trace(gains[3])
    assert trace.metrics["stop_distance_m"] == batch[3, VL.M_DIST]
    assert {f"lagged_slip_{w}" for w in VL.WHEELS} <= set(trace.signals)


def test_the_lag_changes_the_run_and_the_trace_shows_it():
    """Locked wheels (no ABS): the lagged slip reaches the kinematic 1 after the lock, later than
    it; the laws still read the kinematic slip (the `slip_*` columns)."""
    sc = scenario("dry-concrete", "none", relaxation_length_m=0.5, t_max_s=1.0)
    s = sc.trace(sc.gains_array(None)).signals
    locked = np.argmax(s["slip_fl"] >= 1.0)
    assert locked > 0 and s["lagged_slip_fl"][locked] < 0.999
    assert s["lagged_slip_fl"][-1] == pytest.approx(1.0, abs=1e-6)
    static = scenario("dry-concrete", "none", t_max_s=1.0).trace(sc.gains_array(None)).signals
    assert not np.array_equal(static["fx_fl_n"], s["fx_fl_n"])


@pytest.mark.parametrize("bilinear", [True, False], ids=["bilinear", "magic-formula"])
def test_the_closed_loop_agrees_with_an_independent_scipy_integration(bilinear):
    """Split-mu, steering fixed, both lags on: the kernel's RK4 against scipy's RK45 at rtol 1e-8
    of perf/vehicle.py's plain-Python right-hand side with the lagged slips as states, within
    1e-5 relative in v_x, v_y, yaw rate, heading and each wheel's lagged tan(alpha'), 1e-4 in its
    lagged slip (bilinear, measured: at most 4.1e-5, the rear wheel on the slick side, falling to
    8.7e-6 and 2.6e-6 at 0.5 and 0.25 ms: the step's error, not the model's)."""
    from chassistune.perf.vehicle import reference_solution

    extra = {} if bilinear else {**MF, "relaxation_length_m": "tire"}
    sc = scenario("split-mu", steering="fixed", t_max_s=0.6, **{**LAG, **extra})
    g = sc.gains_array(None)
    sol = reference_solution(sc, g, rtol=1e-8, atol=1e-9)
    s = sc.trace(g).signals
    for row, name in ((0, "vx_m_s"), (1, "vy_m_s"), (2, "yaw_rate_rad_s"), (5, "heading_rad")):
        assert s[name][-1] == pytest.approx(sol.y[row, -1], rel=1e-5), name
    for j, w in enumerate(VL.WHEELS):
        assert s[f"lagged_slip_{w}"][-1] == pytest.approx(sol.y[27 + j, -1], rel=1e-4, abs=1e-6)
        tan_alpha = s[f"lagged_tan_alpha_{w}"][-1]
        assert tan_alpha == pytest.approx(sol.y[31 + j, -1], rel=1e-5, abs=1e-9)
    assert abs(s["yaw_rate_rad_s"][-1]) > 0.05
    assert max(abs(s[f"lagged_tan_alpha_{w}"][-1]) for w in VL.WHEELS) > 1e-3


@pytest.mark.parametrize("road", ["dry-concrete", "split-mu"])
def test_the_stop_converges_as_the_step_halves(road):
    """Stop distances of the PID with both lags at dt = 1, 0.5, 0.25 ms: the gaps shrink."""
    d = []
    for dt in (1e-3, 5e-4, 2.5e-4):
        sc = scenario(road, dt_s=dt, steering="fixed", **LAG)
        d.append(sc.metrics(sc.gains_array(None)[None, :])["stop_distance_m"][0])
    assert abs(d[1] - d[2]) < abs(d[0] - d[1])
    assert abs(d[0] - d[2]) / d[2] < 1e-3


@pytest.mark.parametrize("road", ["dry-concrete", "split-mu", "mu-jump"])
@pytest.mark.parametrize("controller", ["pid", "fuzzy-pid"])
def test_no_stop_beats_the_bound(road, controller):
    sc = scenario(road, controller, **LAG)
    gains = np.vstack([sc.gains_array(None), population(sc, 7)])
    m = sc.metrics(gains)
    assert m["stopped"].any()
    stopped = m["stop_distance_m"][m["stopped"]]
    assert np.all(stopped >= sc.bound_distance_m), (stopped.min(), sc.bound_distance_m)


def test_no_magic_formula_stop_beats_the_bound():
    lengths = {"relaxation_length_m": "tire", "lateral_relaxation_length_m": "tire"}
    sc = scenario("split-mu", **MF, **lengths)
    gains = np.vstack([sc.gains_array(None), population(sc, 5)])
    m = sc.metrics(gains)
    assert m["stopped"].any()
    assert np.all(m["stop_distance_m"][m["stopped"]] >= sc.bound_distance_m)


@pytest.mark.parametrize(
    ("params", "field"),
    [
        ({"relaxation_length_m": "-0.1"}, "params.relaxation_length_m"),
        ({"relaxation_length_m": "long"}, "params.relaxation_length_m"),
        ({"lateral_relaxation_length_m": "-1"}, "params.lateral_relaxation_length_m"),
        ({"lateral_relaxation_length_m": "nan"}, "params.lateral_relaxation_length_m"),
        ({"relaxation_length_m": "0.01"}, "params.relaxation_length_m"),  # below v0 dt
        ({"relaxation_length_m": "tire"}, "params.relaxation_length_m"),  # no --tire
        ({"lateral_relaxation_length_m": "tire"}, "params.lateral_relaxation_length_m"),
    ],
)
def test_bad_lengths_are_refused_naming_the_field(params, field):
    with pytest.raises(InputError) as err:
        PLANT.scenario(None, "dry-concrete", "pid", params)
    assert err.value.field == field


def test_a_file_without_lateral_relaxation_terms_is_refused_naming_the_field(tmp_path):
    text = Path(CHRONO).read_text(encoding="utf-8")
    path = tmp_path / "no_pty.tir"
    path.write_text(text.replace("PTY1  ", "PTY9  ", 1), encoding="utf-8")
    with pytest.raises(InputError) as err:
        scenario("dry-concrete", **{**MF, "tire": str(path)}, lateral_relaxation_length_m="tire")
    assert err.value.field == "params.lateral_relaxation_length_m"
    assert "PTY1" in str(err.value)
