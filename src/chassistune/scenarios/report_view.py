"""How the reports present a plant beyond its key metrics (a field of its `PlantSpec`): its
baseline controller, the signals of its response overlays and the metrics of its
generalization matrices (lower-is-better)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Panel:
    """One panel of a response overlay: a trace signal, its axis label, and the baseline's
    signal (the same trace's `passive_*` copy, or the signal of the baseline's own trace)."""

    signal: str
    label: str
    baseline_signal: str = ""


@dataclass(frozen=True)
class PlantView:
    """How the reports present one plant (empty: no overlays, no generalization matrix)."""

    baseline: str = ""
    baseline_label: str = ""
    panels: tuple[Panel, ...] = ()
    generalization_metrics: tuple[tuple[str, str], ...] = ()
    window_s: float | None = None
