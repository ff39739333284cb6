"""Closed loop of the abs-wheel plant with a sampled controller called from outside: a numba law,
or the exported C through ctypes. The test vectors are recorded here.

The loop is the realistic ECU kernel's (`sim.abs_wheel_ecu_kernel`) with an ideal ECU
(`export.source.IDEAL_ECU`: true wheel and vehicle speed, the continuous actuator, no delay, no
cut-out, no schedule), written from the plant's public interface only:
- the plant's right-hand side `sim.abs_wheel_model` (`wheel_slip`, `wheel_rates`) and the tire
  laws `sim.abs_wheel_tires` (`tire_law_mu` on `TireCurve.kernel_data()` and `table_tuples`);
- the quadrature and RK4 stages of `sim.integrate`;
- the scenario's public parameters (`plant_params`, `target_slip`, `scoring`,
  `bound_distance_m`), packed here into the loop's own declared vector (`LOOP`).
At each tick (every ts = m dt, before the step) the controller sees the exact slip
`wheel_slip(v, w, R)`, the wheel speed and whether the pressure sits at q_max or 0, the true
speed as reference speed, the pressure, the pressure and wheel speed at the last tick and the
time (`SIGNALS`); its command
is held over the m classic RK4 steps of (v, w, q, r) with the step-end update (w >= 0, q clipped
to [0, q_max]) and the stop at v_stop located inside the last step. The kernel's private slots
and packed vectors are not read: tests/export check that this loop gives the ECU kernel's stop
distance (to 1e-12; bitwise in practice) and, for the sampled threshold law, the ideal kernel's.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numba
import numpy as np
from numpy.typing import NDArray

from chassistune._branchfree import clip, fmax, select
from chassistune.layout import Layout, Slot
from chassistune.scenarios.abs_wheel import AbsWheelScenario
from chassistune.sim.abs_wheel_layout import STATUS_NAMES
from chassistune.sim.abs_wheel_model import wheel_rates, wheel_slip
from chassistune.sim.abs_wheel_tires import KIND_TABLE, table_tuples, tire_law_mu
from chassistune.sim.integrate import crossing_fraction, rk4_point, rk4_update, trapezoid

Controller = Callable[[NDArray[np.float64]], float]
"""A sampled controller: the command u for one row of inputs (it keeps its own state)."""

SIGNALS = (
    "slip",
    "wheel_speed_rad_s",
    "pressure_at_max",
    "pressure_at_min",
    "reference_speed_m_s",
    "pressure",
    "pressure_prev",
    "wheel_speed_prev_rad_s",
    "time_s",
)
"""What the loop offers a controller at each sample; each law picks its inputs by name."""

LOOP = Layout(
    "export closed loop",
    (
        Slot("dt_s", "s", "integration step"),
        Slot("wheel_radius_m", "m", "R"),
        Slot("v_stop_m_s", "m/s", "the run ends below this speed"),
        Slot("q_max", "preset unit", "pressure limit"),
        Slot("hopeless_distance_m", "m", "the run ends as hopeless beyond this distance"),
        Slot("steps", "-", "step budget ceil(t_max / dt)"),
        Slot("wheel_load_n", "N", "Fz = load_fraction M g"),
        Slot("inv_mass", "1/kg", "1 / M"),
        Slot("inv_inertia", "1/(kg m^2)", "1 / I"),
        Slot("brake_gain", "N m/preset unit", "kq"),
        Slot("actuator_gain", "preset unit/s", "K"),
        Slot("inv_tau", "1/s", "1 / T of the actuator"),
        Slot("tire_law", "-", "KIND_* of sim.abs_wheel_tires"),
        Slot("c0", "-", "tire coefficient"),
        Slot("c1", "-", "tire coefficient"),
        Slot("c2", "-", "tire coefficient"),
        Slot("c3", "-", "tire coefficient"),
    ),
)
(
    L_DT,
    L_RADIUS,
    L_VSTOP,
    L_QMAX,
    L_HOPELESS_M,
    L_STEPS,
    L_FZ,
    L_INV_M,
    L_INV_I,
    L_KQ,
    L_GAIN,
    L_INV_TAU,
    L_LAW,
    L_C0,
    L_C1,
    L_C2,
    L_C3,
) = (LOOP[n] for n in LOOP.names)
X_V, X_W, X_Q, X_R = range(4)
A_STEP, A_DIST, A_STATUS, A_TIME = range(4)
RUNNING = -1.0
STOPPED, HOPELESS, TIMEOUT, DIVERGED = (
    float(STATUS_NAMES.index(n)) for n in ("stopped", "hopeless", "timeout", "diverged")
)
"""Run status: the kernels' codes (STATUS_NAMES), RUNNING until the run ends."""


