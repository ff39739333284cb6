"""The ECU-realistic ABS kernel (docs/ecu.md): the limit to the ideal mode, batch rows
equal to single runs, physical valves, the reference-speed drift, speed-scheduled gains, no NaN
on random gains, bad input."""

from __future__ import annotations

import itertools
import re

import numba
import numpy as np
import pytest
from test_abs_wheel_kernel import CONTROLLERS, ROADS, _has_avx, _population
from test_abs_wheel_mf import CHRONO

from chassistune._branchfree import stack_copy
from chassistune.controllers import laws
from chassistune.errors import InputError
from chassistune.plants.mf_curve import TIRE_SURFACE
from chassistune.plants.tires import KIND_MAGIC_FORMULA
from chassistune.scenarios.abs_wheel import PLANT
from chassistune.sim import abs_wheel_ecu_kernel as EK
from chassistune.sim import abs_wheel_ecu_layout as EL
from chassistune.sim import abs_wheel_kernel as K
from chassistune.sim import abs_wheel_layout as KL

PRESET = "paper-derlsp-ao"
PID_GAINS = np.array([[5000.0, 0.0, 230.0]])
LIMIT = {
    "ecu": "realistic",
    "sensor": "ideal",
    "vref": "true",
    "ecu_delay_samples": 0,
    "valves": "continuous",
    "abs_cutout_m_s": 0.5,
    "valve_dead_time_s": 0.0,
    "valve_min_on_s": 0.0,
}
"""The ideal limit of the realistic ECU (cut-out at v_stop = 0.5 m/s, dt 1 ms)."""


def _distance(road: str, params: dict[str, object]) -> float:
    return float(
        PLANT.scenario(PRESET, road, "pid", params).metrics(PID_GAINS)["stop_distance_m"][0]
    )


def test_the_ecu_runs_the_registrys_kind_and_refuses_an_unknown_one() -> None:
    for name in CONTROLLERS:
        sc = PLANT.scenario(PRESET, "ice", name, {"ecu": "realistic"})
        assert sc.ecu is not None and sc.ecu.vector[EL.ECU["law"]] == laws.kind(name)
    unknown = sc.ecu.vector.copy()
    unknown[EL.ECU["law"]] = len(laws.names())
    with pytest.raises(ValueError, match="no control law of kind"):
        EK.simulate_abs_wheel_ecu(
            np.zeros((1, 1)),
            np.zeros((1, 1)),
            unknown,
            0,
            *([np.zeros(1)] * 5),
            (),
            np.zeros((0, 1)),
            np.zeros((1, 1)),
        )
    assert EL.METRICS.names[: len(KL.METRICS)] == KL.METRICS.names
    assert EL.TRACE.names[: len(KL.TRACE)] == KL.TRACE.names


@pytest.mark.parametrize("road", ["dry-concrete", "ice"])
def test_sampling_converges_to_the_ideal_mode_first_order(road: str) -> None:
    """ecu_ts_s = m dt, m = 8, 4, 2, 1: each halving of the period cuts the distance error by
    at least 1.8 (first order or better; measured 0.86 %, 0.16 %, 0.026 %, 0.011 % on dry
    concrete, 0.13 %, 0.036 %, 0.014 %, 0.0063 % on ice), within 1 % at m = 1."""
    ideal = _distance(road, {})
    errs = [
        abs(_distance(road, {**LIMIT, "ecu_ts_s": m * 1e-3}) - ideal) / ideal for m in (8, 4, 2, 1)
    ]
    assert all(a > 1.8 * b for a, b in itertools.pairwise(errs)), errs
    assert errs[-1] < 0.01


