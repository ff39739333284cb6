"""Time responses of each optimizer's best controller and the plant's baseline, for overlays.

Each optimizer's best gains are re-simulated from the stored spec, all on the scenario seed of
the overall best run; the baseline (no ABS, passive suspension: `plant_view(...).baseline`) on
the same road and seed.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from chassistune.plots.overlay import Line
from chassistune.reports.plant_view import plant_view
from chassistune.reports.tables import StudyData
from chassistune.scenarios.base import Plant
from chassistune.scenarios.report_view import Panel, PlantView
from chassistune.studies.store import RunRecord


@dataclass(frozen=True)
class ResponseSet:
    """Every optimizer's best on one road of one scenario, with the baseline first, all on the
    road realization of seed index `seed`."""

    scenario: str
    road: str
    panels: tuple[Panel, ...]
    curves: tuple[Line, ...]
    seed: int


def best_by_optimizer(data: StudyData, scenario: str) -> dict[str, RunRecord]:
    """Each optimizer's completed run of lowest final cost (lowest seed on ties)."""
    out = {}
    for opt in data.optimizers:
        runs = data.runs(scenario, opt)
        if runs:
            out[opt] = min(runs, key=lambda r: (r.best_cost, r.spec.seed))
    return out


def _baseline_params(record: RunRecord) -> dict[str, object]:
    """The run's parameter overrides less those of its controller (the baseline has others)."""
    from chassistune.controllers.catalogue import get

    own = set(get(record.spec.plant, record.spec.controller).param_names)
    return {k: v for k, v in record.spec.params.items() if k not in own}


MAX_POINTS = 2500
"""Samples kept per curve (every k-th sample of the shown window): enough for a page-wide plot,
small enough for a page that embeds every curve."""


def _window(time_s: np.ndarray, window_s: float | None) -> np.ndarray:
    """Indices of the samples shown: those within the window, thinned to MAX_POINTS."""
    shown = np.flatnonzero(time_s <= window_s) if window_s is not None else np.arange(time_s.size)
    step = max(1, -(-shown.size // MAX_POINTS))
    return shown[::step]


def response_sets(data: StudyData, scenario: str) -> list[ResponseSet]:
    """One ResponseSet per tuned road of `scenario` (empty when no run completed).

    Every optimizer's best gains run on one and the same road realization, that of the overall
    best run's seed (the quarter car's road profile depends on the seed; the ABS's does not), so
    the curves differ only by their gains.
    """
    from chassistune.scenarios.registry import get_plant

    best = best_by_optimizer(data, scenario)
    if not best:
        return []
    overall = min(best.values(), key=lambda r: (r.best_cost, r.spec.seed))
    common = overall.spec.scenario_seed
    view = plant_view(overall.spec.plant)
    if not view.panels:
        return []
    plant = get_plant(overall.spec.plant)
    out = []
    for road in overall.spec.roads:
        curves: list[Line] = []
        for opt, rec in best.items():
            s = rec.spec
            sc = plant.scenario(s.preset, road, s.controller, s.params, common)
            trace = sc.trace(np.array([rec.best_gains[n] for n in sc.gain_names], dtype=float))
            shown = trace.shown
            t = shown["time_s"]
            keep = _window(t, view.window_s)
            if not curves:
                curves.append(_baseline(plant, rec, road, common, shown, view))
            curves.append(
                Line(
                    f"{opt} (seed {s.seed})",
                    t[keep],
                    {p.signal: shown[p.signal][keep] for p in view.panels},
                )
            )
        out.append(ResponseSet(scenario, road, view.panels, tuple(curves), overall.spec.seed))
    return out


def _baseline(
    plant: Plant,
    rec: RunRecord,
    road: str,
    seed: int,
    signals: Mapping[str, np.ndarray],
    view: PlantView,
) -> Line:
    """The baseline: the trace's own passive_* signals, or a run with the baseline controller
    (the run's parameters less its controller's) on the same road and scenario seed."""
    if all(p.baseline_signal for p in view.panels):
        t = signals["time_s"]
        keep = _window(t, view.window_s)
        return Line(
            view.baseline_label,
            t[keep],
            {p.signal: signals[p.baseline_signal][keep] for p in view.panels},
            baseline=True,
        )
    s = rec.spec
    sc = plant.scenario(s.preset, road, view.baseline, _baseline_params(rec), seed)
    shown = sc.trace(np.zeros(len(sc.gain_names))).shown
    t = shown["time_s"]
    keep = _window(t, view.window_s)
    return Line(
        view.baseline_label,
        t[keep],
        {p.signal: shown[p.signal][keep] for p in view.panels},
        baseline=True,
    )
