"""Figures of the single-wheel ABS: speeds, slip against its target, brake torque, distance."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from chassistune.plots.style import pyplot, save
from chassistune.scenarios.base import Scenario, Trace

_MARK = {"color": "k", "ls": ":", "lw": 1}
"""The style of the reference lines (target slip, physical bounds)."""


def plot_trace(scenario: Scenario, trace: Trace, path: str) -> None:
    """One run: vehicle and wheel speed, slip with its target, brake torque, distance vs bound."""
    plot_comparison(scenario, [(scenario.controller.name, trace)], path)


def plot_comparison(
    scenario: Any, runs: Sequence[tuple[str, Trace]], path: str, title: str | None = None
) -> None:
    """Several runs on one road (e.g. no ABS against PID), four panels sharing the time axis."""
    plt = pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(10, 6.5), sharex=True)
    ax_v, ax_s, ax_t, ax_x = axes.ravel()
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, (label, tr) in enumerate(runs):
        sig = tr.signals
        col = colors[k % len(colors)]
        t = sig["time_s"]
        ax_v.plot(t, sig["vehicle_speed_m_s"], color=col, label=f"{label}: vehicle")
        ax_v.plot(
            t, sig["wheel_speed_m_s"], color=col, ls="--", lw=0.9, label=f"{label}: wheel (w R)"
        )
        ax_s.plot(t, sig["slip"], color=col, lw=0.9, label=label)
        ax_t.plot(t, sig["brake_torque_n_m"], color=col, lw=0.9, label=label)
        m = tr.metrics
        stop = (
            f"{m['stop_distance_m']:.1f} m in {m['stop_time_s']:.2f} s"
            if m.get("stopped")
            else f"did not stop ({m.get('status')})"
        )
        ax_x.plot(t, sig["distance_m"], color=col, label=f"{label}: {stop}")
    ax_s.axhline(scenario.target_slip, **_MARK, label="target slip")
    bound_m, bound_s = scenario.bound_distance_m, scenario.bound_time_s
    ax_x.axhline(bound_m, **_MARK, label=f"physical bound {bound_m:.1f} m")
    ax_v.axvline(bound_s, **_MARK, label=f"bound time {bound_s:.2f} s")
    ax_v.set_ylabel("speed [m/s]")
    ax_s.set_ylabel("slip S = (v - w R)/v [-]")
    _zoom_slip(ax_s, scenario.target_slip, [tr.signals["slip"] for _, tr in runs])
    ax_t.set_ylabel("brake torque [N m]")
    ax_x.set_ylabel("distance [m]")
    for ax in (ax_t, ax_x):
        ax.set_xlabel("time [s]")
    for ax in axes.ravel():
        ax.legend(loc="best")
    fig.suptitle(
        title
        or f"abs-wheel, preset {scenario.preset}, road {scenario.road} "
        f"(mu_peak {scenario.mu_peak:.3f})"
    )
    fig.tight_layout()
    save(fig, path)


def _zoom_slip(ax: Any, target: float, slips: Sequence[Any]) -> None:
    """Slip axis around the target (where the controller works); when some run leaves that
    window (a locked wheel), an inset shows the full range 0..1."""
    import numpy as np

    top = max(0.05, 2.5 * target)
    ax.set_ylim(-0.02, top)
    if any(np.nanmax(s, initial=0.0) > top for s in slips):
        inset = ax.inset_axes((0.62, 0.55, 0.35, 0.4))
        for line in ax.get_lines():
            inset.plot(line.get_xdata(), line.get_ydata(), color=line.get_color(), lw=0.6)
        inset.set_ylim(-0.02, 1.02)
        inset.set_title("full range", fontsize=7)
        inset.tick_params(labelsize=6)
