"""Response overlays: several controllers' time responses on stacked panels sharing time."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from chassistune.plots.style import pyplot, save


@dataclass(frozen=True)
class Line:
    """One controller on every panel: `values[signal]` against `time_s`; the baseline is drawn
    grey and dashed under the others."""

    label: str
    time_s: np.ndarray
    values: Mapping[str, np.ndarray]
    baseline: bool = False


def plot_overlay(
    panels: Sequence[tuple[str, str]], lines: Sequence[Line], path: str, title: str
) -> None:
    """`panels` are (signal, y label) pairs, one axis each (two columns from four panels on),
    time shared."""
    plt = pyplot()
    cols = 2 if len(panels) >= 4 else 1
    rows = -(-len(panels) // cols)
    fig, grid = plt.subplots(
        rows, cols, figsize=(10 if cols == 2 else 8, 2.3 * rows + 0.6), sharex=True, squeeze=False
    )
    axes = grid.ravel()[: len(panels)]
    for ax in grid.ravel()[len(panels) :]:
        ax.set_visible(False)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    k = 0
    for line in lines:
        if line.baseline:
            style = {"color": "0.45", "ls": "--", "lw": 1.2, "zorder": 1}
        else:
            style = {"color": colors[k % len(colors)], "lw": 1.0, "zorder": 2}
            k += 1
        for ax, (signal, _) in zip(axes, panels, strict=True):
            ax.plot(line.time_s, line.values[signal], label=line.label, **style)
    for ax, (_, ylabel) in zip(axes, panels, strict=True):
        ax.set_ylabel(ylabel)
    for ax in grid[-1]:
        ax.set_xlabel("time [s]")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(
        handles, labels, loc="upper center", ncol=min(len(labels), 4), bbox_to_anchor=(0.5, 1.0)
    )
    fig.suptitle(title, fontsize=9, y=1.04)
    fig.tight_layout()
    save(fig, path)


def plot_results(results: Mapping[str, Any], path: str, max_panels: int = 6) -> None:
    """`simulate --compare`: SimulationResults by label on one figure, one panel per signal
    (the first `max_panels` signals of the plant's trace, with units), gains in the legend."""
    first = next(iter(results.values()))
    units = first.trace.units
    signals = [n for n in first.trace.signals if n != "time_s"][:max_panels]
    panels = [(n, f"{n} [{units.get(n, '-')}]") for n in signals]
    lines = []
    for label, r in results.items():
        gains = ", ".join(f"{k}={v:.4g}" for k, v in r.gains.items())
        lines.append(
            Line(
                f"{label} ({gains})" if gains else label,
                r.trace.signals["time_s"],
                r.trace.signals,
                baseline=label == "none",
            )
        )
    sc = first.scenario
    plot_overlay(panels, lines, path, f"{sc.plant}, preset {sc.preset}, road {sc.road}")
