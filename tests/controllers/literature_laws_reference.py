"""Test oracle: the five ABS laws of the literature (docs/abs_laws.md) as plain-Python discrete
step functions, and a plain-Python single-wheel closed loop to run them in.

Deliberately independent of the package's kernels: the wheel is the `paper-derlsp-ao` plant of
docs/design.md 3.1 with the bilinear tire of 3.2 written out here, integrated by classic RK4 at
a small step; the law runs every `ts_s` (zero-order hold) on what an ECU has: the wheel speed
(read exactly), the reference speed (the true vehicle speed: the ideal ECU limit), the brake
pressure (a pressure sensor) and the force estimate F = (kq q - I dw/dt) / R from the last
sample's wheel-speed difference. Every law returns a pressure-rate demand r (pressure unit/s),
limited to +-rate_max, which the K/(s(Ts+1)) actuator follows (u = r / K). A law's state is a
tuple, zero at the start unless its `start` says otherwise; its gains a frozen dataclass.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Wheel:
    """paper-derlsp-ao (design.md 3.1), SI; pressure in its own unit (kq = 1 N m per unit)."""

    mass_kg: float = 100.0
    inertia_kg_m2: float = 12.0
    radius_m: float = 0.5
    g_m_s2: float = 9.81
    actuator_gain: float = 100.0
    actuator_tau_s: float = 0.01
    brake_gain: float = 1.0
    q_max: float = 1500.0
    v0_m_s: float = 30.0
    v_stop_m_s: float = 0.5


WHEEL = Wheel()
RATE_MAX = WHEEL.q_max / 0.15
"""The valves' build rate: q_max in 0.15 s (docs/ecu.md `valve_build_time_s`), pressure unit/s."""


@dataclass(frozen=True)
class Road:
    """Bilinear tire (design.md 3.2): optimal slip, peak mu, locked-wheel mu."""

    slip_opt: float
    mu_peak: float
    mu_lock: float

    def mu(self, s: float) -> float:
        st, mh, mg = self.slip_opt, self.mu_peak, self.mu_lock
        if s <= st:
            return mh * s / st
        return (mh - mg * st) / (1.0 - st) - (mh - mg) * s / (1.0 - st)


DRY_CONCRETE = Road(0.2, 0.9, 0.75)
ICE = Road(0.1, 0.1028, 0.07)
WET_ASPHALT = Road(0.2, 0.78, 0.50)


@dataclass(frozen=True)
class TableRoad:
    """A mu-slip table, linear between its nodes (design.md 3.1, MathWorks sldemo_absbrake)."""

    slips: tuple[float, ...]
    mus: tuple[float, ...]

    def mu(self, s: float) -> float:
        return float(np.interp(s, self.slips, self.mus))

    @property
    def mu_peak(self) -> float:
        return max(self.mus)

    @property
    def slip_opt(self) -> float:
        return self.slips[self.mus.index(self.mu_peak)]

    @property
    def mu_lock(self) -> float:
        return self.mus[-1]


_SLDEMO_MU = "0 .4 .8 .97 1 .98 .96 .94 .92 .9 .88 .855 .83 .81 .79 .77 .75 .73 .72 .71 .7"
SLDEMO_TABLE = TableRoad(
    tuple(0.05 * i for i in range(21)), tuple(float(x) for x in _SLDEMO_MU.split())
)
"""Peak 1.0 at slip 0.2, smooth-ish on both sides (0.97 at 0.15, 0.98 at 0.25)."""