@numba.njit(cache=True, nogil=True, error_model="numpy")
def plant_rates(x, u, lc, xc, xs, ys):
    """(dv, dw, dq, dr) of the wheel in state x = (v, w, q, r) under the held command u
    (design.md 3.1)."""
    v, w, q, r = x
    r_w = lc[L_RADIUS]
    c0, c1, c2, c3 = lc[L_C0], lc[L_C1], lc[L_C2], lc[L_C3]
    fx = tire_law_mu(int(lc[L_LAW]), wheel_slip(v, w, r_w), c0, c1, c2, c3, xc, xs, ys) * lc[L_FZ]
    inv_m, inv_i, kq, gain = lc[L_INV_M], lc[L_INV_I], lc[L_KQ], lc[L_GAIN]
    dv, dw, dq, dr, _, _ = wheel_rates(
        w, q, r, fx, u, r_w, inv_m, inv_i, kq, gain, lc[L_INV_TAU], lc[L_QMAX]
    )
    return dv, dw, dq, dr


@numba.njit(cache=True, nogil=True, error_model="numpy")
def advance(x, acc, u, n, lc, xc, xs, ys):
    """Advance the plant x = (v, w, q, r) n RK4 steps of dt with the command u held; acc keeps
    step, distance, status and end time. Returns whether the run ended (stop, divergence,
    hopeless, timeout)."""
    dt = lc[L_DT]
    hs = 0.5 * dt
    h6 = dt / 6.0
    v_stop = lc[L_VSTOP]
    for _ in range(n):
        k = acc[A_STEP]
        if k >= lc[L_STEPS]:
            acc[A_STATUS] = TIMEOUT
            acc[A_TIME] = lc[L_STEPS] * dt
            return True
        t = k * dt
        x0 = (x[X_V], x[X_W], x[X_Q], x[X_R])
        k1 = plant_rates(x0, u, lc, xc, xs, ys)
        k2 = plant_rates(rk4_point(x0, hs, k1), u, lc, xc, xs, ys)
        k3 = plant_rates(rk4_point(x0, hs, k2), u, lc, xc, xs, ys)
        k4 = plant_rates(rk4_point(x0, dt, k3), u, lc, xc, xs, ys)
        vn, wn, qn, rn = rk4_update(x0, h6, k1, k2, k3, k4)
        wn = fmax(wn, 0.0)
        qn = clip(qn, 0.0, lc[L_QMAX])
        v = x0[0]
        stop = vn <= v_stop
        h = crossing_fraction(v, vn, v_stop, stop) * dt
        acc[A_DIST] += trapezoid(v, select(stop, v_stop, vn), h)
        x[X_V], x[X_W], x[X_Q], x[X_R] = vn, wn, qn, rn
        acc[A_STEP] = k + 1.0
        check = vn + wn + qn + rn
        if check - check != 0.0:
            acc[A_STATUS] = DIVERGED
            acc[A_TIME] = t
            return True
        if stop:
            acc[A_STATUS] = STOPPED
            acc[A_TIME] = t + h
            return True
        if acc[A_DIST] > lc[L_HOPELESS_M]:
            acc[A_STATUS] = HOPELESS
            acc[A_TIME] = t + dt
            return True
    return False


@numba.njit(cache=True, nogil=True, error_model="numpy")
def ecu_slip(x, lc):
    """The slip an ideal ECU computes at a tick: `wheel_slip` of the state."""
    return wheel_slip(x[X_V], x[X_W], lc[L_RADIUS])


