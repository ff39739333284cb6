"""Sobol sensitivity bar chart: first-order and total index of each uncertain parameter."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from chassistune.plots.style import pyplot, save


def plot_sobol_indices(
    names: Sequence[str],
    first_order: Sequence[float],
    total: Sequence[float],
    path: str,
    title: str = "",
) -> None:
    """Grouped bars per parameter: S_i (first order) beside S_Ti (total), on [0, 1]."""
    plt = pyplot()
    x = np.arange(len(names))
    fig, ax = plt.subplots(figsize=(max(4.0, 1.1 * len(names) + 2.0), 3.6))
    ax.bar(x - 0.2, first_order, width=0.4, label="first order $S_i$")
    ax.bar(x + 0.2, total, width=0.4, label="total $S_{Ti}$")
    ax.set_xticks(x, list(names), rotation=20, ha="right")
    ax.set_ylim(0.0, max(1.0, float(np.max(total, initial=0.0)) * 1.05))
    ax.set_ylabel("Sobol index")
    ax.set_title(title)
    ax.legend()
    fig.tight_layout()
    save(fig, path)
