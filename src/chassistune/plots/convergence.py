"""Convergence curves: best-so-far cost against evaluations, median with interquartile band."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from chassistune.plots.style import pyplot, save


def plot_convergence(
    runs: Mapping[str, Sequence[tuple[np.ndarray, np.ndarray]]], path: str, title: str = ""
) -> None:
    """`runs[label]` is a list of (history_nfev, history) pairs (one per seed)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for label, curves in runs.items():
        grid = np.unique(np.concatenate([np.asarray(n, dtype=float) for n, _ in curves]))
        values = np.array([np.interp(grid, n, h, left=np.nan) for n, h in curves])
        med = np.nanmedian(values, axis=0)
        line = ax.plot(
            grid, med, label=f"{label} (median of {len(curves)})" if len(curves) > 1 else label
        )[0]
        if len(curves) > 1:
            lo, hi = np.nanpercentile(values, [25, 75], axis=0)
            ax.fill_between(grid, lo, hi, color=line.get_color(), alpha=0.2)
    positive = all(np.all(np.asarray(h) > 0) for c in runs.values() for _, h in c)
    if positive:
        ax.set_yscale("log")
    ax.set_xscale("log")  # the early iterations, where most of the progress is, get room
    ax.set_xlabel("evaluations (log scale)")
    ax.set_ylabel("best cost so far")
    ax.set_title(title)
    ax.legend()
    fig.tight_layout()
    save(fig, path)