@dataclass(frozen=True)
class Measured:
    """What the law sees at a sample instant."""

    t_s: float
    slip: float
    wheel_speed_rad_s: float
    wheel_speed_prev_rad_s: float
    pressure: float
    pressure_prev: float
    v_ref_m_s: float
    ts_s: float
    wheel: Wheel

    @property
    def wheel_accel_rad_s2(self) -> float:
        return (self.wheel_speed_rad_s - self.wheel_speed_prev_rad_s) / self.ts_s

    @property
    def force_n(self) -> float:
        """F = (kq q + I dw/dt) / R, the ECU's tire-force estimate (from I dw/dt = R F - kq q;
        with the wheel's deceleration -dw/dt it reads (kq q - I |dw/dt|) / R), as the mean over
        the last sample: dw/dt its wheel-speed difference over ts, q the mean of its two pressure
        readings (both terms then describe the same interval)."""
        wh = self.wheel
        q_mean = 0.5 * (self.pressure + self.pressure_prev)
        return (wh.brake_gain * q_mean + wh.inertia_kg_m2 * self.wheel_accel_rad_s2) / wh.radius_m

    @property
    def speed_m_s(self) -> float:
        """The reference speed, kept away from 0 for the laws that divide by it."""
        return max(self.v_ref_m_s, 1.0)


def _rate(r: float) -> float:
    return min(max(r, -RATE_MAX), RATE_MAX)


def _slip_model(m: Measured) -> tuple[float, float]:
    """(b, c) of dS/dt = (b q - c F) / v, the wheel-slip dynamics with the force F frozen:
    b = R kq / I, c = R^2 / I + (1 - S) / M (from M dv/dt = -F, I dw/dt = R F - kq q)."""
    wh = m.wheel
    b = wh.radius_m * wh.brake_gain / wh.inertia_kg_m2
    c = wh.radius_m**2 / wh.inertia_kg_m2 + (1.0 - m.slip) / wh.mass_kg
    return b, c


# --- sliding-mode slip control with a boundary layer --------------------------------------------


@dataclass(frozen=True)
class SlidingMode:
    target: float = 0.15
    reach_1_s: float = 20.0  # k: dS/dt = -k sat(sigma / phi) on the pressure the law asks for
    layer: float = 0.05  # phi, slip
    pressure_tau_s: float = 0.02  # the pressure demand is tracked at rate (q_cmd - q) / tau


def sliding_mode_step(g: SlidingMode, state: tuple, m: Measured) -> tuple[tuple, float]:
    """sigma = S - S*; q_cmd = (c F + v dS/dt|wanted) / b with dS/dt|wanted = -k sat(sigma/phi)."""
    b, c = _slip_model(m)
    sigma = m.slip - g.target
    sat = min(max(sigma / g.layer, -1.0), 1.0)
    q_cmd = (c * m.force_n - m.speed_m_s * g.reach_1_s * sat) / b
    q_cmd = min(max(q_cmd, 0.0), m.wheel.q_max)
    return state, _rate((q_cmd - m.pressure) / g.pressure_tau_s)


# --- linear ADRC -------------------------------------------------------------------------------


@dataclass(frozen=True)
class Adrc:
    target: float = 0.15
    omega_c_rad_s: float = 15.0  # controller bandwidth: kp = wc^2, kd = 2 wc
    omega_o_rad_s: float = 60.0  # observer bandwidth: l = (3 wo, 3 wo^2, wo^3)
    b0_scale: float = 1.0  # b0 = scale R kq / (I v)


def adrc_step(g: Adrc, state: tuple, m: Measured) -> tuple[tuple, float]:
    """Second-order ADRC on y = S with input r = dq/dt (Gao 2003): Euler ESO, then
    r = (wc^2 (S* - z1) - 2 wc z2 - z3) / b0."""
    b0 = g.b0_scale * m.wheel.radius_m * m.wheel.brake_gain / (m.wheel.inertia_kg_m2 * m.speed_m_s)
    if not state:
        state = (m.slip, 0.0, 0.0, 0.0)
    z1, z2, z3, r_prev = state
    wo, ts = g.omega_o_rad_s, m.ts_s
    e = z1 - m.slip
    z1, z2, z3 = (
        z1 + ts * (z2 - 3.0 * wo * e),
        z2 + ts * (z3 - 3.0 * wo**2 * e + b0 * r_prev),
        z3 + ts * (-(wo**3) * e),
    )
    wc = g.omega_c_rad_s
    r = _rate((wc**2 * (g.target - z1) - 2.0 * wc * z2 - z3) / b0)
    return (z1, z2, z3, r), r


