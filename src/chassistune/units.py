"""The unit of a name: every metric, trace signal and parameter (text tables, CSV headings, plots,
`list params`), read from one table of name suffixes.

The JSON keys and values stay as design.md 7 has them (SI; scripts read `body_acc_rms` in m/s^2 and
`susp_travel_rms` in m); what a person reads states its unit. A name's unit is that of the longest
suffix of SUFFIXES it ends in (`_rad_s` is rad/s, not s), else NAMES' entry for the whole name;
`passive_x` has the unit of `x`, `x_fl` (a wheel's) that of `x`. The ABS brake pressure has the
preset's unit (PRESSURE, replaced by `with_pressure`). The quarter car's RMS travel and tire
deflection, millimetres in size and named without a unit, are shown in mm. Light: no numpy.
"""

from __future__ import annotations

PRESSURE = "preset unit"
"""The unit of the ABS brake pressure before the preset names it (`with_pressure`)."""

SUFFIXES: dict[str, str] = {
    "_m_s2": "m/s^2",
    "_rad_s2": "rad/s^2",
    "_rad_s": "rad/s",
    "_m_s": "m/s",
    "_n_s_m": "N s/m",
    "spring_n_m": "N/m",
    "stiffness_n_m": "N/m",
    "_n_m": "N m",
    "_kg_m2": "kg m^2",
    "_cycles_per_m": "1/m",
    "_per_s": "1/s",
    "_m3": "m^3",
    "_kg": "kg",
    "_hz": "Hz",
    "_deg": "deg",
    "_rad": "rad",
    "_m": "m",
    "_s": "s",
    "_n": "N",
}
"""Name suffix -> unit (SI; N m a torque, N/m a stiffness). The longest matching suffix wins."""

NAMES: dict[str, str] = {
    "body_acc_rms": "m/s^2",
    "susp_travel_rms": "m",
    "tire_defl_rms": "m",
    "force_rms": "N",
    "objective": "-",
    "objective_exact": "-",
    "damping_ratio": "-",
    "dynamic_tire_load_ratio": "-",
    "distance_ratio": "-",
    "mean_slip": "-",
    "peak_slip": "-",
    "slip_iae": "s",
    "slip_ise": "s",
    "slip_itae": "s^2",
    "ecu_slip_iae": "s",
    "slip_clip_max": "-",
    "r13h_epsilon": "-",
    "r13h_z_al": "-",
    "r13h_k_adhesion": "-",
    "min_slip_unclipped": "-",
    "pressure_min": PRESSURE,
    "pressure_max": PRESSURE,
    "pressure": PRESSURE,
    "q_max": PRESSURE,
    "status": "-",
    "stopped": "-",
    "spun": "-",
    "stable": "-",
    "diverged": "-",
    "trace_rows": "-",
    "n_trace": "-",
    "low_speed_slip_error": "-",
    "load_iterations_max": "-",
    "surface": "-",
    "valve_switches": "-",
    "slip": "-",
    "target_slip": "-",
    "ecu_slip": "-",
    "command": "-",
    "mu": "-",
    "valve_mode": "-",
    "body_acc": "m/s^2",
    "susp_travel": "m",
    "tire_defl": "m",
    "force": "N",
    "road": "m",
    "body_disp": "m",
}
"""Unit of each name that does not end in a suffix of SUFFIXES ('-': dimensionless)."""

WHEELS = ("_fl", "_fr", "_rl", "_rr")
"""A wheel's name ends a per-wheel quantity's name (`slip_fl`) or comes before its unit
(`wheel_speed_fl_m_s`): the quantity's unit is that of the name without it."""

IN_MM = frozenset({"susp_travel_rms", "tire_defl_rms"})
"""Lengths shown in millimetres (their values are a few mm; their names state no unit)."""

_BY_LENGTH = sorted(SUFFIXES.items(), key=lambda item: -len(item[0]))


def si_unit(name: str) -> str:
    """The SI unit of `name` ('' when unknown, '-' when dimensionless)."""
    name = name.removeprefix("passive_")
    if name.endswith(WHEELS):
        name = name[:-3]
    if name in NAMES:
        return NAMES[name]
    return next((unit for suffix, unit in _BY_LENGTH if name.endswith(suffix)), "")


def with_pressure(unit: str, pressure_unit: str) -> str:
    """`unit` with the preset's pressure unit in place of PRESSURE (`N m/kPa`)."""
    return unit.replace(PRESSURE, pressure_unit) if pressure_unit else unit


def shown_unit(name: str) -> tuple[str, float]:
    """(unit, factor): `name`'s value is shown as value * factor in unit (mm for IN_MM)."""
    if name.removeprefix("passive_") in IN_MM:
        return "mm", 1e3
    return si_unit(name), 1.0
