"""The league's cases figure: per plant, laws by held-out cases, coloured and labelled with the
median stop distance over the adhesion bound (docs/league.md)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from chassistune.plots.style import pyplot, save


@dataclass(frozen=True)
class CaseGrid:
    """One plant's panel: its laws (rows, ranked), cases (columns) and values (NaN: no stop)."""

    laws: Sequence[str]
    cases: Sequence[str]
    values: np.ndarray


def plot_league_cases(
    grids: Mapping[str, CaseGrid], path: str, what: str = "median over seeds"
) -> None:
    """One heatmap panel per plant (the values' colour scale starts at the bound, 1); `what`
    says in each title which run's value a cell shows."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(grids), figsize=(6.2 * len(grids), 4.2), squeeze=False)
    for ax, (plant, g) in zip(axes[0], grids.items(), strict=True):
        im = ax.imshow(g.values, cmap="viridis_r", aspect="auto", vmin=1.0)
        top = np.nanmax(g.values) if np.isfinite(g.values).any() else 1.0
        for (i, j), v in np.ndenumerate(g.values):
            finite = bool(np.isfinite(v))
            ax.text(
                j,
                i,
                f"{v:.2f}" if finite else "no stop",
                ha="center",
                va="center",
                fontsize=7,
                color="white" if finite and v < 1.0 + 0.8 * (top - 1.0) else "black",
            )
        ax.set_xticks(range(len(g.cases)), list(g.cases), rotation=30, ha="right")
        ax.set_yticks(range(len(g.laws)), list(g.laws))
        ax.set_title(f"{plant}: stop distance / adhesion bound ({what})")
        ax.grid(False)
        fig.colorbar(im, ax=ax, shrink=0.8)
    fig.tight_layout()
    save(fig, path)