# --- mixed slip-deceleration control -----------------------------------------------------------


@dataclass(frozen=True)
class MixedSlipDecel:
    alpha: float = 0.1  # weight of the wheel deceleration in the regulated variable
    target: float = 0.25  # eps*: set point of eps = (1 - alpha) S + alpha eta
    kp: float = 2e5  # pressure unit/s per unit eps
    kd: float = 2e3  # pressure unit per unit eps


def mixed_step(g: MixedSlipDecel, state: tuple, m: Measured) -> tuple[tuple, float]:
    """eps = (1 - alpha) S + alpha eta, eta = -R dw/dt / g; r = kp e + kd (e - e_prev) / ts,
    e = eps* - eps."""
    eta = -m.wheel.radius_m * m.wheel_accel_rad_s2 / m.wheel.g_m_s2
    e = g.target - ((1.0 - g.alpha) * m.slip + g.alpha * eta)
    e_prev = state[0] if state else e
    return (e,), _rate(g.kp * e + g.kd * (e - e_prev) / m.ts_s)


# --- extremum seeking --------------------------------------------------------------------------


@dataclass(frozen=True)
class ExtremumSeeking:
    start: float = 0.15  # theta at the start, slip
    dither: float = 0.02  # a, slip
    dither_rad_s: float = 10.0  # omega
    gain_1_s: float = 2.5  # k: d theta/dt = k xi
    highpass_rad_s: float = 3.0  # omega_h of the washout on the force estimate
    hold_s: float = 0.5  # theta frozen while the brake first applies
    lo: float = 0.03
    hi: float = 0.5
    kp: float = 5e5  # inner slip loop, pressure unit/s per unit slip
    kd: float = 1e4  # inner slip loop, pressure unit per unit slip


def extremum_seeking_step(g: ExtremumSeeking, state: tuple, m: Measured) -> tuple[tuple, float]:
    """J = F / (M g); J_hp = J - J_lp (first-order washout); theta += ts k J_hp sin(w t);
    target theta + a sin(w t) held by the inner slip loop r = kp e + kd (e - e_prev) / ts."""
    j = m.force_n / (m.wheel.mass_kg * m.wheel.g_m_s2)
    theta, j_lp, e_prev = state if state else (g.start, j, None)
    ts = m.ts_s
    s = math.sin(g.dither_rad_s * m.t_s)
    j_lp += ts * g.highpass_rad_s * (j - j_lp)
    gain = g.gain_1_s if m.t_s >= g.hold_s else 0.0
    theta = min(max(theta + ts * gain * (j - j_lp) * s, g.lo), g.hi)
    e = theta + g.dither * s - m.slip
    e_prev = e if e_prev is None else e_prev
    return (theta, j_lp, e), _rate(g.kp * e + g.kd * (e - e_prev) / ts)


# --- model-predictive slip control -------------------------------------------------------------


@dataclass(frozen=True)
class Mpc:
    target: float = 0.15
    horizon: int = 3
    lookahead_s: float = 0.05  # T_L: the cost weighs the slip projected T_L ahead
    move_weight: float = 1e-2  # rho on (z / q_max)^2 against the slip error squared


