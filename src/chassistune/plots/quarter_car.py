"""Quarter-car figures: time histories and frequency response, passive vs active."""

from __future__ import annotations

from typing import Any

import numpy as np

from chassistune.plots.style import pyplot, save
from chassistune.scenarios.base import Trace
from chassistune.units import shown_unit

WINDOW_S = 5.0
"""Time histories show at most the first WINDOW_S seconds (the RMS values use the whole run)."""

_SERIES = (
    ("body_acc_m_s2", "passive_body_acc_m_s2", "body acceleration", "body_acc_rms"),
    ("susp_travel_m", "passive_susp_travel_m", "suspension travel", "susp_travel_rms"),
    ("tire_defl_m", "passive_tire_defl_m", "tire deflection", "tire_defl_rms"),
)
"""(signal, passive signal, label, its RMS metric): each drawn in its metric's shown unit (mm
for travel and tire deflection, `units.shown_unit`)."""


def plot_trace(scenario: Any, trace: Trace, path: str) -> None:
    """Road, body acceleration, travel and tire deflection (passive vs active, first 5 s),
    |body acceleration / road velocity| against frequency, and the RMS comparison table."""
    plt = pyplot()
    fig, axes = plt.subplots(3, 2, figsize=(11, 9))
    sig, m = trace.signals, trace.metrics
    t = sig["time_s"]
    shown = t <= WINDOW_S
    label = scenario.controller.name
    ax_road, ax_acc, ax_trav, ax_tire, ax_freq, ax_tab = axes.ravel()

    ax_road.plot(t[shown], sig["road_m"][shown] * 1e3, color="0.3", lw=0.8)
    ax_road.set_ylabel("road profile z0 [mm]")
    ax_road.set_title(
        f"{scenario.road} at {scenario.road_params.speed_m_s:g} m/s, seed {scenario.seed}"
    )
    for ax, (active, passive, ylabel, metric) in zip(
        (ax_acc, ax_trav, ax_tire), _SERIES, strict=True
    ):
        unit, factor = shown_unit(metric)
        ax.plot(t[shown], sig[passive][shown] * factor, color="0.55", lw=0.8, label="passive")
        ax.plot(t[shown], sig[active][shown] * factor, color="C0", lw=0.8, label=label)
        ax.set_ylabel(f"{ylabel} [{unit}]")
        ax.legend(loc="upper right")
    for ax in (ax_road, ax_acc, ax_trav, ax_tire):
        ax.set_xlabel(
            "time [s]" + (f" (first {WINDOW_S:g} s of {t[-1]:g} s)" if t[-1] > WINDOW_S else "")
        )

    gains = getattr(trace, "gains", np.zeros(len(scenario.gain_names)))
    freq = np.geomspace(0.1, 100.0, 600)
    fr = scenario.frequency_response(gains, freq)
    ax_freq.loglog(freq, fr["passive"], color="0.55", label="passive")
    ax_freq.loglog(freq, fr["active"], color="C0", label=label)
    ax_freq.set_xlabel("frequency [Hz]")
    ax_freq.set_ylabel("|body acc. / road velocity| [1/s]")
    ax_freq.legend()

    rows = [
        [
            f"{name} [{shown_unit(key)[0]}]",
            _fmt(m.get(f"passive_{key}"), key),
            _fmt(m.get(key), key),
            _ratio(m, key),
        ]
        for name, key in (
            ("body acc. RMS", "body_acc_rms"),
            ("travel RMS", "susp_travel_rms"),
            ("tire defl. RMS", "tire_defl_rms"),
            ("force RMS", "force_rms"),
        )
    ]
    rows.append(["objective Q (eq. 10) [-]", "3", _fmt(m.get("objective")), ""])
    rows.append(["exact Q (Lyapunov) [-]", "3", _fmt(m.get("objective_exact")), ""])
    rows.append(["damping ratio [-]", _fmt(m.get("damping_ratio")), "", ""])
    ax_tab.axis("off")
    table = ax_tab.table(
        cellText=rows,
        colLabels=["", "passive", label, "ratio"],
        loc="center",
        cellLoc="right",
        colWidths=[0.4, 0.2, 0.2, 0.15],
    )
    table.auto_set_font_size(False)
    table.set_fontsize(8)
    table.scale(1.0, 1.5)
    gains_text = ", ".join(f"{n} = {v:g}" for n, v in zip(scenario.gain_names, gains, strict=True))
    ax_tab.set_title(f"{scenario.preset}: {gains_text or 'no gains'}")
    fig.tight_layout()
    save(fig, path)


def _fmt(x: object, metric: str = "") -> str:
    """A table cell: `x` in the unit `metric` is shown in (as given without a metric)."""
    factor = shown_unit(metric)[1] if metric else 1.0
    return "-" if x is None else f"{float(x) * factor:.4g}"  # type: ignore[arg-type]


def _ratio(m: dict[str, Any], key: str) -> str:
    a, p = m.get(key), m.get(f"passive_{key}")
    return "-" if a is None or not p else f"{a / p:.3f}"
