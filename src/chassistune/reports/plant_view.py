"""How the reports present each plant beyond its PlantSpec (whose `key_metrics` the tables
read): its baseline controller, the signals of its response overlays and the metrics of its
generalization matrices (lower-is-better). `plant_view` is the one place the reports ask for them.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Panel:
    """One panel of a response overlay: a trace signal, its axis label, and the baseline's
    signal (the same trace's `passive_*` copy, or the signal of the baseline's own trace)."""

    signal: str
    label: str
    baseline_signal: str = ""


@dataclass(frozen=True)
class PlantView:
    """How the reports present one plant."""

    baseline: str
    baseline_label: str
    panels: tuple[Panel, ...]
    generalization_metrics: tuple[tuple[str, str], ...]
    window_s: float | None = None


_VIEWS: dict[str, PlantView] = {
    "abs-wheel": PlantView(
        baseline="none",
        baseline_label="no ABS",
        panels=(
            Panel("slip", "slip S [-]"),
            Panel("vehicle_speed_m_s", "vehicle speed v [m/s]"),
            Panel("brake_torque_n_m", "brake torque [N m]"),
            Panel("distance_m", "distance [m]"),
        ),
        generalization_metrics=(
            ("distance_ratio", "stop distance / bound"),
            ("locked_time_s", "locked time [s]"),
        ),
    ),
    "quarter-car": PlantView(
        baseline="passive",
        baseline_label="passive",
        panels=(
            Panel("body_acc_m_s2", "body acceleration [m/s^2]", "passive_body_acc_m_s2"),
            Panel("susp_travel_m", "suspension travel [m]", "passive_susp_travel_m"),
            Panel("tire_defl_m", "tire deflection [m]", "passive_tire_defl_m"),
        ),
        generalization_metrics=(
            ("body_acc_rms", "body acc. RMS [m/s^2]"),
            ("susp_travel_rms", "travel RMS [m]"),
        ),
        window_s=5.0,
    ),
}

_NONE = PlantView("", "", (), ())


def plant_view(plant: str) -> PlantView:
    """The report's view of `plant` (an empty view for a plant it does not know)."""
    return _VIEWS.get(plant, _NONE)