def mpc_qp(
    n: int,
    *,
    slip: float,
    target: float,
    v_m_s: float,
    q: float,
    force_n: float,
    ts_s: float,
    rate_max: float,
    lookahead_s: float,
    move_weight: float,
    wheel: Wheel = WHEEL,
) -> tuple[np.ndarray, np.ndarray, float]:
    """(H, f, dq_max) of the MPC's QP in the moves z_l = q_(l+1) - q_l, l = 0 .. n-1. The
    prediction S_(j+1) = S_j + (ts / v)(b q_(j+1) - c F) (force and 1 - S frozen at the sample)
    gives the projected slip y_j = S_j + T_L (b q_j - c F) / v = y_free_j + sum_(l<j) G_jl z_l,
    G_jl = beta (j - l) + gamma, beta = ts b / v, gamma = T_L b / v; the cost
    sum_j (y_j - S*)^2 + rho sum_l (z_l / q_max)^2; dq_max = rate_max ts bounds each move."""
    meas = Measured(0.0, slip, 0.0, 0.0, q, q, v_m_s, ts_s, wheel)
    b, c = _slip_model(meas)
    v = max(v_m_s, 1.0)
    beta, gamma = ts_s * b / v, lookahead_s * b / v
    j = np.arange(1, n + 1, dtype=float)
    drift = (b * q - c * force_n) / v
    free = slip + j * ts_s * drift + lookahead_s * drift
    gm = np.array(
        [[beta * (i + 1 - col) + gamma if col <= i else 0.0 for col in range(n)] for i in range(n)]
    )
    h = 2.0 * (gm.T @ gm + move_weight / wheel.q_max**2 * np.eye(n))
    f = 2.0 * gm.T @ (free - target)
    return h, f, rate_max * ts_s


def qp_by_enumeration(
    h: np.ndarray, f: np.ndarray, lo: np.ndarray, hi: np.ndarray, q0: float, q_max: float
) -> np.ndarray:
    """The QP's minimiser (moves in [lo, hi], 0 <= q0 + cumulated moves <= q_max) by enumeration
    of the active sets: every set of at most n rows of C = [I; L] at a bound, with independent
    rows, its KKT system solved in a batch; the primal-feasible one with multipliers of the right
    sign is the minimiser (unique: H > 0)."""
    tol = 1e-9
    n = f.shape[0]
    scale = 1.0 / np.abs(h).max()  # the same minimiser; multipliers of order one
    h, f = h * scale, f * scale
    c = np.vstack([np.eye(n), np.tril(np.ones((n, n)))])
    lower = np.concatenate([lo, np.full(n, -q0)])
    upper = np.concatenate([hi, np.full(n, q_max - q0)])
    z_free = np.linalg.solve(h, -f)
    if np.all(c @ z_free >= lower - tol) and np.all(c @ z_free <= upper + tol):
        return z_free
    found = []
    for k in range(1, n + 1):
        sets = [
            (rows, sides)
            for rows in itertools.combinations(range(2 * n), k)
            for sides in itertools.product((0, 1), repeat=k)
        ]
        rows = np.array([s[0] for s in sets])
        sides = np.array([s[1] for s in sets])
        ca = c[rows]
        independent = np.abs(np.linalg.det(ca @ np.transpose(ca, (0, 2, 1)))) > 1e-9
        ca, rows, sides = ca[independent], rows[independent], sides[independent]
        kkt = np.zeros((len(ca), n + k, n + k))
        kkt[:, :n, :n] = h
        kkt[:, :n, n:] = np.transpose(ca, (0, 2, 1))
        kkt[:, n:, :n] = ca
        rhs = np.concatenate(
            [np.broadcast_to(-f, (len(ca), n)), np.where(sides == 1, upper[rows], lower[rows])],
            axis=1,
        )
        sol = np.linalg.solve(kkt, rhs[..., None])[..., 0]
        z, nu = sol[:, :n], sol[:, n:]
        s = z @ c.T
        slack = tol * (1.0 + np.abs(nu).max(axis=1, keepdims=True))
        primal = np.all((s >= lower - tol) & (s <= upper + tol), axis=1)
        dual = np.all(np.where(sides == 1, nu >= -slack, nu <= slack), axis=1)
        found.extend(z[primal & dual])
    if not found:
        raise AssertionError("no KKT point found: the enumeration is wrong")
    spread = np.ptp(np.array(found), axis=0).max()
    if spread > 1e-7 * (1.0 + np.abs(found[0]).max()):
        raise AssertionError(f"KKT points disagree by {spread:g}")
    return found[0]


