"""Figures of a study report: convergence bands, final-cost box plots, best responses (PNG)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from chassistune import stats
from chassistune.plots.style import pyplot, save
from chassistune.studies.store import RunRecord


def _log_scale_suits(values: Sequence[np.ndarray]) -> bool:
    v = np.concatenate([np.ravel(a) for a in values]) if values else np.zeros(0)
    v = v[np.isfinite(v)]
    return bool(v.size) and bool(np.all(v > 0)) and float(v.max() / v.min()) > 30.0


def convergence_figure(runs: Mapping[str, Sequence[RunRecord]], path: str, title: str) -> None:
    """Best cost so far against evaluations per optimizer: median line, interquartile band."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.2))
    drawn = []
    for label, recs in runs.items():
        recs = [r for r in recs if r.history]
        if not recs:
            continue
        grid = np.unique(np.concatenate([np.asarray(r.history_nfev, dtype=float) for r in recs]))
        band = stats.convergence_band([r.history for r in recs], [r.history_nfev for r in recs],
                                      grid)
        line = ax.plot(band["nfev"], band["median"], drawstyle="steps-post",
                       label=f"{label} (median of {len(recs)})")[0]
        ax.fill_between(band["nfev"], band["q25"], band["q75"], step="post",
                        color=line.get_color(), alpha=0.2, lw=0)
        drawn.extend([band["q25"], band["q75"]])
    if _log_scale_suits(drawn):
        ax.set_yscale("log")
    ax.set_xlabel("evaluations")
    ax.set_ylabel("best cost so far")
    ax.set_title(f"{title}\nmedian and interquartile band over seeds", fontsize=9)
    if drawn:
        ax.legend()
    fig.tight_layout()
    save(fig, path)


def boxplot_figure(costs: Mapping[str, np.ndarray], path: str, title: str) -> None:
    """Final best cost per optimizer: box plot with every run as a point."""
    plt = pyplot()
    labels = list(costs)
    fig, ax = plt.subplots(figsize=(max(4.0, 1.2 * len(labels) + 2), 4.0))
    data = [np.asarray(costs[k], dtype=float) for k in labels]
    ax.boxplot(data, showfliers=False, widths=0.5)
    ax.set_xticks(range(1, len(labels) + 1), labels)
    jitter = np.random.default_rng(0)
    for i, v in enumerate(data, start=1):
        ax.plot(i + jitter.uniform(-0.12, 0.12, v.size), v, "o", ms=3.5, alpha=0.6, color="C0")
    if _log_scale_suits(data):
        ax.set_yscale("log")
    ax.set_ylabel("final best cost")
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    save(fig, path)


def response_figures(record: RunRecord, path_for_road: Mapping[str, str]) -> list[str]:
    """The plant's own response plot of a run's best gains on each tuned road (re-simulated
    with the run's scenario seed); the paths written."""
    from chassistune.plots.registry import plot_trace
    from chassistune.scenarios.registry import get_plant

    s = record.spec
    plant = get_plant(s.plant)
    written = []
    for road in s.roads:
        sc = plant.scenario(s.preset, road, s.controller, s.params, s.scenario_seed)
        gains = np.array([record.best_gains[n] for n in sc.gain_names], dtype=float)
        plot_trace(sc, sc.trace(gains), path_for_road[road])
        written.append(path_for_road[road])
    return written
