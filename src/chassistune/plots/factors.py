"""Tuned controller parameters inside their search box (deffao-vehicle-abs Fig. 6: the fuzzy PID's
factors tuned by AO and DEFFAO): each parameter's place in [lower, upper], every seed a point."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from chassistune.plots.style import pyplot, save


def plot_factors_in_box(
    bounds: Mapping[str, tuple[float, float]],
    tuned: Mapping[str, Sequence[Mapping[str, float]]],
    defaults: Mapping[str, float],
    path: str,
    title: str,
) -> None:
    """x: the parameters, tick-labelled with their box; y: (value - lower)/(upper - lower).
    `tuned[label]` holds one parameter set per seed (drawn as points, their median as a bar);
    the defaults are black crosses."""
    plt = pyplot()
    names = list(bounds)
    x = np.arange(len(names))
    fig, ax = plt.subplots(figsize=(max(6.0, 0.9 * len(names) + 2.5), 4.2))

    def place(values: Mapping[str, float]) -> np.ndarray:
        return np.array([(values[n] - lo) / (hi - lo) for n, (lo, hi) in bounds.items()])

    width = 0.7 / max(len(tuned), 1)
    for k, (label, sets) in enumerate(tuned.items()):
        dx = (k - (len(tuned) - 1) / 2) * width
        pos = np.array([place(s) for s in sets])
        median = np.median(pos, axis=0)
        bars = ax.bar(
            x + dx, median, width=width, alpha=0.35, label=f"{label} (median of {len(sets)})"
        )
        for row in pos:
            ax.plot(x + dx, row, "o", ms=3, color=bars.patches[0].get_facecolor()[:3])
    ax.plot(x, place(defaults), "x", color="k", ms=7, label="default (untuned)")
    ax.set_xticks(x, [f"{n}\n[{lo:.3g}, {hi:.3g}]" for n, (lo, hi) in bounds.items()], fontsize=7)
    ax.set_ylim(-0.03, 1.03)
    ax.set_ylabel("place in the search box [-]\n(0: lower bound, 1: upper)")
    ax.set_title(title)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=3)
    fig.tight_layout()
    save(fig, path)
