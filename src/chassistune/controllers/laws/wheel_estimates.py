"""What the literature's slip laws estimate from an ECU's measurements (docs/abs_laws.md, "Plant,
units and what a law measures"), shared by them: the wheel acceleration over the last sample,
the tire force F = (kq (q + q_prev) / 2 + I dw/dt) / R, and the pressure-rate demand r limited
to +-rate_limit (held as the actuator command u = r / K); with the laws' calibration (the
nominal I, M, kq, K and the valves' build rate, never read from the plant) as parameters per
plant family, and the same arithmetic in C.
"""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws.forms import FORM
from chassistune.controllers.specs import ParamSpec

G_M_S2 = 9.81
"""The laws' standard gravity (the wheel deceleration in g)."""

SAMPLE_PERIOD = ParamSpec(
    "ts_s",
    "s",
    0.005,
    "sample period of the law in the ideal kernels (the ECU's 5 ms clock)",
    positive=True,
)


def calibration(inertia: float, mass: float, q_max: float) -> tuple[ParamSpec, ...]:
    """The laws' calibration of a plant family: nominal wheel inertia, mass on the wheel, brake
    gain kq, pressure limit, actuator gain K, and the pressure-rate limit (q_max in 0.15 s, the
    valves' build rate, docs/ecu.md `valve_build_time_s`)."""
    return (
        ParamSpec(
            "nominal_inertia_kg_m2", "kg m^2", inertia, "the law's wheel inertia I", positive=True
        ),
        ParamSpec("nominal_mass_kg", "kg", mass, "the law's mass on the wheel M", positive=True),
        ParamSpec("nominal_brake_gain", "N m/unit", 1.0, "the law's brake gain kq", positive=True),
        ParamSpec("nominal_q_max", "unit", q_max, "the law's pressure limit q_max", positive=True),
        ParamSpec(
            "nominal_actuator_gain", "unit/s", 100.0, "the law's actuator gain K", positive=True
        ),
        ParamSpec(
            "rate_limit", "unit/s", q_max / 0.15, "largest pressure rate demanded", positive=True
        ),
    )


WHEEL_CALIBRATION = calibration(12.0, 100.0, 1500.0)
"""paper-derlsp-ao's wheel (design.md 3.1): I = 12 kg m^2, M = 100 kg, q_max = 1500."""
VEHICLE_CALIBRATION = calibration(0.6, 277.5, 2500.0)
"""The 7-DOF vehicle's wheels (design.md 3.3): J = 0.6 kg m^2, a quarter of 1110 kg,
q_max = 2500."""
CALIBRATION = tuple(p.name for p in WHEEL_CALIBRATION)

C_HELPERS = """\
/* pressure-rate demand r limited to +-rate_limit */
static double ct_rate_limit(double r, double rate_limit)
{
    if (r > rate_limit) r = rate_limit;
    if (r < -rate_limit) r = -rate_limit;
    return r;
}
"""
"""`rate_limit` in C."""

C_FORCE = """\
/* tire force estimate F = (kq (q + q_prev) / 2 + I (w - w_prev) / ts) / R */
static double ct_force_estimate(const ct_state *s, const double *in)
{
    double a = (in[CT_IN_WHEEL_SPEED_RAD_S] - in[CT_IN_WHEEL_SPEED_PREV_RAD_S]) / s->p.ts_s;
    double q_mean = 0.5 * (in[CT_IN_PRESSURE] + in[CT_IN_PRESSURE_PREV]);
    return (s->p.nominal_brake_gain * q_mean + s->p.nominal_inertia_kg_m2 * a)
           / s->p.wheel_radius_m;
}
"""
"""`force_estimate` in C (on the law's inputs and parameters by name)."""


@functools.cache
def forms() -> tuple[Any, Any]:
    """(force_estimate, rate_limit), numba functions: the tire force estimate
    F(q, q_prev, w, w_prev, ts, R, I, kq) and the limited rate demand r(r, rate_limit) of
    `C_FORCE` and `C_HELPERS`, in their operation order (a law's command is r / K)."""
    from numba import njit

    @njit(**FORM)
    def force_estimate(q, q_prev, w, w_prev, ts, radius, inertia, kq):
        a = (w - w_prev) / ts
        q_mean = 0.5 * (q + q_prev)
        return (kq * q_mean + inertia * a) / radius

    @njit(**FORM)
    def rate_limit(r, limit):
        if r > limit:
            r = limit
        if r < -limit:
            r = -limit
        return r

    return force_estimate, rate_limit


@functools.cache
def tick_force() -> Any:
    """The numba function F(sig, c, ts): `forms`' force estimate at a tick of the ideal kernels,
    from the law signals `sig` (`forms.SIGNALS`: the pressure and wheel speed now and at the last
    sample, R) and the controller vector `c` (`forms.PARAMS`: the nominal I and kq)."""
    from numba import njit

    force_estimate, _ = forms()

    @njit(**FORM)
    def at_tick(sig, c, ts):
        return force_estimate(
            sig[F.SIG_PRESSURE],
            sig[F.SIG_PRESSURE_PREV],
            sig[F.SIG_WHEEL_SPEED],
            sig[F.SIG_WHEEL_SPEED_PREV],
            ts,
            sig[F.SIG_RADIUS],
            c[F.P_INERTIA],
            c[F.P_BRAKE_GAIN],
        )

    return at_tick
