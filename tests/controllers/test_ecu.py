"""ECU parts: toothed-wheel sensor, reference speed, three-state valves, quantizer."""

from __future__ import annotations

import math
from decimal import Decimal, localcontext

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from chassistune.controllers import ecu as E
from chassistune.controllers.ecu_params import EcuParams, draw_noise, orifice_gains

ZERO = np.zeros(1)


def _edge_time(k: int, pitch: float, w0: float, alpha: float) -> float:
    """Exact time of edge k on theta(t) = w0 t - alpha t^2 / 2 (stable root)."""
    theta = k * pitch
    return 2.0 * theta / (w0 + math.sqrt(w0 * w0 - 2.0 * alpha * theta))


def _decelerating_wheel(
    teeth: int, timer_s: float, w0: float = 60.0, alpha: float = 18.0, dt: float = 1e-3
) -> list[tuple[float, float, float, int, float]]:
    """Drive the sensor over a wheel decelerating uniformly from w0 (rad/s) to near rest.

    Returns per step end: (t, true speed, estimate, last edge index, captured t_prev)."""
    pitch = 2.0 * math.pi / teeth
    k_next = E.sensor_first_edge(0.0, teeth, ZERO)
    t_last, t_prev, w_est = -1.0, -1.0, w0
    rows = []
    for i in range(int((w0 / alpha) / dt) - 1):
        ta, tb = i * dt, (i + 1) * dt
        th_a, th_b = w0 * ta - 0.5 * alpha * ta * ta, w0 * tb - 0.5 * alpha * tb * tb
        k_next, t_last, t_prev, w_est = E.sensor_step(
            th_a,
            th_b,
            w0 - alpha * ta,
            w0 - alpha * tb,
            ta,
            dt,
            k_next,
            t_last,
            t_prev,
            w_est,
            teeth,
            timer_s,
            ZERO,
            ZERO,
        )
        rows.append((tb, w0 - alpha * tb, w_est, k_next - 1, t_prev))
    assert pitch > 0.0
    return rows


