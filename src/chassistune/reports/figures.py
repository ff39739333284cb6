"""PNG figures of the static report: convergence bands, final-cost box plots, and the best
responses of every optimizer over the baseline (`PngFigures`, the static `sections.Figures`)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from chassistune._rng import make_rng
from chassistune.plots.overlay import plot_overlay
from chassistune.plots.style import pyplot, save
from chassistune.reports.bands import convergence_bands, log_scale_suits
from chassistune.reports.html import FigureView
from chassistune.reports.responses import ResponseSet
from chassistune.reports.sections import ASSETS, Assets
from chassistune.studies.store import RunRecord


def convergence_figure(runs: Mapping[str, Sequence[RunRecord]], path: str, title: str) -> None:
    """Best cost so far against evaluations per optimizer: median line, interquartile band."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.2))
    _convergence_axes(ax, runs)
    ax.set_title(f"{title}\nmedian and interquartile band over seeds", fontsize=9)
    fig.tight_layout()
    save(fig, path)


def convergence_panels_figure(
    panels: Mapping[str, Mapping[str, Sequence[RunRecord]]], path: str, title: str
) -> None:
    """`convergence_figure` of several cells (a panel per cell, titled by its key), two columns."""
    plt = pyplot()
    cols = min(2, len(panels))
    rows = -(-len(panels) // cols)
    fig, grid = plt.subplots(rows, cols, figsize=(6 * cols, 3.6 * rows), squeeze=False)
    for ax, (name, runs) in zip(grid.ravel(), panels.items(), strict=False):
        _convergence_axes(ax, runs)
        ax.set_title(name, fontsize=9)
    for ax in grid.ravel()[len(panels) :]:
        ax.set_visible(False)
    fig.suptitle(f"{title}: median and interquartile band over seeds", fontsize=10)
    fig.tight_layout()
    save(fig, path)


def _convergence_axes(ax: Any, runs: Mapping[str, Sequence[RunRecord]]) -> None:
    """Median best-so-far cost and its interquartile band per label on `ax`."""
    drawn = []
    for label, (n, band) in convergence_bands(runs).items():
        line = ax.plot(
            band["nfev"], band["median"], drawstyle="steps-post", label=f"{label} (median of {n})"
        )[0]
        ax.fill_between(
            band["nfev"],
            band["q25"],
            band["q75"],
            step="post",
            color=line.get_color(),
            alpha=0.2,
            lw=0,
        )
        drawn.extend([band["q25"], band["q75"]])
    if log_scale_suits(drawn):
        ax.set_yscale("log")
    ax.set_xlabel("evaluations")
    ax.set_ylabel("best cost so far")
    if drawn:
        ax.legend()


def boxplot_figure(costs: Mapping[str, np.ndarray], path: str, title: str) -> None:
    """Final best cost per optimizer: box plot with every run as a point."""
    plt = pyplot()
    labels = list(costs)
    fig, ax = plt.subplots(figsize=(max(4.0, 1.2 * len(labels) + 2), 4.0))
    data = [np.asarray(costs[k], dtype=float) for k in labels]
    ax.boxplot(data, showfliers=False, widths=0.5)
    ax.set_xticks(range(1, len(labels) + 1), labels)
    jitter = make_rng(0)
    for i, v in enumerate(data, start=1):
        ax.plot(i + jitter.uniform(-0.12, 0.12, v.size), v, "o", ms=3.5, alpha=0.6, color="C0")
    if log_scale_suits(data):
        ax.set_yscale("log")
    ax.set_ylabel("final best cost")
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    save(fig, path)


class PngFigures:
    """Draws each figure into DIR/report/figures/NAME.png (in the report's set of files) and
    embeds it in the page."""

    def __init__(self, assets: Assets) -> None:
        self.assets = assets
        self.folder = assets.root / ASSETS / "figures"
        self.folder.mkdir(parents=True, exist_ok=True)
        self.written: list[Path] = []

    def remove_stale(self) -> None:
        """Remove the figures of a previous report that this one did not draw (once this
        report's files are in place)."""
        for old in self.folder.glob("*.png"):
            if old not in self.written:
                old.unlink()

    def _draw(self, name: str, draw: Callable[[str], None], title: str, caption: str) -> FigureView:
        path = self.folder / f"{name}.png"
        with self.assets.staged.path(path) as tmp:
            draw(tmp)
        self.written.append(path)
        return FigureView.from_png(
            Path(tmp),
            self.assets.next_id("figure"),
            title,
            caption,
            path.relative_to(self.assets.root).as_posix(),
        )

    def convergence(
        self, scenario: str, runs: Mapping[str, Sequence[RunRecord]], name: str
    ) -> FigureView:
        return self._draw(
            name,
            lambda path: convergence_figure(runs, path, scenario),
            f"Convergence, {scenario}",
            "Best cost so far against evaluations: median over seeds (line) and "
            "interquartile band.",
        )

    def final_costs(self, scenario: str, costs: Mapping[str, np.ndarray], name: str) -> FigureView:
        return self._draw(
            name,
            lambda path: boxplot_figure(costs, path, f"{scenario}: final best cost"),
            f"Final cost distribution, {scenario}",
            "Box plot of the final best cost per optimizer; points are runs.",
        )

    def responses(self, rs: ResponseSet, name: str) -> FigureView:
        base = next((c.label for c in rs.curves if c.baseline), "")
        return self._draw(
            name,
            lambda path: plot_overlay(
                [(p.signal, p.label) for p in rs.panels],
                rs.curves,
                path,
                f"{rs.scenario} on {rs.road}: each optimizer's best run",
            ),
            f"Best controllers against {base}, {rs.scenario}, on {rs.road}",
            f"Each optimizer's lowest-cost gains (label: the seed that found them) "
            f"re-simulated on {rs.road}, all on the road realization of seed "
            f"{rs.seed}, over the {base} baseline (grey, dashed).",
        )
