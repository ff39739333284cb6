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
    grey and dashed under the others, an emphasized line (the tuned controller) thicker and over
    them, so a default controller with a similar response cannot hide it."""

    label: str
    time_s: np.ndarray
    values: Mapping[str, np.ndarray]
    baseline: bool = False
    emphasized: bool = False


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
            style = {
                "color": colors[k % len(colors)],
                "lw": 2.0 if line.emphasized else 1.0,
                "zorder": 3 if line.emphasized else 2,
            }
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


DISTANCE = "distance_m"
"""The signal a braking comparison is decided on: always a panel where the trace has it."""


def compared_signals(results: Mapping[str, Any], max_panels: int) -> list[str]:
    """The panels of a comparison: the trace's signals in its order, without time and without
    any signal constant in every run (a fixed target slip says nothing), the distance last."""
    traces = [r.trace.shown for r in results.values()]
    varying = [
        n
        for n in traces[0]
        if n not in ("time_s", DISTANCE)
        and any(np.ptp(np.asarray(t[n], dtype=float)) > 0 for t in traces)
    ]
    if DISTANCE in traces[0]:
        return [*varying[: max_panels - 1], DISTANCE]
    return varying[:max_panels]


def plot_results(results: Mapping[str, Any], path: str, max_panels: int = 6) -> None:
    """`simulate --compare`: SimulationResults by label on one figure, one panel per compared
    signal (`compared_signals`, with units), gains in the legend; `tuned` drawn over the rest."""
    first = next(iter(results.values()))
    units = first.trace.units
    panels = [(n, f"{n} [{units.get(n, '-')}]") for n in compared_signals(results, max_panels)]
    lines = []
    for label, r in results.items():
        gains = ", ".join(f"{k}={v:.4g}" for k, v in r.gains.items())
        lines.append(
            Line(
                f"{label} ({gains})" if gains else label,
                r.trace.signals["time_s"],
                r.trace.shown,
                baseline=label == "none",
                emphasized=label == "tuned",
            )
        )
    sc = first.scenario
    plot_overlay(panels, lines, path, f"{sc.plant}, preset {sc.preset}, road {sc.road}")
