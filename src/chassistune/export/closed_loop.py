"""Closed loop of the abs-wheel plant with a sampled controller called from outside: a numba law,
or the exported C through ctypes. The test vectors are recorded here.

The plant is integrated exactly as `chassistune.sim.abs_wheel_kernel` integrates it for its sampled
laws: classic RK4 (`sim.integrate`) at the step dt on (v, w, q, r) with the command u held
(zero-order hold) over each sample period ts = m dt, the kernel's own right-hand side
(`plant_rates`), the same step-end update (wheel speed >= 0, pressure clipped to [0, q_max],
clipped slip) and the same stop at v_stop located inside the last step. At each sample the
controller sees the ECU inputs of an ideal sensor set: the clipped slip at the sample, the wheel
speed (rad/s) and whether the pressure sits at q_max or 0. Driving the kernel's own sampled
threshold law, this loop gives the kernel's stop distance bit for bit (tests/export); for the
continuous laws it is the sampled loop that the kernel's realistic ECU mode (issue 15) will run.

The kernel's internals are read in `kernel_plant` and `plant_rates` only (its packed plant vector,
tire data and rates); besides them only its public slot and status constants are used."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from chassistune._branchfree import clip, fmax, select
from chassistune.scenarios.abs_wheel import AbsWheelScenario
from chassistune.sim import abs_wheel_kernel as K
from chassistune.sim.abs_wheel_tires import KIND_TABLE, table_tuples
from chassistune.sim.integrate import crossing_fraction, rk4_point, rk4_update, trapezoid

Controller = Callable[[NDArray[np.float64]], float]
"""A sampled controller: the command u for one row of inputs (it keeps its own state)."""

SIGNALS = ("slip", "wheel_speed_rad_s", "pressure_at_max", "pressure_at_min")
"""What the loop offers a controller at each sample; each law picks its inputs by name."""

# loop constants (L_*), plant state (X_*) and accumulators (A_*) of `advance`
L_DT, L_RADIUS, L_VSTOP, L_QMAX, L_HOPELESS_M, L_STEPS = range(6)
X_V, X_W, X_Q, X_R = range(4)
A_STEP, A_DIST, A_SLIP, A_STATUS, A_TIME = range(5)
RUNNING = -1.0
STOPPED, HOPELESS, TIMEOUT, DIVERGED = (float(c) for c in (
    K.STATUS_STOPPED, K.STATUS_HOPELESS, K.STATUS_TIMEOUT, K.STATUS_DIVERGED))
"""Run status: the kernel's codes, RUNNING until the run ends."""


# -- the kernel's internals: the one place that reads them -----------------------------------

def kernel_plant(scenario: AbsWheelScenario) -> tuple[NDArray[np.float64], tuple[Any, ...]]:
    """The kernel's plant vector of `scenario` and its tire as the kernel's lanes read it (law,
    four coefficients, padded table nodes), as `simulate_abs_wheel` converts them."""
    p, kind, coef, xs, ys = scenario._kernel_args[:5]
    c = np.zeros(4)
    c[: len(coef)] = coef
    nodes = table_tuples(xs, ys) if kind == KIND_TABLE else K._NO_TABLE
    return p, (kind, c[0], c[1], c[2], c[3], *(np.array(t) for t in nodes))


@numba.njit(cache=True, nogil=True, error_model="numpy")
def plant_rates(v, w, q, r, u, p, tire):
    """(dv, dw, dq, dr) of the wheel under the command u (DESIGN 3.1): the kernel's own rates
    with its continuous PID off (kp = ki = kd = 0, z = xf = 0: its command is the held u)."""
    law, c0, c1, c2, c3, xc, xs, ys = tire
    dv, dw, dq, dr, _, _, _ = K._rates(
        law, v, w, q, r, 0.0, 0.0, u, 0.0, 0.0, 0.0, p[K.P_TARGET], p[K.P_RADIUS],
        p[K.P_LOAD] * p[K.P_MASS] * p[K.P_G], 1.0 / p[K.P_MASS], 1.0 / p[K.P_INERTIA], p[K.P_KQ],
        p[K.P_K], 1.0 / p[K.P_TAU], p[K.P_QMAX], p[K.P_NFILTER], c0, c1, c2, c3, xc, xs, ys)
    return dv, dw, dq, dr


# ---------------------------------------------------------------------------------------------