def mpc_step(g: Mpc, state: tuple, m: Measured) -> tuple[tuple, float]:
    """The first move of the QP's minimiser, applied as the rate z_0 / ts over the sample."""
    h, f, dq = mpc_qp(
        g.horizon,
        slip=m.slip,
        target=g.target,
        v_m_s=m.v_ref_m_s,
        q=m.pressure,
        force_n=m.force_n,
        ts_s=m.ts_s,
        rate_max=RATE_MAX,
        lookahead_s=g.lookahead_s,
        move_weight=g.move_weight,
        wheel=m.wheel,
    )
    box = np.full(g.horizon, dq)
    z = qp_by_enumeration(h, f, -box, box, min(max(m.pressure, 0.0), m.wheel.q_max), m.wheel.q_max)
    return state, _rate(z[0] / m.ts_s)


# --- the closed loop ---------------------------------------------------------------------------

Step = Callable[[object, tuple, Measured], tuple[tuple, float]]


@dataclass(frozen=True)
class Stop:
    distance_m: float
    time_s: float
    stopped: bool
    slip_min: float
    slip_max: float
    finite: bool
    t_s: np.ndarray  # sample instants
    slip: np.ndarray  # true slip at each sample
    law_state: list  # the law's state after each sample


def bound_m(road: Road | TableRoad, wh: Wheel = WHEEL) -> float:
    """The adhesion bound (v0^2 - v_stop^2) / (2 mu_peak g)."""
    return (wh.v0_m_s**2 - wh.v_stop_m_s**2) / (2.0 * road.mu_peak * wh.g_m_s2)


def locked_m(road: Road | TableRoad, wh: Wheel = WHEEL) -> float:
    """The locked wheel's distance from the start: (v0^2 - v_stop^2) / (2 mu_lock g)."""
    return (wh.v0_m_s**2 - wh.v_stop_m_s**2) / (2.0 * road.mu_lock * wh.g_m_s2)


def _plant_rates(x: tuple, r_cmd: float, road: Road, wh: Wheel) -> tuple:
    """d/dt of (v, w, q, r, dist), design.md 3.1: M dv/dt = -mu M g, I dw/dt = R F - kq q (w held
    at 0 while the brake holds it), T dr/dt = r_cmd - r (u = r_cmd / K), dq/dt = r with q kept in
    [0, q_max]."""
    v, w, q, r, _ = x
    s = min(max((v - w * wh.radius_m) / v, 0.0), 1.0) if v > 0.0 else 0.0
    force = road.mu(s) * wh.mass_kg * wh.g_m_s2
    dw = (wh.radius_m * force - wh.brake_gain * q) / wh.inertia_kg_m2
    if w <= 0.0 and dw < 0.0:
        dw = 0.0
    dq = 0.0 if (q >= wh.q_max and r > 0.0) or (q <= 0.0 and r < 0.0) else r
    return (-force / wh.mass_kg, dw, dq, (r_cmd - r) / wh.actuator_tau_s, v)


