"""The units a metric is shown in (text tables, plot tables, report tables).

The JSON keys and values stay as DESIGN 7 has them (SI; scripts read `body_acc_rms` in m/s^2 and
`susp_travel_rms` in m); what a person reads states its unit, and the quarter car's travel and
tire deflection, millimetres in size, are shown in mm. A metric's unit comes from its name's
suffix (`_m`, `_s`, `_m_s2`, ...) or, for names without one, from METRIC_UNITS; `passive_x`
has the unit of `x`. Light: no numpy.
"""

from __future__ import annotations

METRIC_UNITS: dict[str, str] = {
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
}
"""SI unit of each metric whose name does not end in one."""

SUFFIXES = (
    ("_m_s2", "m/s^2"),
    ("_m_s", "m/s"),
    ("_n_m", "N m"),
    ("_per_s", "1/s"),
    ("_kg", "kg"),
    ("_m", "m"),
    ("_s", "s"),
    ("_n", "N"),
)
"""Name suffix -> SI unit, longest first."""

IN_MM = frozenset({"susp_travel_rms", "tire_defl_rms", "travel_3sigma_m"})
"""Lengths shown in millimetres (their values are a few mm)."""


def si_unit(name: str) -> str:
    """The SI unit of metric `name` ('' when unknown, '-' when dimensionless)."""
    name = name.removeprefix("passive_")
    if name in METRIC_UNITS:
        return METRIC_UNITS[name]
    return next((unit for suffix, unit in SUFFIXES if name.endswith(suffix)), "")


def shown_unit(name: str) -> tuple[str, float]:
    """(unit, factor): metric `name` is shown as value * factor in unit (mm for IN_MM)."""
    if name.removeprefix("passive_") in IN_MM:
        return "mm", 1e3
    return si_unit(name), 1.0
