"""The arguments of a law's kernel forms (`Law.forms`: start, tick), declared by name.

A kernel hands a sampled law its signals at a sample instant as the tuple `sig` (`SIGNALS`),
the held values of the continuous PID as `held` (`HELD`: the command u0 the sampled laws hold
and the gains kp, ki, kd it integrates with), the law's memory `mem` (`registry.slots("memory")`
floats, zero at the start), its gain row `g` with the first column `g0` of its gains (a vehicle with
per-axle gains reads the rear wheels' from column g0 = n_gains), and the controller vector `c`
(`PARAMS`). A law reads each by name: `sig[SIG_SLIP_ERROR]`, `c[P_AMPLITUDE]`,
`g[g0 + gains(SPEC)["kp"]]`. A law's continuous form (`registry.ContinuousForm`) reads its
state `x` by the names it declares and the held values by `HELD`.
"""

from __future__ import annotations

from typing import Any

from chassistune.controllers.specs import ControllerSpec
from chassistune.layout import Layout, Slot

FORM: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy", "inline": "always"}
"""numba options of a law's kernel forms (inlined into the kernels)."""

SIGNALS = Layout(
    "law signals",
    (
        Slot("slip_error", "-", "e = S_target - S of the law's channel"),
        Slot("slip", "-", "the channel's wheel slip S"),
        Slot("target_slip", "-", "the channel's target slip S_target"),
        Slot("wheel_speed_rad_s", "rad/s", "the channel's wheel speed w"),
        Slot("wheel_speed_prev_rad_s", "rad/s", "w at the last sample instant"),
        Slot("wheel_radius_m", "m", "R"),
        Slot("slip_error_rate", "1/s", "filtered de/dt = N (e - xf) of the PID's filter state"),
        Slot("reference_speed_m_s", "m/s", "the speed the slip is taken against (the plant's)"),
        Slot("pressure", "unit", "the channel's brake pressure q (the plant's)"),
        Slot("pressure_prev", "unit", "q at the last sample instant"),
        Slot("time_s", "s", "t_k, the time of the sample instant"),
    ),
)
(
    SIG_SLIP_ERROR,
    SIG_SLIP,
    SIG_TARGET,
    SIG_WHEEL_SPEED,
    SIG_WHEEL_SPEED_PREV,
    SIG_RADIUS,
    SIG_ERROR_RATE,
    SIG_SPEED,
    SIG_PRESSURE,
    SIG_PRESSURE_PREV,
    SIG_TIME,
) = range(len(SIGNALS))

ECU_SIGNALS = Layout(
    "ecu law signals",
    (
        Slot("slip", "-", "the ECU's slip (vref - w R) / vref in [0, 1]"),
        Slot("wheel_speed_rad_s", "rad/s", "the wheel speed as the sensor reads it"),
        Slot("pressure_at_max", "-", "1 while the brake pressure sits at q_max, else 0"),
        Slot("pressure_at_min", "-", "1 while the brake pressure is 0, else 0"),
        Slot("target_slip", "-", "the target slip S_target"),
        Slot("amplitude", "-", "command magnitude of the switching laws"),
        Slot("reference_speed_m_s", "m/s", "the ECU's reference speed estimate vref"),
        Slot("pressure", "unit", "the brake pressure of the valve model"),
        Slot("pressure_prev", "unit", "the pressure at the last tick"),
        Slot("wheel_speed_prev_rad_s", "rad/s", "the wheel speed read at the last tick"),
        Slot("time_s", "s", "t_k, the time of the tick"),
    ),
)
"""The signals the ECU kernel hands a law's `EcuForm` at a tick, in this order (`sig`); the
law's inputs are the ones it names (`Law.ecu_inputs`)."""

HELD = Layout(
    "held values of the continuous law",
    (
        Slot("u0", "-", "command held between samples, added to the PID's output"),
        Slot("kp", "1/(slip)", "proportional gain of the continuous PID"),
        Slot("ki", "1/(slip s)", "integral gain of the continuous PID"),
        Slot("kd", "s/(slip)", "derivative gain of the continuous PID"),
    ),
)
H_U0, H_KP, H_KI, H_KD = range(len(HELD))

PARAMS = Layout(
    "abs controller",
    (
        Slot("ts_s", "s", "sample period of the sampled laws"),
        Slot("amplitude", "-", "command magnitude of the switching laws"),
        Slot("decel_threshold_m_s2", "m/s^2", "threshold ABS: -a"),
        Slot("accel_threshold_m_s2", "m/s^2", "threshold ABS: +a"),
        Slot("slip_margin", "-", "threshold ABS: dump above target + margin"),
        Slot("slow_fraction", "-", "threshold ABS: slow build rate / amplitude"),
        Slot("pressure_tau_s", "s", "sliding mode: time constant of the pressure loop"),
        Slot("nominal_inertia_kg_m2", "kg m^2", "the literature laws' wheel inertia I"),
        Slot("nominal_mass_kg", "kg", "the literature laws' mass on the wheel M"),
        Slot("nominal_brake_gain", "N m/unit", "the literature laws' brake gain kq"),
        Slot("nominal_q_max", "unit", "the literature laws' pressure limit"),
        Slot("nominal_actuator_gain", "unit/s", "the literature laws' actuator gain K"),
        Slot("rate_limit", "unit/s", "the literature laws' largest pressure rate"),
        Slot("horizon", "samples", "model-predictive law: samples predicted, 1 .. 5"),
    ),
)
"""The controller vector `c` of the ideal kernels: the laws' fixed numeric parameters."""
P_TS, P_AMPLITUDE, P_DECEL, P_ACCEL, P_SLIP_MARGIN, P_SLOW = (
    PARAMS[n]
    for n in (
        "ts_s",
        "amplitude",
        "decel_threshold_m_s2",
        "accel_threshold_m_s2",
        "slip_margin",
        "slow_fraction",
    )
)
P_PRESSURE_TAU, P_INERTIA, P_MASS, P_BRAKE_GAIN, P_QMAX, P_ACTUATOR_GAIN, P_RATE_LIMIT = (
    PARAMS[n]
    for n in (
        "pressure_tau_s",
        "nominal_inertia_kg_m2",
        "nominal_mass_kg",
        "nominal_brake_gain",
        "nominal_q_max",
        "nominal_actuator_gain",
        "rate_limit",
    )
)
P_HORIZON = PARAMS["horizon"]


def gains(spec: ControllerSpec) -> Layout:
    """The gain columns of a law's spec, by name (registry order)."""
    return Layout(
        f"{spec.plant} {spec.name} gains", tuple(Slot(g.name, g.unit) for g in spec.gains)
    )