def closed_loop(
    step: Step,
    gains: object,
    road: Road,
    *,
    wheel: Wheel = WHEEL,
    ts_s: float = 5e-3,
    dt_s: float = 2.5e-4,
    t_max_s: float = 60.0,
) -> Stop:
    """One stop from v0 with the wheel rolling freely and the brake released; the law runs every
    ts_s (a whole number of RK4 steps of dt_s); the run ends at v_stop (the distance interpolated
    in the last step) or t_max_s."""
    per_tick = round(ts_s / dt_s)
    wh = wheel
    x = (wh.v0_m_s, wh.v0_m_s / wh.radius_m, 0.0, 0.0, 0.0)
    w_prev, q_prev = x[1], x[2]
    state: tuple = ()
    r_cmd = 0.0
    ts, slips, states = [], [], []
    t = 0.0
    n = 0
    finite = True
    while x[0] > wh.v_stop_m_s and t < t_max_s:
        if n % per_tick == 0:
            v, w, q = x[0], x[1], x[2]
            s = min(max((v - w * wh.radius_m) / v, 0.0), 1.0)
            m = Measured(t, s, w, w_prev, q, q_prev, v, ts_s, wh)
            state, r_cmd = step(gains, state, m)
            finite = finite and math.isfinite(r_cmd)
            w_prev, q_prev = w, q
            ts.append(t)
            slips.append(s)
            states.append(state)
        x0 = x
        k1 = _plant_rates(x, r_cmd, road, wh)
        k2 = _plant_rates(_add(x, k1, dt_s / 2), r_cmd, road, wh)
        k3 = _plant_rates(_add(x, k2, dt_s / 2), r_cmd, road, wh)
        k4 = _plant_rates(_add(x, k3, dt_s), r_cmd, road, wh)
        x = tuple(
            xi + dt_s / 6.0 * (a + 2.0 * b + 2.0 * c + d)
            for xi, a, b, c, d in zip(x, k1, k2, k3, k4, strict=True)
        )
        x = (x[0], max(x[1], 0.0), min(max(x[2], 0.0), wh.q_max), x[3], x[4])
        finite = finite and all(math.isfinite(xi) for xi in x)
        if not finite:
            break
        t += dt_s
        n += 1
    stopped = x[0] <= wh.v_stop_m_s
    dist, time = x[4], t
    if stopped and finite:  # linear interpolation to v = v_stop in the last step
        frac = (x0[0] - wh.v_stop_m_s) / (x0[0] - x[0])
        dist = x0[4] + frac * (x[4] - x0[4])
        time = t - dt_s + frac * dt_s
    arr = np.array(slips)
    return Stop(
        dist,
        time,
        stopped,
        float(arr.min()),
        float(arr.max()),
        finite,
        np.array(ts),
        arr,
        states,
    )


def _add(x: tuple, k: tuple, h: float) -> tuple:
    return tuple(xi + h * ki for xi, ki in zip(x, k, strict=True))


LAWS: dict[str, tuple[Step, object]] = {
    "sliding-mode": (sliding_mode_step, SlidingMode()),
    "adrc": (adrc_step, Adrc()),
    "mixed-slip-deceleration": (mixed_step, MixedSlipDecel()),
    "extremum-seeking": (extremum_seeking_step, ExtremumSeeking()),
    "mpc": (mpc_step, Mpc()),
}
"""Registry name -> (step, default gains)."""


def assert_kernel_runs_reference(
    sc: Any, ref: Any, ts_s: float, distance_rtol: float, slip_atol: float
) -> None:
    """The scenario's run from its default gains stops, as the reference `closed_loop` run
    `ref` does, at its distance within distance_rtol, with its slip at every sample instant
    (ts_s) within slip_atol of the reference's (over more than 400 samples of a moving slip)."""
    g = sc.gains_array(None)
    m = sc.metrics(g[None, :])
    assert m["status"][0] == "stopped" and ref.stopped
    assert abs(m["stop_distance_m"][0] / ref.distance_m - 1.0) < distance_rtol
    slip = sc.trace(g).signals["slip"]
    ticks = np.arange(0, len(slip), round(ts_s / sc.plant_params.dt_s))
    n = min(len(ticks), len(ref.slip))
    assert n > 400 and np.ptp(ref.slip) > 0.1
    assert np.max(np.abs(slip[ticks[:n]] - ref.slip[:n])) < slip_atol


def assert_batch_rows_are_single_runs(sc: Any, rows: int = 5, seed: int = 7) -> None:
    """Random gains in the controller's box: each row's stop distance in one batch equals its
    run alone, bit for bit."""
    rng = np.random.default_rng(seed)
    lo, hi = (np.array([getattr(g, b) for g in sc.controller.gains]) for b in ("lo", "hi"))
    pop = lo + (hi - lo) * rng.random((rows, len(lo)))
    batch = sc.metrics(pop)["stop_distance_m"]
    single = [sc.metrics(row[None, :])["stop_distance_m"][0] for row in pop]
    assert np.array_equal(batch, np.array(single))
