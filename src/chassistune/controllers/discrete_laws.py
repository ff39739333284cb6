"""The discrete laws' declarations: names and order of each law's inputs, parameters and state
entries (the numba forms are in `controllers.discrete`; this module imports no numba, so that the
law modules declaring them stay light to import). A law's kind is its registry's
(`controllers.laws.kind`)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class DiscreteLaw:
    """Names of a discrete law's inputs, parameters and state entries (vector order)."""

    controller: str
    inputs: tuple[str, ...]
    params: tuple[str, ...]
    state: tuple[str, ...]
    table_outputs: int  # outputs read from the rule base's lookup table (0: no table)
    form: str  # the discrete form, named


_PID_INPUTS = ("slip", "pressure_at_max", "pressure_at_min")
LAWS: dict[str, DiscreteLaw] = {
    "pid": DiscreteLaw(
        "pid",
        _PID_INPUTS,
        ("kp", "ki", "kd", "n_filter", "target_slip", "ts_s"),
        ("started", "integral", "filter"),
        0,
        "parallel PID, forward-Euler integrator, backward-Euler derivative filter",
    ),
    "fuzzy-pid": DiscreteLaw(
        "fuzzy-pid",
        _PID_INPUTS,
        (
            "ke",
            "kec",
            "ku_p",
            "ku_i",
            "ku_d",
            "kp0",
            "ki0",
            "kd0",
            "n_filter",
            "target_slip",
            "ts_s",
        ),
        ("started", "integral", "filter"),
        3,
        "parallel PID with table-scheduled gains, forward-Euler integrator, backward-Euler "
        "derivative filter",
    ),
    "fuzzy-immune-pid": DiscreteLaw(
        "fuzzy-immune-pid",
        ("slip",),
        ("k_immune", "eta", "ki", "kd", "ke", "kec", "target_slip", "ts_s"),
        ("started", "u_prev", "e_prev", "e_prev2"),
        1,
        "incremental (velocity) PID with table-scheduled proportional gain",
    ),
    "threshold": DiscreteLaw(
        "threshold",
        ("slip", "wheel_speed_rad_s"),
        (
            "amplitude",
            "decel_threshold_m_s2",
            "accel_threshold_m_s2",
            "slip_margin",
            "slow_fraction",
            "target_slip",
            "ts_s",
            "wheel_radius_m",
        ),
        ("started", "phase", "wheel_speed_prev", "wheel_accel"),
        0,
        "sampled phase machine (build, hold, dump, recover, slow build)",
    ),
}
