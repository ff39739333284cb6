"""Figures of the vehicle ABS: speeds, slips with targets, loads, brake torques, yaw and heading,
and the top-view path with the car's outline at a few instants."""

from __future__ import annotations

from typing import Any

import numpy as np

from chassistune.plots.style import pyplot, save
from chassistune.scenarios.base import Trace

WHEELS = ("fl", "fr", "rl", "rr")
WHEEL_COLORS = {"fl": "C0", "fr": "C1", "rl": "C2", "rr": "C3"}
OUTLINES = 6
"""Car outlines drawn along the path."""


def car_outline(
    x: float, y: float, psi: float, front_m: float, rear_m: float, half_width_m: float
) -> np.ndarray:
    """Corners (5, 2) of the body rectangle at CG (x, y) with heading psi, closed."""
    body = np.array(
        [
            [front_m, half_width_m],
            [-rear_m, half_width_m],
            [-rear_m, -half_width_m],
            [front_m, -half_width_m],
            [front_m, half_width_m],
        ]
    )
    c, s = np.cos(psi), np.sin(psi)
    return np.column_stack(
        (x + c * body[:, 0] - s * body[:, 1], y + s * body[:, 0] + c * body[:, 1])
    )


def plot_trace(scenario: Any, trace: Trace, path: str) -> None:
    """One run on six panels sharing the time axis, plus the top view."""
    plt = pyplot()
    fig = plt.figure(figsize=(13, 10))
    grid = fig.add_gridspec(4, 2, height_ratios=(1, 1, 1, 1.2))
    ax_v = fig.add_subplot(grid[0, 0])
    ax_s = fig.add_subplot(grid[0, 1], sharex=ax_v)
    ax_fz = fig.add_subplot(grid[1, 0], sharex=ax_v)
    ax_tb = fig.add_subplot(grid[1, 1], sharex=ax_v)
    ax_r = fig.add_subplot(grid[2, 0], sharex=ax_v)
    ax_psi = fig.add_subplot(grid[2, 1], sharex=ax_v)
    ax_top = fig.add_subplot(grid[3, :])
    sig, m = trace.shown, trace.metrics
    t = sig["time_s"]
    ax_v.plot(t, sig["speed_m_s"], color="k", label="car (CG speed)")
    for w in WHEELS:
        col = WHEEL_COLORS[w]
        ax_v.plot(t, sig[f"wheel_speed_{w}_m_s"], color=col, lw=0.8, label=f"wheel {w} (w R)")
        ax_s.plot(t, sig[f"slip_{w}"], color=col, lw=0.8, label=w)
        ax_s.plot(t, sig[f"target_slip_{w}"], color=col, lw=0.8, ls=":")
        ax_fz.plot(t, sig[f"load_{w}_n"], color=col, lw=0.9, label=w)
        ax_tb.plot(t, sig[f"brake_torque_{w}_n_m"], color=col, lw=0.8, label=w)
    ax_v.set_ylabel("speed [m/s]")
    ax_s.set_ylabel("slip [-] (dotted: target; locked: 1)")
    ax_s.set_ylim(-0.02, 1.02)
    ax_fz.set_ylabel("wheel load Fz [N]")
    ax_tb.set_ylabel("brake torque [N m]")
    ax_r.plot(t, sig["yaw_rate_rad_s"], color="C4")
    ax_r.set_ylabel("yaw rate [rad/s]")
    ax_psi.plot(t, np.degrees(sig["heading_rad"]), color="C5", label="heading")
    if np.any(sig["steer_rad"] != 0.0):
        ax_psi.plot(t, np.degrees(sig["steer_rad"]), color="C6", lw=0.8, label="steering")
    ax_psi.set_ylabel("angle [deg]")
    for ax in (ax_r, ax_psi):
        ax.set_xlabel("time [s]")
    for ax in (ax_v, ax_s, ax_fz, ax_tb, ax_psi):
        ax.legend(loc="best", ncol=2)

    pp = scenario.plant_params
    x, y = sig["x_m"], sig["y_m"]
    ax_top.plot(
        x,
        y,
        color="k",
        lw=0.8,
        label=f"CG path: {m['stop_distance_m']:.1f} m (bound {m['bound_distance_m']:.1f} m)",
    )
    half = 0.5 * max(pp.track_front_m, pp.track_rear_m) + 0.1
    for k in np.linspace(0, len(t) - 1, OUTLINES).astype(int):
        body = car_outline(
            x[k], y[k], sig["heading_rad"][k], pp.cg_to_front_m + 0.8, pp.cg_to_rear_m + 0.8, half
        )
        ax_top.plot(body[:, 0], body[:, 1], color="C0", lw=0.9)
        ax_top.annotate(f"{t[k]:.1f} s", (x[k], y[k]), fontsize=7, ha="center")
    ax_top.set_aspect("equal", adjustable="datalim")
    ax_top.set_xlabel("X [m]")
    ax_top.set_ylabel("Y [m] (left +)")
    ax_top.legend(loc="best")
    title = (
        f"abs-vehicle, preset {scenario.preset}, road {scenario.road}, "
        f"{scenario.controller.name}, steering {scenario.steering.steering}"
    )
    if m.get("spun"):
        title += f": spun at {m['spin_time_s']:.2f} s"
    fig.suptitle(title)
    fig.tight_layout()
    save(fig, path)
