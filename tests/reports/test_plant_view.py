"""Every registered plant declares in its spec how the reports present it: the signals of its
response panels are in its traces and its generalization metrics among its metrics."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.reports.plant_view import plant_view
from chassistune.scenarios.registry import get_plant, plant_names, plant_spec


@pytest.mark.parametrize("plant", plant_names())
def test_the_view_names_signals_and_metrics_the_plant_has(plant: str) -> None:
    view = plant_view(plant)
    assert view is plant_spec(plant).view
    assert view.panels and view.generalization_metrics and view.baseline
    sc = get_plant(plant).scenario(None, None, view.baseline, {})
    trace = sc.trace(np.zeros(len(sc.gain_names)))
    for panel in view.panels:
        assert panel.signal in trace.signals
        assert not panel.baseline_signal or panel.baseline_signal in trace.signals
    assert {m for m, _ in view.generalization_metrics} <= trace.metrics.keys()


def test_an_unregistered_plant_gets_the_empty_view() -> None:
    view = plant_view("no-such-plant")
    assert not view.panels and not view.generalization_metrics