@pytest.mark.parametrize(
    ("teeth", "timer_s", "tol"), [(10_000, 1e-9, 2e-3), (1_000_000, 1e-9, 1e-2)]
)
def test_fine_toothed_sensor_converges(teeth: int, timer_s: float, tol: float) -> None:
    """At m = 1 a toothed wheel timed to 1 ns lands within 1 % of the ideal distance (measured
    10^4 teeth: 0.10 % dry, 0.067 % ice; 10^6 teeth: 0.32 %, 0.37 %: coarser, its period is
    only about a hundred timer ticks at speed, see docs/ecu.md)."""
    for road in ("dry-concrete", "ice"):
        d = _distance(
            road,
            {
                **LIMIT,
                "ecu_ts_s": 1e-3,
                "sensor": "toothed",
                "sensor_teeth": teeth,
                "sensor_timer_s": timer_s,
            },
        )
        assert d == pytest.approx(_distance(road, {}), rel=tol), road


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_batch_row_equals_single_run_no_nan_physical_valves(controller: str) -> None:
    """Realistic defaults (48 teeth, 5 ms, one sample of delay, slew-limited reference,
    three-state valves, cut-out): row i of a batch is bitwise run i alone (also on 2 threads),
    the costs are finite, the pressure stays within [return, supply] = [0, q_max], and no valve
    state lasts less than the minimum on-time."""
    sc = PLANT.scenario(
        PRESET, "wet-asphalt", controller, {"ecu": "realistic", "sensor_jitter_s": 2e-6}
    )
    g = _population(sc, 20, CONTROLLERS.index(controller))
    batch = sc.raw(g, workers=1)
    for i in range(0, len(g), 3):
        assert sc.raw(g[i : i + 1], workers=1).tobytes() == batch[i : i + 1].tobytes()
    assert sc.raw(g, workers=2).tobytes() == batch.tobytes()
    assert np.all(np.isfinite(sc.cost_from_raw(batch)))
    m = sc.metrics_from_raw(batch)
    assert np.all(m["pressure_min"] >= 0.0) and np.all(m["pressure_max"] <= 1500.0)
    assert np.all(m["valve_min_interval_s"] >= 2e-3 - 1e-12)
    assert np.all(m["valve_switches"] > 0)


@pytest.mark.parametrize("controller", ["pid", "threshold"])
def test_population_beyond_the_lanes_row_equals_single_run(controller: str) -> None:
    """More candidates than lanes (lanes refilled from the queue, then closed): row i of the
    batch is bitwise run i alone, with a toothed sensor whose teeth are uneven."""
    sc = PLANT.scenario(
        PRESET, "wet-asphalt", controller, {"ecu": "realistic", "sensor_spacing_error": 0.05}
    )
    g = _population(sc, 2 * EK.LANES + 7, 3)
    batch = sc.raw(g, workers=1)
    for i in range(0, len(g), 5):
        assert sc.raw(g[i : i + 1], workers=1).tobytes() == batch[i : i + 1].tobytes()


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_continuous_valves_random_gains_give_no_nan(controller: str) -> None:
    sc = PLANT.scenario(
        PRESET, "ice", controller, {"ecu": "realistic", "valves": "continuous", "vref": "accel"}
    )
    g = _population(sc, 12, 7)
    raw = sc.raw(g)
    assert np.all(np.isfinite(sc.cost_from_raw(raw)))
    assert np.all(np.isin(raw[:, EL.METRICS["status"]], [0, 1, 2, 3]))


def test_diverging_gains_end_diverged_with_a_finite_penalty() -> None:
    sc = PLANT.scenario(PRESET, "dry-concrete", "pid", {"ecu": "realistic", "valves": "continuous"})
    g = np.array([[5000.0, 0.0, 230.0], [1e308, 1e308, 0.0], [-1e4, 0.0, -1e3]])
    m = sc.metrics(g)
    assert m["status"][0] == "stopped" and m["status"][1] == "diverged"
    assert np.all(np.isfinite(sc.cost(g)))


def test_trace_agrees_with_the_metrics_and_shows_the_ecu() -> None:
    sc = PLANT.scenario(PRESET, "dry-concrete", "pid", {"ecu": "realistic"})
    tr = sc.trace(sc.gains_array(None))
    assert tr.metrics["stop_distance_m"] == pytest.approx(tr.signals["distance_m"][-1])
    assert tr.metrics["stop_distance_m"] == sc.metrics(PID_GAINS)["stop_distance_m"][0]
    assert np.all(tr.signals["vref_m_s"] >= tr.signals["wheel_speed_est_m_s"] - 1e-9)
    assert set(np.unique(tr.signals["valve_mode"])) <= {-1.0, 0.0, 1.0}


