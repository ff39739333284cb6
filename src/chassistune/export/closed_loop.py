"""Closed loop of the abs-wheel plant with a sampled controller called from outside: a numba law,
or the exported C through ctypes. The test vectors are recorded here.

The plant is integrated exactly as `chassistune.sim.abs_wheel_kernel` integrates it for its sampled
laws: the kernel's own RK4 stage function at the step dt with the command u held (zero-order hold)
over each sample period ts = m dt, the same step-end update (wheel speed >= 0, pressure clipped to
[0, q_max], clipped slip) and the same stop at v_stop located inside the last step. At each sample
the controller sees the ECU inputs of an ideal sensor set: the clipped slip at the sample, the
wheel speed (rad/s) and whether the pressure sits at q_max or 0. Driving the kernel's own sampled
threshold law, this loop gives the kernel's stop distance bit for bit (tests/export); for the
continuous laws it is the sampled loop that the kernel's realistic ECU mode (issue 15) will run.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numba
import numpy as np
from numpy.typing import NDArray

from chassistune.plants.abs_wheel import AbsWheelScenario
from chassistune.sim import abs_wheel_kernel as K

Controller = Callable[[NDArray[np.float64]], float]
"""A sampled controller: the command u for one row of inputs (it keeps its own state)."""

SIGNALS = ("slip", "wheel_speed_rad_s", "pressure_at_max", "pressure_at_min")
"""What the loop offers a controller at each sample; each law picks its inputs by name."""

A_STEP, A_DIST, A_SLIP, A_STATUS, A_TIME = 0, 1, 2, 3, 4
RUNNING = -1.0


@numba.njit(cache=True, nogil=True, error_model="numpy")
def advance(x, k4, acc, u0, n, p, kind, coef, xs, ys):
    """Advance the plant n RK4 steps of dt with the command u0 held; acc keeps step, distance,
    slip, status and end time. Returns whether the run ended (stop, divergence, hopeless)."""
    dt = p[K.P_DT]
    hs = 0.5 * dt
    h6 = dt / 6.0
    r_w = p[K.P_RADIUS]
    v_stop = p[K.P_VSTOP]
    q_max = p[K.P_QMAX]
    active = np.zeros(1, dtype=np.int64)
    zero = np.zeros(1)
    u_arr = np.full(1, u0)
    u_tmp = np.zeros(1)
    k1 = np.zeros_like(x)
    k2 = np.zeros_like(x)
    k3 = np.zeros_like(x)
    n_steps = math.ceil(p[K.P_TMAX] / dt - 1e-9)
    for _ in range(n):
        k = int(acc[A_STEP])
        if k >= n_steps:
            acc[A_STATUS] = K.STATUS_TIMEOUT
            acc[A_TIME] = n_steps * dt
            return True
        t = k * dt
        K._stage(1, active, x, k4, 0.0, k1, u_tmp, u_arr, zero, zero, zero, p, kind, coef, xs, ys)
        K._stage(1, active, x, k1, hs, k2, u_tmp, u_arr, zero, zero, zero, p, kind, coef, xs, ys)
        K._stage(1, active, x, k2, hs, k3, u_tmp, u_arr, zero, zero, zero, p, kind, coef, xs, ys)
        K._stage(1, active, x, k3, dt, k4, u_tmp, u_arr, zero, zero, zero, p, kind, coef, xs, ys)
        new = np.empty(K.N_STATE)
        for s in range(K.N_STATE):
            new[s] = x[s, 0] + h6 * (k1[s, 0] + 2.0 * k2[s, 0] + 2.0 * k3[s, 0] + k4[s, 0])
        vi = x[K.S_V, 0]
        vn = new[K.S_V]
        new[K.S_W] = max(new[K.S_W], 0.0)
        new[K.S_Q] = min(max(new[K.S_Q], 0.0), q_max)
        s_new = min(max((vn - new[K.S_W] * r_w) / vn, 0.0), 1.0)
        stop = vn <= v_stop
        frac = (vi - v_stop) / (vi - vn) if stop else 1.0
        h = frac * dt
        acc[A_DIST] += 0.5 * h * (vi + (v_stop if stop else vn))
        x[:, 0] = new
        acc[A_SLIP] = s_new
        acc[A_STEP] = k + 1
        check = vn + new[K.S_W] + new[K.S_R]
        if check - check != 0.0:
            acc[A_STATUS] = K.STATUS_DIVERGED
            acc[A_TIME] = t
            return True
        if stop:
            acc[A_STATUS] = K.STATUS_STOPPED
            acc[A_TIME] = t + h
            return True
        if acc[A_DIST] > p[K.P_HOPELESS_M]:
            acc[A_STATUS] = K.STATUS_HOPELESS
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
    status: int  # abs_wheel_kernel.STATUS_*

    def inputs(self, names: tuple[str, ...]) -> NDArray[np.float64]:
        """The input rows (samples, len(names)) of a law."""
        return np.column_stack([self.signals[n] for n in names])


def run(scenario: AbsWheelScenario, ts_s: float, controller: Controller,
        input_names: tuple[str, ...]) -> LoopResult:
    """Run the closed loop of `scenario` with `controller` called every ts_s (whole steps of dt).

    `input_names` (from SIGNALS) select and order the inputs handed to the controller."""
    p, kind, coef, xs, ys, _, _, _ = scenario._kernel_args
    dt = scenario.plant_params.dt_s
    m = max(1, round(ts_s / dt))
    x = np.zeros((K.N_STATE, 1))
    x[K.S_V, 0] = p[K.P_V0]
    x[K.S_W, 0] = p[K.P_V0] / p[K.P_RADIUS]
    x[K.S_XF, 0] = p[K.P_TARGET]
    k4 = np.zeros_like(x)
    acc = np.array([0.0, 0.0, 0.0, RUNNING, 0.0])
    rows: list[list[float]] = []
    commands: list[float] = []
    pick = [SIGNALS.index(n) for n in input_names]
    while True:
        q = x[K.S_Q, 0]
        sample = [acc[A_SLIP], x[K.S_W, 0], float(q >= p[K.P_QMAX]), float(q <= 0.0)]
        rows.append(sample)
        u = float(controller(np.array([sample[i] for i in pick])))
        commands.append(u)
        if advance(x, k4, acc, u, m, p, kind, coef, xs, ys):
            break
    data = np.array(rows)
    return LoopResult({n: data[:, i].copy() for i, n in enumerate(SIGNALS)}, np.array(commands),
                      float(acc[A_DIST]), float(acc[A_TIME]), int(acc[A_STATUS]))
