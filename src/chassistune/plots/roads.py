"""The friction roads' mu-slip curves: every road on one figure (`chassistune list roads --plot`)
or a paper's roads on one panel (derlsp-ao-abs Fig. 2, deffao-vehicle-abs Fig. 2)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from chassistune.plants.tires import KIND_BURCKHARDT, TireCurve
from chassistune.plots.style import pyplot, save

SLIP_POINTS = 1001


def plot_friction_curves(curves: Mapping[str, TireCurve], path: str) -> None:
    """mu(S) of every road, labelled by road name with its peak marked: piecewise-linear roads
    (bilinear curves and tables) in the left panel, Burckhardt's in the right."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 6.0), sharey=True)
    slip = np.linspace(0.0, 1.0, SLIP_POINTS)
    panels = {False: axes[0], True: axes[1]}
    for name, curve in curves.items():
        _draw_curve(panels[curve.kernel_data()[0] == KIND_BURCKHARDT], name, curve, slip)
    axes[0].set_title("bilinear and table roads")
    axes[1].set_title("Burckhardt roads: mu = c1 (1 - exp(-c2 S)) - c3 S")
    axes[0].set_ylabel("friction coefficient mu [-]")
    for ax in axes:
        ax.set_xlabel("longitudinal slip S = (v - w R) / v [-]")
        ax.set_xlim(0.0, 1.0)
        ax.set_ylim(bottom=0.0)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, fontsize=7)
    fig.suptitle("tire-road friction curves (v: vehicle speed [m/s], w R: wheel speed [m/s])")
    fig.tight_layout()
    save(fig, path)


def plot_mu_slip(curves: Mapping[str, TireCurve], path: str, title: str) -> None:
    """mu(S) of the given roads on one panel, each peak marked."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.2))
    slip = np.linspace(0.0, 1.0, SLIP_POINTS)
    for name, curve in curves.items():
        _draw_curve(ax, name, curve, slip)
    ax.set_xlabel("longitudinal slip S = (v - w R) / v [-]")
    ax.set_ylabel("friction coefficient mu [-]")
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(bottom=0.0)
    ax.set_title(title)
    ax.legend(loc="best")
    fig.tight_layout()
    save(fig, path)


def _draw_curve(ax: Any, name: str, curve: TireCurve, slip: np.ndarray) -> None:
    """One road's mu(S), labelled with its peak, the peak marked."""
    mu_peak, s_peak, _ = curve.peak()
    (line,) = ax.plot(
        slip, curve.mu(slip), lw=1.3, label=f"{name} (peak {mu_peak:.4g} at S = {s_peak:.3g})"
    )
    ax.plot([s_peak], [mu_peak], "o", ms=4, color=line.get_color())
