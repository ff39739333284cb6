"""Figures of a fuzzy rule base: membership functions and control surfaces (exact inference).

matplotlib is imported when a figure is drawn, never at package import; no pyplot state is used.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from chassistune._io import atomic_path
from chassistune.fuzzy.engine import evaluate
from chassistune.fuzzy.rulebase import RuleBase, Variable

SURFACE_POINTS = 241  # per axis (aligned with the built-ins' knots): exact inference per pixel row


def _plot_sets(ax: Any, var: Variable, role: str) -> None:
    from matplotlib.ticker import MaxNLocator

    lo, hi = var.universe
    x = np.linspace(lo, hi, 1201)
    for s in var.sets:
        (line,) = ax.plot(x, s.mf(x), lw=1.5)
        peak = float(np.clip(np.mean(s.core), lo, hi))
        ha = "left" if peak <= lo else "right" if peak >= hi else "center"
        ax.text(peak, 1.03, s.name, ha=ha, va="bottom", fontsize=7, color=line.get_color())
    ax.set_xlim(lo, hi)
    ax.xaxis.set_major_locator(MaxNLocator(nbins=5))  # tick labels of a narrow panel apart
    ax.set_ylim(0.0, 1.18)
    ax.set_title(f"{role} {var.name}", fontsize=9)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)


def _plot_surface(
    fig: Any, ax: Any, rb: RuleBase, k: int, g0: np.ndarray, g1: np.ndarray, z: np.ndarray
) -> None:
    """The control surface seen from above: colour, contours, dashed lines at the input peaks."""
    out = rb.outputs[k]
    lo, hi = out.universe
    signed = lo < 0.0 < hi
    cmap, vmin, vmax = ("RdBu_r", -max(-lo, hi), max(-lo, hi)) if signed else ("viridis", lo, hi)
    mesh = ax.pcolormesh(g0, g1, z.T, cmap=cmap, vmin=vmin, vmax=vmax, shading="gouraud")
    # Levels halfway between twelfths of the range: set peaks and plateaus sit on twelfths, and a
    # contour through a plateau only draws its rounding noise.
    levels = lo + (hi - lo) * (2.0 * np.arange(12) + 1.0) / 24.0
    contours = ax.contour(g0, g1, z.T, levels=levels, colors="k", linewidths=0.5, alpha=0.6)
    ax.clabel(contours, fontsize=6, fmt="%.3g")  # labels the axes would clip: `_drop_clipped`
    for axis, var in enumerate(rb.inputs):
        for s in var.sets:
            peak = float(np.mean(s.core))
            line = ax.axvline if axis == 0 else ax.axhline
            line(peak, color="0.3", lw=0.5, ls=":")
    ax.set_xlabel(rb.inputs[0].name)
    ax.set_ylabel(rb.inputs[1].name)
    ax.set_title(f"{out.name}({rb.inputs[0].name}, {rb.inputs[1].name})", fontsize=10)
    ax.set_aspect("equal" if rb.inputs[0].span == rb.inputs[1].span else "auto")
    fig.colorbar(mesh, ax=ax, shrink=0.85, label=out.name)


def _drop_clipped(fig: Any) -> None:
    """Remove the contour labels that stick out of their axes (the axes would cut them to a
    misleading fragment, "92" of 0.792), once the layout is final."""
    from matplotlib.text import Text

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        box = ax.bbox
        for t in [a for a in ax.texts if isinstance(a, Text) and a.get_clip_on()]:
            ext = t.get_window_extent(renderer)
            if ext.x0 < box.x0 or ext.x1 > box.x1 or ext.y0 < box.y0 or ext.y1 > box.y1:
                t.remove()


def plot_memberships(rb: RuleBase, path: str | Path, title: str) -> Path:
    """The membership functions of every input and output of `rb`, one panel each, in one row."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    variables = [("input", v) for v in rb.inputs] + [("output", v) for v in rb.outputs]
    fig = Figure(figsize=(3.0 * len(variables), 2.6), layout="constrained")
    FigureCanvasAgg(fig)
    for ax, (role, var) in zip(
        np.atleast_1d(fig.subplots(1, len(variables))), variables, strict=True
    ):
        _plot_sets(ax, var, role)
    fig.suptitle(title, fontsize=10)
    return _save(fig, path)


def _save(fig: Any, path: str | Path) -> Path:
    """Write a figure atomically (never a half-written file); its format from the suffix."""
    out = Path(path)
    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=110, format=out.suffix.lstrip(".").lower() or "png")
    return out


def plot_rulebase(rb: RuleBase, path: str | Path) -> Path:
    """Draw the sets of every variable and the control surface of every output; save to `path`."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    variables = [("input", v) for v in rb.inputs] + [("output", v) for v in rb.outputs]
    n_top = len(variables)
    n_bottom = len(rb.outputs) if len(rb.inputs) in (1, 2) else 0
    width = max(3.0 * n_top, 4.8 * n_bottom)
    fig = Figure(figsize=(width, 2.4 + (4.2 if n_bottom else 0.0)), layout="constrained")
    FigureCanvasAgg(fig)
    rows: Any = fig.subfigures(2, 1, height_ratios=[2.4, 4.2]) if n_bottom else [fig]
    top, bottom = rows[0], (rows[1] if n_bottom else None)
    for ax, (role, var) in zip(np.atleast_1d(top.subplots(1, n_top)), variables, strict=True):
        _plot_sets(ax, var, role)
    title = f"rule base {rb.name}: {len(rb.rules)} rules, Mamdani min/max, centroid"
    top.suptitle(title, fontsize=10)
    if bottom is not None and len(rb.inputs) == 2:
        g0 = np.linspace(*rb.inputs[0].universe, SURFACE_POINTS)
        g1 = np.linspace(*rb.inputs[1].universe, SURFACE_POINTS)
        x0, x1 = np.meshgrid(g0, g1, indexing="ij")
        z = evaluate(rb, np.stack([x0.ravel(), x1.ravel()], axis=1))
        for k, ax in enumerate(np.atleast_1d(bottom.subplots(1, n_bottom))):
            _plot_surface(bottom, ax, rb, k, g0, g1, z[:, k].reshape(x0.shape))
    elif bottom is not None:
        x = np.linspace(*rb.inputs[0].universe, 1201)
        z = evaluate(rb, x[:, None])
        for k, ax in enumerate(np.atleast_1d(bottom.subplots(1, n_bottom))):
            ax.plot(x, z[:, k])
            ax.set_xlabel(rb.inputs[0].name)
            ax.set_title(rb.outputs[k].name, fontsize=9)
            ax.grid(alpha=0.3)
    if bottom is not None and len(rb.inputs) == 2:
        _drop_clipped(fig)
    return _save(fig, path)
