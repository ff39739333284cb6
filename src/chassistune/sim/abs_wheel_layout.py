"""Declared inputs and outputs of the single-wheel ABS kernel (`sim.abs_wheel_kernel`).

Every slot of the plant vector, the controller vector, the metrics row and the trace row is
declared here once, with its unit; the kernel takes its integer slot constants from these layouts
and the scenario packs and decodes through them (`pack_plant`, `pack_controller`,
`decode_metrics`, `decode_trace`). A new metric or trace signal: one `Slot` line here plus the
kernel line that writes it.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from chassistune.controllers.laws.forms import PARAMS
from chassistune.layout import Layout, Slot

PLANT = Layout(
    "abs-wheel plant",
    (
        Slot("mass_kg", "kg", "vehicle mass on the wheel M"),
        Slot("wheel_inertia_kg_m2", "kg m^2", "wheel inertia I"),
        Slot("wheel_radius_m", "m", "wheel radius R"),
        Slot("v0_m_s", "m/s", "initial speed"),
        Slot("g_m_s2", "m/s^2", "gravity"),
        Slot("actuator_gain", "preset unit/s", "K of the brake actuator K/(s(Ts+1))"),
        Slot("actuator_tau_s", "s", "T of the brake actuator"),
        Slot("brake_gain", "N m/preset unit", "kq: brake torque per unit pressure"),
        Slot("q_max", "preset unit", "pressure limit"),
        Slot("v_stop_m_s", "m/s", "the run ends below this speed"),
        Slot("t_max_s", "s", "the run times out after this"),
        Slot("dt_s", "s", "integration step"),
        Slot("load_fraction", "-", "wheel load as a fraction of M g"),
        Slot("target_slip", "-", "slip set point"),
        Slot("hopeless_distance_m", "m", "the run ends as hopeless beyond this distance"),
        Slot("lock_ratio", "-", "the wheel counts as locked while w R < lock_ratio v"),
        Slot("n_filter", "rad/s", "derivative filter coefficient N of the PID laws"),
        Slot(
            "relaxation_length_m",
            "m",
            "sigma of the lagged longitudinal slip (0: the tire reads the kinematic slip)",
        ),
    ),
)

CONTROLLER = PARAMS
"""The controller vector: the laws' fixed numeric parameters (`controllers.laws.forms`)."""

STATUS_NAMES = ("stopped", "hopeless", "timeout", "diverged")
"""How a run ended: the code in the metrics' `status` column indexes this tuple."""

METRICS = Layout(
    "abs-wheel metrics",
    (
        Slot("status", "-", "index into STATUS_NAMES"),
        Slot("stop_time_s", "s", "time at v_stop (or at the end of the run)"),
        Slot("stop_distance_m", "m", "distance travelled"),
        Slot("wheel_lock_time_s", "s", "first time the wheel counts as locked (NaN: never)"),
        Slot("slip_iae", "s", "integral of |S_target - S|"),
        Slot("slip_itae", "s^2", "integral of t |S_target - S|"),
        Slot("slip_ise", "s", "integral of (S_target - S)^2"),
        Slot("mean_slip", "-", "time average of the slip"),
        Slot("peak_slip", "-", "largest slip"),
        Slot("locked_time_s", "s", "time spent locked"),
        Slot("slip_clip_max", "-", "largest clipping of the slip into [0, 1] (a physics check)"),
        Slot("trace_rows", "-", "rows written to the trace"),
        Slot("min_slip_unclipped", "-", "smallest slip before clipping (a physics check)"),
    ),
)

TRACE = Layout(
    "abs-wheel trace",
    (
        Slot("time_s", "s"),
        Slot("vehicle_speed_m_s", "m/s"),
        Slot("wheel_speed_m_s", "m/s"),
        Slot("slip", "-"),
        Slot("target_slip", "-"),
        Slot("pressure", "preset unit"),
        Slot("brake_torque_n_m", "N m"),
        Slot("command", "-"),
        Slot("distance_m", "m"),
        Slot("mu", "-"),
    ),
)

RUN_METRICS = tuple(n for n in METRICS.names if n not in ("status", "trace_rows"))
"""The metrics a run reports (status is decoded to its name, trace_rows is bookkeeping)."""


def pack_plant(values: Mapping[str, float]) -> np.ndarray:
    """The kernel's plant vector from every PLANT slot by name."""
    return PLANT.pack(values)


def pack_controller(values: Mapping[str, float]) -> np.ndarray:
    """The kernel's controller vector by name; slots the controller does not use are 0."""
    return CONTROLLER.pack({n: float(values.get(n, 0.0)) for n in CONTROLLER.names})


def decode_metrics(raw: np.ndarray) -> dict[str, np.ndarray]:
    """The run metrics by name, `stopped` and `status` (names) from the kernel's rows."""
    out = METRICS.decode(raw, RUN_METRICS)
    status = raw[:, METRICS["status"]].astype(int)
    out["stopped"] = status == STATUS_NAMES.index("stopped")
    out["status"] = np.array(STATUS_NAMES)[status]
    return out


def decode_trace(trace: np.ndarray, metrics_row: np.ndarray) -> dict[str, np.ndarray]:
    """The trace signals by name (the rows the kernel wrote)."""
    return TRACE.decode(trace[: int(metrics_row[METRICS["trace_rows"]])])
