"""Declared inputs and outputs of the ECU-realistic single-wheel ABS kernel
(`sim.abs_wheel_ecu_kernel`), extending the ideal kernel's layouts
(`sim.abs_wheel_layout`): the ECU vector, and metrics and trace rows that start with every slot
of the ideal kernel's (same columns, so the scenario scores both modes alike) and add the ECU's.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from chassistune.layout import Layout, Slot
from chassistune.sim import abs_wheel_layout as KL

ECU = Layout(
    "abs-wheel ecu",
    (
        Slot("law", "-", "the law's kind (`controllers.laws.kind`)"),
        Slot("steps_per_tick", "-", "ecu_ts_s / dt_s (a whole number)"),
        Slot("delay_samples", "samples", "computation delay"),
        Slot("toothed", "-", "1: toothed-wheel sensor, 0: the true wheel speed"),
        Slot("teeth", "teeth", "tone-wheel teeth"),
        Slot("timer_s", "s", "edge capture timer resolution"),
        Slot("stale_bound", "-", "1: cap a stale estimate by pitch / age, 0: hold it"),
        Slot("vref_mode", "-", "0 true, 1 slew-limited, 2 accelerometer"),
        Slot("vref_decel_max_m_s2", "m/s^2", "a_max of the slew-limited reference"),
        Slot("accel_bias_m_s2", "m/s^2", "accelerometer bias"),
        Slot("vref_agree_m_s", "m/s", "re-anchor when the wheel agrees within this"),
        Slot("free_pressure", "preset unit", "a brake at most this pressure counts as released"),
        Slot("vref_agree_m_s2", "m/s^2", "re-anchor only when the wheel's acceleration agrees"),
        Slot("anchor_samples", "samples", "re-anchor only after this many agreeing samples"),
        Slot("three_state", "-", "1: build/hold/dump valves, 0: the continuous actuator"),
        Slot("kb", "preset unit^0.5/s", "orifice gain of the inlet"),
        Slot("kd", "preset unit^0.5/s", "orifice gain of the outlet"),
        Slot("dead_time_s", "s", "valve dead time"),
        Slot("min_on_s", "s", "valve minimum on-time"),
        Slot("cutout_m_s", "m/s", "ABS off below this reference speed (latched)"),
        Slot("scheduled", "-", "1: kp, kd scaled by max(vref / v0, floor)"),
        Slot("schedule_floor", "-", "smallest schedule factor"),
        Slot("amplitude", "-", "command of the switching laws and the driver's demand"),
    ),
)

METRICS = Layout(
    "abs-wheel ecu metrics",
    (
        *KL.METRICS.slots,
        Slot("ecu_slip_iae", "s", "integral of |S_target - S_ecu| (the slip the ECU computed)"),
        Slot("cutout_time_s", "s", "time of the low-speed cut-out (NaN: never)"),
        Slot("valve_switches", "-", "valve state changes"),
        Slot("valve_min_interval_s", "s", "shortest time between two valve state changes"),
        Slot("vref_gap_max_m_s", "m/s", "largest |v - vref| at the ticks before the cut-out"),
        Slot("pressure_min", "preset unit", "lowest brake pressure"),
        Slot("pressure_max", "preset unit", "highest brake pressure"),
        Slot(
            "low_speed_slip_error",
            "-",
            "largest |S_target - S| (true slip) at step ends with 1 < v < 9 m/s, before cut-out",
        ),
    ),
)

TRACE = Layout(
    "abs-wheel ecu trace",
    (
        *KL.TRACE.slots,
        Slot("vref_m_s", "m/s"),
        Slot("wheel_speed_est_m_s", "m/s"),
        Slot("ecu_slip", "-"),
        Slot("valve_mode", "-"),
        Slot(
            "edge_prev_s",
            "s",
            "captured time of the edge before the last, as read at the latest "
            "tick (-1: none yet; toothed sensor)",
        ),
        Slot("edge_last_s", "s", "captured time of the last edge, as read at the latest tick"),
    ),
)


def pack_ecu(values: Mapping[str, float]) -> np.ndarray:
    """The kernel's ECU vector from every ECU slot by name."""
    return ECU.pack(values)


def decode_metrics(raw: np.ndarray) -> dict[str, np.ndarray]:
    """The run metrics by name (the ideal kernel's, decoded alike, plus the ECU's)."""
    out = KL.decode_metrics(raw[:, : len(KL.METRICS)])
    out.update(METRICS.decode(raw, METRICS.names[len(KL.METRICS) :]))
    return out


def decode_trace(trace: np.ndarray, metrics_row: np.ndarray) -> dict[str, np.ndarray]:
    """The trace signals by name (the rows the kernel wrote)."""
    return TRACE.decode(trace[: int(metrics_row[METRICS["trace_rows"]])])