def test_slew_limited_reference_drifts_threshold_does_not_anchor_it() -> None:
    """A continuous slip controller never lets the wheel spin up: the slew-limited reference
    (a_max 1.2 g) follows the wheel down, by 25.8 m/s on ice (it collapses with the wheel) and
    8.4 m/s on dry concrete. Contrary to what one might expect, the threshold ABS does not
    keep it anchored either (26.0 m/s on ice, 9.2 m/s on dry): its release phases end when the
    wheel stops re-accelerating, judged against the drifting reference, so the wheel never
    reaches the vehicle speed again. The accelerometer reference holds on dry concrete."""

    def gap(road: str, controller: str, vref: str) -> float:
        sc = PLANT.scenario(PRESET, road, controller, {"ecu": "realistic", "vref": vref})
        return float(sc.metrics(sc.gains_array(None)[None, :])["vref_gap_max_m_s"][0])

    assert gap("ice", "pid", "slew-limited") > 20.0
    assert gap("dry-concrete", "pid", "slew-limited") > 5.0
    assert gap("ice", "threshold", "slew-limited") > 20.0
    assert gap("dry-concrete", "pid", "accel") < 0.5
    assert gap("dry-concrete", "threshold", "accel") < 0.5


@pytest.mark.parametrize("road", ["ice", "dirt-0.2"])
def test_speed_scheduled_gains_remove_the_low_speed_oscillation(road: str) -> None:
    """Fixed-gain PID, ideal sensor and reference, 1 ms: the true slip error between 1 and
    9 m/s reaches 0.084 on ice and 0.13 on dirt-0.2 (the equilibrium is unstable at low speed);
    with kp, kd scaled by v_ref / v0 it stays at 3e-15 on ice and halves on dirt-0.2 (0.066);
    on dry concrete fixed gains already hold it (2.6e-6)."""

    def err(r: str, schedule: str) -> float:
        sc = PLANT.scenario(
            PRESET, r, "pid", {**LIMIT, "ecu_ts_s": 1e-3, "gain_schedule": schedule}
        )
        return float(sc.metrics(PID_GAINS)["low_speed_slip_error"][0])

    fixed, scheduled = err(road, "off"), err(road, "speed")
    assert fixed > 0.05
    assert scheduled < 0.6 * fixed
    assert err("dry-concrete", "off") < 1e-4
    if road == "ice":
        assert scheduled < 1e-6


def test_bad_ecu_input_names_the_field() -> None:
    with pytest.raises(InputError, match=r"params\.ecu\b"):
        PLANT.scenario(PRESET, "ice", "pid", {"ecu": "fancy"})
    with pytest.raises(InputError, match=r"params\.ecu_ts_s"):
        PLANT.scenario(PRESET, "ice", "pid", {"ecu": "realistic", "ecu_ts_s": 4.5e-3})
    with pytest.raises(InputError, match=r"params\.sensor_teeth"):
        PLANT.scenario(PRESET, "ice", "pid", {"sensor_teeth": 60})  # ideal mode: unknown
    with pytest.raises(InputError, match=r"params\.vref"):
        PLANT.scenario(PRESET, "ice", "pid", {"ecu": "realistic", "vref": "gps"})


def test_ideal_mode_is_the_ideal_kernel() -> None:
    sc = PLANT.scenario(PRESET, "dry-concrete", "pid", {"ecu": "ideal"})
    assert sc.ecu is None
    assert sc.raw(PID_GAINS).shape[1] == len(KL.METRICS)
    assert EK.LOW_SPEED_BAND_M_S == (1.0, 9.0)


def test_the_ecu_gap_study_config_plans() -> None:
    from pathlib import Path

    from chassistune.studies.spec import load_config, plan_study

    path = Path(__file__).parents[2] / "examples" / "studies" / "ecu-gap.toml"
    plan = plan_study(load_config(str(path)))
    assert any(r.params.get("ecu") == "realistic" for r in plan.runs)