@numba.njit(cache=True, nogil=True, error_model="numpy")
def advance(x, acc, u, n, lc, p, tire):
    """Advance the plant x = (v, w, q, r) n RK4 steps of dt with the command u held; acc keeps
    step, distance, slip, status and end time. Returns whether the run ended (stop, divergence,
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
        v, w, q, r = x[X_V], x[X_W], x[X_Q], x[X_R]
        k1v, k1w, k1q, k1r = plant_rates(v, w, q, r, u, p, tire)
        k2v, k2w, k2q, k2r = plant_rates(rk4_point(v, hs, k1v), rk4_point(w, hs, k1w),
                                         rk4_point(q, hs, k1q), rk4_point(r, hs, k1r), u, p, tire)
        k3v, k3w, k3q, k3r = plant_rates(rk4_point(v, hs, k2v), rk4_point(w, hs, k2w),
                                         rk4_point(q, hs, k2q), rk4_point(r, hs, k2r), u, p, tire)
        k4v, k4w, k4q, k4r = plant_rates(rk4_point(v, dt, k3v), rk4_point(w, dt, k3w),
                                         rk4_point(q, dt, k3q), rk4_point(r, dt, k3r), u, p, tire)
        vn = rk4_update(v, h6, k1v, k2v, k3v, k4v)
        wn = fmax(rk4_update(w, h6, k1w, k2w, k3w, k4w), 0.0)
        qn = clip(rk4_update(q, h6, k1q, k2q, k3q, k4q), 0.0, lc[L_QMAX])
        rn = rk4_update(r, h6, k1r, k2r, k3r, k4r)
        stop = vn <= v_stop
        h = crossing_fraction(v, vn, v_stop, stop) * dt
        acc[A_DIST] += trapezoid(v, select(stop, v_stop, vn), h)
        x[X_V], x[X_W], x[X_Q], x[X_R] = vn, wn, qn, rn
        acc[A_SLIP] = clip((vn - wn * lc[L_RADIUS]) / vn, 0.0, 1.0)
        acc[A_STEP] = k + 1.0
        check = vn + wn + rn
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


@dataclass(frozen=True)
class LoopResult:
    """A closed-loop run: ECU inputs and command at every sample, and how the run ended."""

    signals: dict[str, NDArray[np.float64]]  # SIGNALS, one value per sample
    u: NDArray[np.float64]  # command per sample
    stop_distance_m: float
    stop_time_s: float
    status: int  # the kernel's status code (STATUS_NAMES)

    def inputs(self, names: tuple[str, ...]) -> NDArray[np.float64]:
        """The input rows (samples, len(names)) of a law."""
        return np.column_stack([self.signals[n] for n in names])


def _loop_constants(scenario: AbsWheelScenario) -> NDArray[np.float64]:
    """dt, wheel radius, stop speed, q_max, the hopeless distance and the step budget (L_*), from
    the same numbers the kernel receives."""
    pp = scenario.plant_params
    lc = np.zeros(6)
    lc[L_DT] = pp.dt_s
    lc[L_RADIUS] = pp.wheel_radius_m
    lc[L_VSTOP] = pp.v_stop_m_s
    lc[L_QMAX] = pp.q_max
    lc[L_HOPELESS_M] = scenario.scoring.hopeless_factor * scenario.bound_distance_m
    lc[L_STEPS] = math.ceil(pp.t_max_s / pp.dt_s - 1e-9)
    return lc


def run(scenario: AbsWheelScenario, ts_s: float, controller: Controller,
        input_names: tuple[str, ...]) -> LoopResult:
    """Run the closed loop of `scenario` with `controller` called every ts_s (whole steps of dt).

    `input_names` (from SIGNALS) select and order the inputs handed to the controller."""
    p, tire = kernel_plant(scenario)
    lc = _loop_constants(scenario)
    pp = scenario.plant_params
    m = max(1, round(ts_s / pp.dt_s))
    x = np.array([pp.v0_m_s, pp.v0_m_s / pp.wheel_radius_m, 0.0, 0.0])
    acc = np.array([0.0, 0.0, 0.0, RUNNING, 0.0])
    rows: list[list[float]] = []
    commands: list[float] = []
    pick = [SIGNALS.index(n) for n in input_names]
    while True:
        q = x[X_Q]
        sample = [acc[A_SLIP], x[X_W], float(q >= pp.q_max), float(q <= 0.0)]
        rows.append(sample)
        u = float(controller(np.array([sample[i] for i in pick])))
        commands.append(u)
        if advance(x, acc, u, m, lc, p, tire):
            break
    data = np.array(rows)
    return LoopResult({n: data[:, i].copy() for i, n in enumerate(SIGNALS)}, np.array(commands),
                      float(acc[A_DIST]), float(acc[A_TIME]), int(acc[A_STATUS]))