LANE = Layout(
    "abs-wheel ecu lane rows",
    (
        # plant state at the lane's step
        Slot("v_m_s", "m/s", "vehicle speed"),
        Slot("w_rad_s", "rad/s", "wheel speed"),
        Slot("q", "preset unit", "brake pressure"),
        Slot("r", "preset unit/s", "actuator rate (continuous actuator)"),
        Slot("theta_rad", "rad", "wheel angle (toothed sensor)"),
        Slot("slip", "-", "true slip at the last step end (0 at the start: the metrics')"),
        Slot("state_slip", "-", "slip of (v, w) now: `wheel_slip`, the last step's s_new"),
        Slot("step", "-", "steps done (t = step dt)"),
        Slot("tick", "-", "ECU ticks done"),
        # the last step's start and end facts
        Slot("v_start_m_s", "m/s", "vehicle speed at the start of the last step"),
        Slot("theta_start_rad", "rad", "wheel angle at the start of the last step"),
        Slot("w_start_rad_s", "rad/s", "wheel speed at the start of the last step"),
        Slot("h_s", "s", "length of the last step (up to v_stop)"),
        Slot("stopped", "-", "1 if the last step crossed v_stop"),
        Slot("status", "-", "end status (STATUS_NAMES) once ended"),
        Slot("t_end_s", "s", "end time once ended"),
        Slot("ended", "-", "1 once the run ended"),
        # toothed sensor
        Slot("edge_next", "-", "index of the next edge"),
        Slot("edge_next_rad", "rad", "wheel angle of the next edge"),
        Slot("edge_last_s", "s", "captured time of the last edge (-1: none)"),
        Slot("edge_prev_s", "s", "captured time of the edge before (-1: none)"),
        Slot("w_est_rad_s", "rad/s", "speed estimate from the last edge period"),
        Slot("read_last_s", "s", "edge_last_s as read at the latest tick"),
        Slot("read_prev_s", "s", "edge_prev_s as read at the latest tick"),
        # reference speed, ECU slip, cut-out, command
        Slot("vref_m_s", "m/s", "reference speed"),
        Slot("vw_prev_m_s", "m/s", "wheel speed read at the tick before"),
        Slot("vw_m_s", "m/s", "wheel speed read at the latest tick"),
        Slot("anchor_held", "samples", "agreeing samples in a row (accelerometer reference)"),
        Slot("ecu_slip", "-", "slip the ECU computed at the latest tick"),
        Slot("cut", "-", "1 once cut out"),
        Slot("u0", "-", "held command of the continuous actuator"),
        Slot("cmd", "-", "command after the delay line and the cut-out"),
        Slot("residual", "preset unit", "sigma-delta residual of the duty pulses"),
        Slot("w_read_prev_rad_s", "rad/s", "wheel speed read at the tick before (the law's)"),
        Slot("pressure_prev", "preset unit", "brake pressure at the tick before (the law's)"),
        # valve pulses (previous and current) and their accounting
        Slot("pulse0_mode", "-", "previous pulse: valve state"),
        Slot("pulse0_start_s", "s", "previous pulse: start"),
        Slot("pulse0_on_s", "s", "previous pulse: on-time"),
        Slot("pulse1_mode", "-", "current pulse: valve state"),
        Slot("pulse1_start_s", "s", "current pulse: start"),
        Slot("pulse1_on_s", "s", "current pulse: on-time"),
        Slot("q_switch", "-", "1 if a valve switches inside the step (three-state valves)"),
        Slot("q_half", "preset unit", "pressure at t + dt/2 of a step with a switch"),
        Slot("q_full", "preset unit", "pressure at t + dt of a step with a switch"),
        Slot("valve", "-", "valve state last accounted"),
        Slot("valve_change_s", "s", "time of the last valve state change (NaN: none)"),
        # metrics
        Slot("distance_m", "m"),
        Slot("iae", "s"),
        Slot("itae", "s^2"),
        Slot("ise", "s"),
        Slot("slip_integral", "s"),
        *(METRICS.slots[METRICS[n]] for n in METRICS.names[len(KL.METRICS) :]),
        Slot("clip_max", "-"),
        Slot("min_slip", "-"),
        Slot("peak_slip", "-"),
        Slot("locked_s", "s"),
        Slot("lock_time_s", "s", "NaN: never"),
        # the lane's plant row
        Slot("wheel_radius_m", "m"),
        Slot("wheel_load_n", "N"),
        Slot("inv_mass", "1/kg"),
        Slot("inv_inertia", "1/(kg m^2)"),
        Slot("brake_gain", "N m/preset unit"),
        Slot("actuator_gain", "preset unit/s"),
        Slot("inv_tau", "1/s"),
        Slot("q_max", "preset unit"),
        Slot("v0_m_s", "m/s"),
        Slot("v_stop_m_s", "m/s"),
        Slot("target_slip", "-"),
        Slot("lock_ratio", "-"),
        Slot("hopeless_distance_m", "m"),
        # transient slip (docs/tires.md)
        Slot("lagged_slip", "-", "the slip the tire reads, S' (relaxation length > 0)"),
        Slot("relaxation_length_m", "m", "0: the tire reads the slip itself"),
    ),
)
"""Rows of the realistic kernel's lane array: row r of lane l at r * LANES + l."""