@pytest.mark.parametrize("road", ["dry-concrete", "ice"])
def test_sensor_estimate_within_the_edge_timing_bound_on_the_trace(road: str) -> None:
    """Default realistic ECU (48 teeth, 1 us timer): at every tick that has two captured edges
    t_a < t_b, the estimate pitch / (t_b - t_a) is the mean wheel speed over the true edge
    period, stretched by at most one timer tick tau each way: it lies in
    [min w (1 - tau/T), max w (1 + tau/T)] over [t_a - tau, t_b + tau] (T = t_b - t_a; min and
    max over the trace rows bracketing the window, widened by the largest change between two
    rows). Also in the form |w_est - w(t)| <= w_mean tau / (T - tau) + alpha_max (t - t_a)
    (alpha_max the largest |dw/dt| on the trace up to t, plus one row's change)."""
    sc = PLANT.scenario(PRESET, road, "threshold", {"ecu": "realistic"})
    s = sc.trace(sc.gains_array(None)).signals
    t, w, est = s["time_s"], s["wheel_speed_m_s"], s["wheel_speed_est_m_s"]
    ta, tb = s["edge_prev_s"], s["edge_last_s"]
    tau = sc.ecu.params.sensor_timer_s
    pitch_m = 2.0 * np.pi / sc.ecu.params.sensor_teeth * sc.plant_params.wheel_radius_m
    dw = np.abs(np.diff(w))
    alpha = np.concatenate([[0.0], np.maximum.accumulate(dw / np.diff(t))])
    checked = 0
    for i in np.flatnonzero(ta >= 0.0):
        period = tb[i] - ta[i]
        assert est[i] == pytest.approx(pitch_m / period, rel=1e-12)
        lo = max(np.searchsorted(t, ta[i] - tau) - 1, 0)
        hi = min(np.searchsorted(t, tb[i] + tau) + 1, t.size)
        slack = dw[lo : hi - 1].max() if hi - lo > 1 else 0.0
        assert est[i] >= (w[lo:hi].min() - slack) * (1.0 - tau / period) - 1e-12
        assert est[i] <= (w[lo:hi].max() + slack) * (1.0 + tau / period) + 1e-12
        age_bound = est[i] * tau / (period - tau) + (alpha[i] + slack / 1e-3) * (t[i] - ta[i])
        assert abs(est[i] - w[i]) <= age_bound + slack
        checked += 1
    assert checked > 0.9 * np.count_nonzero(t < t[-1] - 0.1)
    # the bound is not vacuous: the estimate does differ from the true speed
    assert np.max(np.abs(est - w)) > 1e-3


def test_spacing_error_shows_as_periodic_noise_of_the_tooth_pattern() -> None:
    """A free-rolling wheel (PID with zero gains: no brake, constant speed w) with tooth
    spacing errors d_k (std 0.05 pitch, drawn from the run's seed): the estimate at each tick
    is pitch w / (pitch + d_k - d_k-1) for the last edge k before the tick (to one timer tick),
    a function of the tooth index only: periodic with the revolution, with components up to
    the tooth frequency; its relative spread is about sqrt(2) 0.05. Without spacing errors
    the estimate is w to the timer resolution (tau w / pitch = 4.6e-4 here)."""
    base = {"ecu": "realistic", "valves": "continuous", "vref": "true"}
    for sigma in (0.05, 0.0):
        sc = PLANT.scenario(
            PRESET, "dry-concrete", "pid", {**base, "sensor_spacing_error": sigma}, seed=7
        )
        s = sc.trace(np.zeros(3)).signals
        r = sc.plant_params.wheel_radius_m
        w = sc.plant_params.v0_m_s / r
        assert np.all(s["wheel_speed_m_s"] == pytest.approx(w * r, rel=1e-12))
        teeth = sc.ecu.params.sensor_teeth
        pitch = 2.0 * np.pi / teeth
        d = sc.ecu.noise[0] if sigma > 0.0 else np.zeros(teeth)
        ticks = s["edge_prev_s"] >= 0.0
        t_tick = s["edge_last_s"][ticks]
        k = np.rint(w * t_tick / pitch).astype(int)  # |d_k| <= 0.45 pitch
        period = (pitch + d[k % teeth] - d[(k - 1) % teeth]) / w
        expected = pitch / period * r
        tol = expected * 2.0 * sc.ecu.params.sensor_timer_s / period + 1e-12
        assert np.all(np.abs(s["wheel_speed_est_m_s"][ticks] - expected) <= tol)
        spread = np.std(s["wheel_speed_est_m_s"][ticks] / (w * r) - 1.0)
        if sigma > 0.0:
            assert spread == pytest.approx(np.sqrt(2.0) * sigma, rel=0.35)
            assert len(np.unique(k % teeth)) == teeth  # every tooth seen: the pattern repeats
        else:  # the timer alone: one tick of the pitch period
            assert spread < sc.ecu.params.sensor_timer_s * w / pitch