@dataclass(frozen=True)
class LoopResult:
    """A closed-loop run: ECU inputs and command at every sample, and how the run ended."""

    signals: dict[str, NDArray[np.float64]]  # SIGNALS, one value per sample
    u: NDArray[np.float64]  # command per sample
    stop_distance_m: float
    stop_time_s: float
    status: int  # the kernels' status code (STATUS_NAMES)

    def inputs(self, names: tuple[str, ...]) -> NDArray[np.float64]:
        """The input rows (samples, len(names)) of a law."""
        return np.column_stack([self.signals[n] for n in names])


def loop_vector(scenario: AbsWheelScenario) -> NDArray[np.float64]:
    """The loop's constants (`LOOP`) from the scenario's public parameters, computed as the
    kernels compute them (Fz = (load_fraction M) g, reciprocals of M, I and T)."""
    pp = scenario.plant_params
    kind, coef, _, _ = scenario.tire.kernel_data()
    c = np.zeros(4)
    c[: len(coef)] = coef
    return LOOP.pack(
        {
            "dt_s": pp.dt_s,
            "wheel_radius_m": pp.wheel_radius_m,
            "v_stop_m_s": pp.v_stop_m_s,
            "q_max": pp.q_max,
            "hopeless_distance_m": scenario.scoring.hopeless_factor * scenario.bound_distance_m,
            "steps": math.ceil(pp.t_max_s / pp.dt_s - 1e-9),
            "wheel_load_n": pp.load_fraction * pp.mass_kg * pp.g_m_s2,
            "inv_mass": 1.0 / pp.mass_kg,
            "inv_inertia": 1.0 / pp.wheel_inertia_kg_m2,
            "brake_gain": pp.brake_gain,
            "actuator_gain": pp.actuator_gain,
            "inv_tau": 1.0 / pp.actuator_tau_s,
            "tire_law": kind,
            "c0": c[0],
            "c1": c[1],
            "c2": c[2],
            "c3": c[3],
        }
    )


def _tire_nodes(scenario: AbsWheelScenario) -> tuple[tuple[float, ...], ...]:
    """The padded table of a table tire (`table_tuples`), a two-node dummy for the others."""
    kind, _, xs, ys = scenario.tire.kernel_data()
    if kind != KIND_TABLE:
        xs, ys = np.array([0.0, 1.0]), np.array([0.0, 0.0])
    return table_tuples(xs, ys)


def run(
    scenario: AbsWheelScenario, ts_s: float, controller: Controller, input_names: tuple[str, ...]
) -> LoopResult:
    """Run the closed loop of `scenario` with `controller` called every ts_s (whole steps of dt).

    `input_names` (from SIGNALS) select and order the inputs handed to the controller."""
    lc = loop_vector(scenario)
    xc, xs, ys = _tire_nodes(scenario)
    pp = scenario.plant_params
    m = max(1, round(ts_s / pp.dt_s))
    x = np.array([pp.v0_m_s, pp.v0_m_s / pp.wheel_radius_m, 0.0, 0.0])
    acc = np.array([0.0, 0.0, RUNNING, 0.0])
    rows: list[list[float]] = []
    commands: list[float] = []
    pick = [SIGNALS.index(n) for n in input_names]
    q_prev, w_prev = 0.0, x[X_W]
    while True:
        q, w, t = x[X_Q], x[X_W], acc[A_STEP] * pp.dt_s
        sample = [float(ecu_slip(x, lc)), w, float(q >= pp.q_max), float(q <= 0.0)]
        sample += [x[X_V], q, q_prev, w_prev, t]
        q_prev, w_prev = q, w
        rows.append(sample)
        u = float(controller(np.array([sample[i] for i in pick])))
        commands.append(u)
        if advance(x, acc, u, m, lc, xc, xs, ys):
            break
    data = np.array(rows)
    return LoopResult(
        {n: data[:, i].copy() for i, n in enumerate(SIGNALS)},
        np.array(commands),
        float(acc[A_DIST]),
        float(acc[A_TIME]),
        int(acc[A_STATUS]),
    )