def _error_and_bound(
    teeth: int, timer_s: float, alpha: float = 18.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """|estimate - true speed|, its analytic bound and the true speed at every step end after
    two captured edges. Bound: the captured period is within one timer tick of the true one,
    T_hat in (T - tau, T + tau), so |pitch/T_hat - w_mean| <= w_mean tau / (T - tau), and the
    mean speed over the last period differs from the speed now by at most alpha (t - t_k-1)."""
    pitch = 2.0 * math.pi / teeth
    err, bound, speed = [], [], []
    for t, w, w_est, k, t_prev in _decelerating_wheel(teeth, timer_s, alpha=alpha):
        if t_prev < 0.0:
            continue
        t_k, t_k1 = _edge_time(k, pitch, 60.0, alpha), _edge_time(k - 1, pitch, 60.0, alpha)
        period = t_k - t_k1
        w_mean = pitch / period
        err.append(abs(w_est - w))
        bound.append(w_mean * timer_s / (period - timer_s) + alpha * (t - t_k1))
        speed.append(w)
    return np.array(err), np.array(bound), np.array(speed)


@pytest.mark.parametrize(
    ("teeth", "timer_s"), [(48, 1e-6), (1000, 1e-7), (10_000, 1e-9), (1_000_000, 1e-9)]
)
def test_sensor_error_within_the_tooth_and_timer_bound(teeth: int, timer_s: float) -> None:
    err, bound, speed = _error_and_bound(teeth, timer_s)
    assert speed.min() < 0.5  # edges arrive down to a crawl: every speed is checked
    assert np.all(err <= bound * (1.0 + 1e-9) + 1e-12)


def test_sensor_holds_between_edges_and_lags_at_low_speed() -> None:
    rows = _decelerating_wheel(48, 1e-6)
    ests = np.array([r[2] for r in rows])
    edges = np.array([r[3] for r in rows])
    same_edge = edges[1:] == edges[:-1]
    assert same_edge.any()
    assert np.all(ests[1:][same_edge] == ests[:-1][same_edge])  # no edge: the estimate holds
    truth = np.array([r[1] for r in rows])
    slow = truth < 2.0
    assert np.max(ests[slow] - truth[slow]) > 0.1  # 48 teeth: the estimate lags at a crawl


def test_fine_sensor_converges_to_the_true_speed() -> None:
    """10^6 teeth and a 1 ns timer: above 1 rad/s the error is the timer over the edge period,
    w tau N / (2 pi) relative (0.9 % at 60 rad/s, falling with the speed), where 48 teeth and
    1 us lag by more than the speed itself at a crawl (one edge per 0.13 s at 1 rad/s)."""
    err, _, speed = _error_and_bound(1_000_000, 1e-9)
    rel = (err / speed)[speed >= 1.0]
    slow = speed[speed >= 1.0] < 6.0
    assert rel.max() < 0.0092
    assert rel[slow].max() < 1e-3
    err48, _, speed48 = _error_and_bound(48, 1e-6)
    crawl = (speed48 >= 1.0) & (speed48 < 6.0)
    assert (err48 / speed48)[crawl].max() > 1.0


def _constant_speed_edges(
    w: float, teeth: int, spacing: np.ndarray, seconds: float, jitter: np.ndarray = ZERO
) -> tuple[np.ndarray, np.ndarray]:
    """(estimate, captured period) after each captured edge at constant speed (timer 1 ps)."""
    dt = 1e-4
    k_next = E.sensor_first_edge(0.0, teeth, spacing)
    t_last, t_prev, w_est = -1.0, -1.0, w
    est, periods = [], []
    for i in range(round(seconds / dt)):
        ta = i * dt
        k_old = k_next
        k_next, t_last, t_prev, w_est = E.sensor_step(
            w * ta,
            w * (ta + dt),
            w,
            w,
            ta,
            dt,
            k_next,
            t_last,
            t_prev,
            w_est,
            teeth,
            1e-12,
            spacing,
            jitter,
        )
        if k_next > k_old and t_prev >= 0.0:
            est.append(w_est)
            periods.append(t_last - t_prev)
    return np.array(est), np.array(periods)


def _constant_speed_estimates(w: float, teeth: int, spacing: np.ndarray, revs: int) -> np.ndarray:
    return _constant_speed_edges(w, teeth, spacing, revs * 2.0 * math.pi / w)[0]


def test_spacing_error_shows_as_lines_at_the_rotation_harmonics() -> None:
    teeth, w, revs = 48, 50.0, 17
    spacing = draw_noise(EcuParams(sensor_spacing_error=0.05), seed=3).spacing_rad
    assert spacing.shape == (teeth,)
    est = _constant_speed_estimates(w, teeth, spacing, revs)[: teeth * (revs - 2)]
    n_rev = revs - 2
    spec = np.abs(np.fft.rfft(est - est.mean())) ** 2
    harmonic = np.arange(spec.size) % n_rev == 0  # multiples of the rotation frequency
    assert spec[harmonic].sum() > 0.999 * spec.sum()
    assert est.std() > 0.01 * w  # the spacing error is visible
    perfect = _constant_speed_estimates(w, teeth, np.zeros(1), 3)
    assert np.max(np.abs(perfect - w)) < 1e-6 * w


def test_sinusoidal_spacing_error_gives_one_line() -> None:
    teeth, w, order = 48, 50.0, 3
    pitch = 2.0 * math.pi / teeth
    spacing = 0.02 * pitch * np.sin(2.0 * math.pi * order * np.arange(teeth) / teeth)
    est = _constant_speed_estimates(w, teeth, spacing, 12)[: teeth * 10]
    spec = np.abs(np.fft.rfft(est - est.mean()))
    assert int(np.argmax(spec)) == order * 10  # order x rotation frequency
    assert spec[order * 10] > 0.99 * np.sqrt((spec**2).sum())


VALVES = EcuParams()
P_S, P_R = 1500.0, 0.0
KB, KD = orifice_gains(VALVES, P_S, P_R)


def test_orifice_law_is_exact_and_meets_its_fill_times() -> None:
    assert E.orifice_advance(P_R, E.VALVE_BUILD, VALVES.valve_build_time_s, KB, KD, P_S, P_R) == P_S
    assert (
        E.orifice_advance(P_R, E.VALVE_BUILD, 0.99 * VALVES.valve_build_time_s, KB, KD, P_S, P_R)
        < P_S
    )
    assert E.orifice_advance(P_S, E.VALVE_DUMP, VALVES.valve_dump_time_s, KB, KD, P_S, P_R) == P_R
    p, h = 300.0, 0.01
    half = E.orifice_advance(
        E.orifice_advance(p, 1, h / 2, KB, KD, P_S, P_R), 1, h / 2, KB, KD, P_S, P_R
    )
    assert half == pytest.approx(E.orifice_advance(p, 1, h, KB, KD, P_S, P_R), rel=1e-13)
    q, n = p, 10_000  # RK4 on dp/dt = kb sqrt(ps - p)
    for _ in range(n):
        f = lambda x: KB * math.sqrt(max(P_S - x, 0.0))  # noqa: E731
        s = h / n
        k1 = f(q)
        k2 = f(q + s / 2 * k1)
        k3 = f(q + s / 2 * k2)
        q += s / 6 * (k1 + 2 * k2 + 2 * k3 + f(q + s * k3))
    assert E.orifice_advance(p, 1, h, KB, KD, P_S, P_R) == pytest.approx(q, rel=1e-10)


def _run_modulator(
    rates: list[float], p0: float, params: EcuParams = VALVES
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Drive the modulator with one duty-quantized pulse per control period.

    Returns pressures at every 1e-5 s, the valve state there, and the sample times."""
    ts, dead, min_on = params.ecu_ts_s, params.valve_dead_time_s, params.valve_min_on_s
    prev = (E.VALVE_HOLD, 0.0, 0.0)
    cur = (E.VALVE_HOLD, 0.0, 0.0)
    p, residual = p0, 0.0
    h = 1e-5
    per = round(ts / h)
    ps, modes, times = [], [], []
    for k, rate in enumerate(rates):
        t_tick = k * ts
        mode, on, residual = E.duty_pulse(rate, residual, p, ts, KB, KD, P_S, P_R, min_on)
        prev, cur = cur, (mode, t_tick + dead, on)
        for j in range(per):
            t = t_tick + j * h
            modes.append(E.valve_mode_at(t, *prev, *cur))
            p = E.modulator_advance(p, t, h, *prev, *cur, KB, KD, P_S, P_R)
            ps.append(p)
            times.append(t + h)
    return np.array(ps), np.array(modes), np.array(times)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.floats(-1e6, 1e6, allow_nan=False), min_size=2, max_size=40), st.floats(0.0, 1500.0)
)
def test_valves_stay_between_return_and_supply_and_respect_min_on(
    rates: list[float], p0: float
) -> None:
    ps, modes, times = _run_modulator(rates, p0)
    assert np.all(np.isfinite(ps))
    assert np.all((ps >= P_R) & (ps <= P_S))
    change = np.nonzero(modes[1:] != modes[:-1])[0]
    gaps = np.diff(times[change])
    assert np.all(gaps >= VALVES.valve_min_on_s - 2e-5)


def test_duty_pulses_track_a_pressure_rate() -> None:
    """5000 units/s asks for 25 units per period, about 1.3 ms of inlet: below the 2 ms
    minimum on-time, so single pulses overshoot; the carried residual keeps the mean rate."""
    rate = 5e3
    ps, _, _ = _run_modulator([rate] * 40, 200.0)
    per = round(VALVES.ecu_ts_s / 1e-5)
    rise = ps[per * 39 - 1] - ps[per - 1]
    assert rise == pytest.approx(rate * 38 * VALVES.ecu_ts_s, rel=0.05)
    ps_down, _, _ = _run_modulator([-rate] * 40, 1200.0)
    fall = ps_down[per * 39 - 1] - ps_down[per - 1]
    assert fall == pytest.approx(-rate * 38 * VALVES.ecu_ts_s, rel=0.05)


def test_slew_limited_vref_on_a_cycling_wheel() -> None:
    """Vehicle at -8 m/s^2; the wheel cycles between 30 % slip and free rolling every 0.2 s.
    With a_max above the deceleration the estimate never exceeds the truth, never falls below
    the wheel, and re-anchors to the truth when the wheel spins up."""
    ts, a_max = 5e-3, 11.77
    t = np.arange(0.0, 3.0, ts)
    v = 30.0 - 8.0 * t
    slip = 0.3 * (np.arange(t.size) % 40) / 40  # saw of 0.2 s: builds slip, releases to 0
    wheel = v * (1.0 - slip)
    vref = np.empty_like(t)
    prev = wheel[0]
    for i in range(t.size):
        prev = E.vref_slew(prev, wheel[i], a_max, ts)
        vref[i] = prev
    assert np.all(vref >= wheel)
    assert np.all(vref <= v + 1e-12)
    anchored = slip == 0.0
    assert np.allclose(vref[anchored], v[anchored])
    assert np.max(v - vref) <= (a_max - 8.0) * 0.2 + 1e-9  # slews at a_max for one cycle


def test_slew_limited_vref_drifts_on_a_wheel_held_at_constant_slip() -> None:
    ts = 5e-3
    t = np.arange(0.0, 5.0, ts)
    v = 10.0 - 1.0 * t  # ice: 1 m/s^2
    wheel = 0.9 * v  # a continuous controller holding 10 % slip
    prev = v[0]
    for i in range(t.size):
        prev = E.vref_slew(prev, wheel[i], 11.77, ts)
    assert prev == pytest.approx(wheel[-1])  # vref sits on the wheel: the computed slip is 0
    assert v[-1] - prev == pytest.approx(0.1 * v[-1])


def test_select_high_and_accelerometer_reference() -> None:
    assert E.select_high4(1.0, 4.0, 2.0, 3.0) == 4.0
    ts, bias = 5e-3, 0.1
    v_true, vref = 20.0, 20.0
    for _ in range(400):  # 2 s at -5 m/s^2, the wheel far below (slipping): no anchoring
        v_true -= 5.0 * ts
        a_meas = E.accelerometer(-5.0, bias, 0.0)
        vref = E.vref_accel(vref, 0.5 * v_true, -5.0, a_meas, ts, 0.3, 0.5, False, 0, 1)[0]
    assert vref - v_true == pytest.approx(bias * 2.0, rel=1e-9)
    vref = E.vref_accel(vref, v_true, -5.0, a_meas, ts, 0.3, 0.5, False, 0, 1)[0]  # anchors
    assert vref == v_true


def test_accelerometer_reference_ignores_a_wheel_slowing_down() -> None:
    """A wheel decelerating at 15 m/s^2 while the vehicle does 8 m/s^2 stays within 0.3 m/s of
    the estimate for a sample at a time; it must not drag the estimate down with it."""
    ts = 5e-3
    v_true, wheel, vref = 30.0, 30.0, 30.0
    for _ in range(100):
        v_true -= 8.0 * ts
        wheel -= 15.0 * ts
        vref = E.vref_accel(vref, wheel, -15.0, -8.0, ts, 0.3, 0.5, False, 0, 1)[0]
    assert vref == pytest.approx(v_true, abs=1e-9)
    assert v_true - wheel > 3.0


def test_accelerometer_reference_reanchors_on_a_released_wheel() -> None:
    """A +0.1 m/s^2 bias has lifted the estimate 0.4 m/s above the truth while the wheel
    slipped; the brake is released (coasting, a_true = 0): speed agreement alone never brings
    it back (it keeps climbing at the bias rate), a released stable wheel re-anchors it, a
    released wheel still spinning up does not."""
    ts, v = 5e-3, 20.0
    a_meas = E.accelerometer(0.0, 0.1, 0.0)
    vref = v + 0.4
    for _ in range(1000):  # 5 s
        vref = E.vref_accel(vref, v, 0.0, a_meas, ts, 0.3, 0.5, False, 0, 1)[0]
    assert vref - v == pytest.approx(0.9, rel=1e-9)
    assert E.vref_accel(vref, v, 20.0, a_meas, ts, 0.3, 0.5, True, 0, 1)[0] > v  # spinning up
    assert E.vref_accel(vref, v, 0.0, a_meas, ts, 0.3, 0.5, True, 0, 1)[0] == v


def test_accelerometer_reference_reanchors_only_after_a_run_of_agreeing_samples() -> None:
    """The end of a release on ice: the wheel (13 % slip, brake released) agrees with the
    vehicle's acceleration for one sample, then spins up again: with hold_samples = 4 the
    estimate is not dragged onto it; four agreeing samples in a row re-anchor it."""
    ts, v, wheel = 5e-3, 23.6, 20.5
    vref, held = E.vref_accel(v, wheel, -1.0, -0.9, ts, 0.3, 0.5, True, 0, 4)
    assert (vref, held) == (pytest.approx(v - 0.9 * ts), 1)
    vref, held = E.vref_accel(vref, wheel, 30.0, -0.9, ts, 0.3, 0.5, True, held, 4)
    assert held == 0 and vref > wheel + 3.0
    for i in range(4):
        vref, held = E.vref_accel(vref, wheel, -1.0, -0.9, ts, 0.3, 0.5, True, held, 4)
        assert (vref == wheel) == (i == 3)
    assert E.vref_accel(v, wheel, -1.0, -0.9, ts, 0.3, 0.5, True, 0, 1)[0] == wheel


def test_cutout_latches_and_schedule_scales() -> None:
    assert not E.cutout_latch(False, 2.5, 2.0)
    assert E.cutout_latch(False, 1.9, 2.0)
    assert E.cutout_latch(True, 30.0, 2.0)
    assert E.cutout_latch(1.0, 30.0, 2.0) and not E.cutout_latch(0.0, 30.0, 2.0)  # float rows
    assert E.speed_schedule(15.0, 30.0, 0.05) == 0.5
    assert E.speed_schedule(0.0, 30.0, 0.05) == 0.05


finite = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)


@settings(max_examples=200, deadline=None)
@given(
    theta0=st.floats(0.0, 1e3),
    dtheta=st.floats(0.0, 20.0),
    w0=st.floats(0.0, 400.0),
    w1=st.floats(0.0, 400.0),
    t0=st.floats(0.0, 100.0),
    dt=st.floats(1e-6, 1e-2),
    teeth=st.integers(1, 1_000_000),
    timer=st.floats(1e-10, 1e-3),
    t_last=st.floats(-1.0, 100.0),
    jit=st.floats(0.0, 1e-3),
    w_est=st.floats(0.0, 1e3),
)
def test_sensor_never_produces_nan(
    theta0: float,
    dtheta: float,
    w0: float,
    w1: float,
    t0: float,
    dt: float,
    teeth: int,
    timer: float,
    t_last: float,
    jit: float,
    w_est: float,
) -> None:
    k = E.sensor_first_edge(theta0, teeth, ZERO)
    jitter = np.array([jit, -jit])
    k2, tl, tp, w = E.sensor_step(
        theta0, theta0 + dtheta, w0, w1, t0, dt, k, t_last, -1.0, w_est, teeth, timer, ZERO, jitter
    )
    k3, tl, tp, w = E.sensor_step(
        theta0 + dtheta,
        theta0 + 2 * dtheta,
        w1,
        w0,
        t0 + dt,
        dt,
        k2,
        tl,
        tp,
        w,
        teeth,
        timer,
        ZERO,
        jitter,
    )
    assert k <= k2 <= k3
    assert math.isfinite(w) and w >= 0.0
    assert math.isfinite(E.sensor_read(w, tl, t0 + 3 * dt, teeth, True))


@settings(max_examples=200, deadline=None)
@given(
    teeth=st.integers(3, 400),
    seed=st.integers(0, 2**32 - 1),
    theta0=st.floats(0.0, 1e4),
    turn=st.floats(0.0, 3.0),
)
def test_edges_passed_are_the_last_two_edges_up_to_the_angle(
    teeth: int, seed: int, theta0: float, turn: float
) -> None:
    """Against the definition: the largest edge index whose angle is at most theta1, and the one
    before it unless that is before k_first, with spacing errors at the clip (edges in order)."""
    pitch = 2.0 * math.pi / teeth
    rng = np.random.default_rng(seed)
    spacing = rng.uniform(-0.45, 0.45, teeth) * pitch
    k_first = E.sensor_first_edge(theta0, teeth, spacing)
    theta1 = max(theta0 + turn, E.edge_angle(k_first, teeth, spacing))
    ks = np.arange(k_first - 2, k_first + 3 * teeth + 4)
    angles = np.array([E.edge_angle(int(k), teeth, spacing) for k in ks])
    assert np.all(np.diff(angles) > 0.0)
    k_end = int(ks[angles <= theta1].max())
    assert E.edges_passed(k_first, theta1, teeth, spacing) == (max(k_first, k_end - 1), k_end)


@settings(max_examples=300, deadline=None)
@given(
    rate=finite,
    p=st.floats(-1e4, 1e4),
    ts=st.floats(1e-4, 0.05),
    frac=st.floats(0.0, 0.5),
    v=st.floats(0.0, 100.0),
    a=finite,
    noise=finite,
)
def test_modulator_and_vref_never_produce_nan(
    rate: float, p: float, ts: float, frac: float, v: float, a: float, noise: float
) -> None:
    mode, on, residual = E.duty_pulse(rate, noise, p, ts, KB, KD, P_S, P_R, frac * ts)
    assert mode in (-1, 0, 1) and 0.0 <= on <= ts and math.isfinite(residual)
    q = E.modulator_advance(p, 0.0, ts, mode, 0.0, on, -mode, 0.5 * ts, on, KB, KD, P_S, P_R)
    assert P_R <= q <= P_S
    assert math.isfinite(E.vref_slew(v, 0.5 * v, abs(a), ts))
    assert math.isfinite(
        E.vref_accel(
            v, 0.5 * v, a, E.accelerometer(a, 0.1, noise), ts, 0.3, 0.5, frac > 0.25, 0, 4
        )[0]
    )
    assert math.isfinite(E.speed_schedule(v, 30.0, 0.05))


def _edge_time_errors(dt: float) -> np.ndarray:
    """Captured minus exact edge times on a wheel whose speed oscillates,
    w = 20 + 5 sin(2 pi 10 t) rad/s (timer 1e-15 s: the interpolation error alone)."""
    from scipy.optimize import brentq

    teeth, w0, amp, om = 48, 20.0, 5.0, 2.0 * math.pi * 10.0
    pitch = 2.0 * math.pi / teeth

    def theta(t: float) -> float:
        return w0 * t + amp * (1.0 - math.cos(om * t)) / om

    def speed(t: float) -> float:
        return w0 + amp * math.sin(om * t)

    k_next = E.sensor_first_edge(0.0, teeth, ZERO)
    t_last, t_prev, w_est = -1.0, -1.0, w0
    errs = []
    for i in range(round(0.3 / dt)):
        ta, tb = i * dt, (i + 1) * dt
        k_old = k_next
        k_next, t_last, t_prev, w_est = E.sensor_step(
            theta(ta),
            theta(tb),
            speed(ta),
            speed(tb),
            ta,
            dt,
            k_next,
            t_last,
            t_prev,
            w_est,
            teeth,
            1e-15,
            ZERO,
            ZERO,
        )
        if k_next > k_old:
            k = k_next - 1
            exact = brentq(lambda t, k=k: theta(t) - k * pitch, ta, tb, xtol=1e-16, rtol=1e-15)
            errs.append(t_last - exact)
    return np.abs(np.array(errs))


def test_edge_times_are_fourth_order_in_the_step() -> None:
    """Cubic Hermite on the angle and its rate: time error <= max|theta''''| dt^4 / (384 w_min)
    and falling 16x per halving of the step."""
    coarse, fine = _edge_time_errors(2e-3), _edge_time_errors(1e-3)
    d4 = 5.0 * (2.0 * math.pi * 10.0) ** 3
    assert coarse.max() <= d4 * 2e-3**4 / (384.0 * 15.0) + 2e-15
    assert coarse.max() / fine.max() > 10.0


def _exact_crossing(
    target: float, theta0: float, theta1: float, w0: float, w1: float, dt_s: float
) -> float:
    """The crossing of the Hermite angle of a step with `target` in 50-digit decimals (120
    bisections) of the same float data."""
    dt, t0, t1, a0, a1, tg = (Decimal(x) for x in (dt_s, theta0, theta1, w0, w1, target))

    def angle(x: Decimal) -> Decimal:
        return (
            (2 * x**3 - 3 * x**2 + 1) * t0
            + (x**3 - 2 * x**2 + x) * dt * a0
            + (-2 * x**3 + 3 * x**2) * t1
            + (x**3 - x**2) * dt * a1
        )

    lo, hi = Decimal(0), Decimal(1)
    with localcontext() as ctx:
        ctx.prec = 50
        for _ in range(120):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if angle(mid) < tg else (lo, mid)
    return float((lo + hi) / 2)


def test_edge_search_settles_to_float_resolution_at_any_wheel_angle() -> None:
    """Far into a stop (the wheel at hundreds of radians) the edge search still finds the
    crossing to a few ulps of s, in at most 6 iterations: it works on the angle turned in the
    step, not on the angle itself (whose rounding, 1e-14 rad at 100 rad, is 1e-12 of a step)."""
    rng = np.random.default_rng(4)
    errors, iterations = [], []
    for _ in range(300):
        w0 = rng.uniform(5.0, 60.0)
        w1 = w0 * (1.0 + rng.uniform(-0.05, 0.05))
        theta0 = rng.uniform(0.0, 1e3)
        theta1 = theta0 + 1e-3 * (w0 + w1) / 2.0
        target = theta0 + rng.uniform(0.01, 1.0) * (theta1 - theta0)
        s, lo, hi, done, a, dtheta = E.crossing_start(target, theta0, theta1)
        n = 0
        while not done:
            s, lo, hi, done = E.crossing_iteration(s, lo, hi, done, a, dtheta, w0, w1, 1e-3)
            n += 1
        assert s == E.crossing_fraction(target, theta0, theta1, w0, w1, 1e-3)
        errors.append(abs(s - _exact_crossing(target, theta0, theta1, w0, w1, 1e-3)))
        iterations.append(n)
    assert max(errors) <= 4.0 * 2.0**-52
    assert max(iterations) <= 6


def test_jitter_spreads_the_captured_period() -> None:
    """Edge jitter of std sigma makes the captured period err by about sqrt(2) sigma."""
    teeth, w, sigma = 48, 50.0, 2e-6
    jitter = draw_noise(EcuParams(sensor_jitter_s=sigma), seed=5).jitter_s
    _, periods = _constant_speed_edges(w, teeth, ZERO, 4.0, jitter)
    dev = periods - 2.0 * math.pi / teeth / w
    assert dev.std() == pytest.approx(math.sqrt(2.0) * sigma, rel=0.15)


def test_bounded_read_sees_a_locked_wheel() -> None:
    """A wheel that stops shows no edge: the held estimate stays, the bounded read falls as
    pitch / (time since the last edge)."""
    teeth, w_est, t_last = 48, 40.0, 1.0
    pitch = 2.0 * math.pi / teeth
    assert E.sensor_read(w_est, t_last, 1.5, teeth, False) == w_est
    assert E.sensor_read(w_est, t_last, 1.5, teeth, True) == pytest.approx(pitch / 0.5)
    assert E.sensor_read(w_est, t_last, 1.001, teeth, True) == w_est  # edge not yet overdue


def test_switching_laws_command_the_valves_directly() -> None:
    ts, min_on = 5e-3, 2e-3
    assert E.switching_pulse(10.0, 10.0, ts, min_on) == (E.VALVE_BUILD, ts)
    assert E.switching_pulse(-10.0, 10.0, ts, min_on) == (E.VALVE_DUMP, ts)
    assert E.switching_pulse(0.0, 10.0, ts, min_on) == (E.VALVE_HOLD, 0.0)
    assert E.switching_pulse(2.5, 10.0, ts, min_on) == (E.VALVE_BUILD, min_on)  # slow build
    assert E.switching_pulse(1.0, 10.0, ts, min_on) == (E.VALVE_HOLD, 0.0)  # below min_on / 2


def test_state_read_from_float_rows() -> None:
    """Lane kernels keep every state in float rows: a whole float edge index or valve state
    gives the same step as an integer."""
    args = (0.0, 1.0, 20.0, 20.0, 0.0, 0.05)
    tail = (-1.0, -1.0, 20.0, 48, 1e-6, ZERO, ZERO)
    assert E.sensor_step(*args, 1.0, *tail) == E.sensor_step(*args, 1, *tail)
    assert E.orifice_advance(100.0, 1.0, 1e-3, KB, KD, P_S, P_R) == E.orifice_advance(
        100.0, E.VALVE_BUILD, 1e-3, KB, KD, P_S, P_R
    )
    assert E.modulator_advance(
        100.0, 0.0, 5e-3, 0.0, 0.0, 0.0, -1.0, 1e-3, 2e-3, KB, KD, P_S, P_R
    ) == E.modulator_advance(100.0, 0.0, 5e-3, 0, 0.0, 0.0, -1, 1e-3, 2e-3, KB, KD, P_S, P_R)