@pytest.mark.parametrize("road", ["dry-concrete", "wet-asphalt", "ice"])
def test_default_reference_gives_sensible_stops(road: str) -> None:
    """The default realistic ECU (accelerometer reference): the threshold ABS and the PID with
    the registry gains stop without locking the wheel, within 20 % (threshold) and 40 % (PID;
    the accelerometer bias of 0.1 m/s^2 lifts the reference over a 45 s stop on ice) of the
    adhesion bound, and the reference stays within 2.5 m/s of the truth before the cut-out.
    With the slew-limited reference the same runs drift by 8-26 m/s (test above)."""
    for controller, ratio in (("threshold", 1.2), ("pid", 1.4)):
        sc = PLANT.scenario(PRESET, road, controller, {"ecu": "realistic"})
        assert sc.ecu.params.vref == "accel"
        m = sc.metrics(sc.gains_array(None)[None, :])
        assert m["status"][0] == "stopped"
        assert np.isnan(m["wheel_lock_time_s"][0])
        assert 1.0 < m["distance_ratio"][0] < ratio
        assert m["vref_gap_max_m_s"][0] < 2.5


def _packed(f: numba.core.dispatcher.Dispatcher) -> int:
    """Packed double arithmetic instructions (ymm/zmm registers) in compiled function f."""
    asm = f.inspect_asm(f.signatures[0])
    return len(re.findall(r"\bv(?:mul|add|sub|div|fmadd\w*|sqrt)pd\s[^\n]*%[yz]mm", asm))


@pytest.mark.slow
@pytest.mark.skipif(not _has_avx(), reason="needs an x86 CPU with AVX2")
@pytest.mark.parametrize("law", [*sorted(ROADS), KIND_MAGIC_FORMULA])
def test_vector_loops_vectorize(law: int) -> None:
    """Packed double arithmetic in the step's vector loop of each tire law and in the metrics'
    vector loop: a call or a branch added to `plant_step` or `step_metrics` would silently fall
    back to scalar code."""
    steps = EK._plant_steps_of(law)

    @numba.njit(_nrt=False)  # type: ignore[misc]
    def run(st, c4, xc_tuple, xs_tuple, ys_tuple, poly):  # type: ignore[no-untyped-def]
        xc, xs, ys = stack_copy(xc_tuple), stack_copy(xs_tuple), stack_copy(ys_tuple)
        tire = (c4[0], c4[1], c4[2], c4[3], xc, xs, ys, poly)
        steps(st, EK.LANES, True, (1e-3, 5e-4, 1e-3 / 6.0, tire, 1.0, 1.0))

    if law == KIND_MAGIC_FORMULA:
        sc = PLANT.scenario("paper-derlsp-ao", TIRE_SURFACE, "pid", {"tire": CHRONO})
    else:
        sc = PLANT.scenario(*ROADS[law], "pid")
    _p, kind, coef, xs, ys, *_ = sc._kernel_args
    run(np.zeros(EK.N_ROWS * EK.LANES), *K.tire_arguments(kind, coef, xs, ys))
    metrics = numba.njit(error_model="numpy", _nrt=False)(
        EK._metric_steps.py_func
    )  # uncached: its code to read
    metrics(np.zeros(EK.N_ROWS * EK.LANES), EK.LANES, EK.LANES, 1e-3, 100, 0.1)
    print(f"law {law}: {_packed(steps)} packed in the step, {_packed(metrics)} in the metrics")
    assert _packed(steps) >= 80, "the plant step no longer vectorizes"
    assert _packed(metrics) >= 50, "the step metrics no longer vectorize"
