"""Plots by plant: the figure of a trace, drawn by the function its PlantSpec names.

Used by reports, papers and the CLI only (it imports matplotlib through the plot modules).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import cast

from chassistune._registry import resolve
from chassistune.scenarios.base import Scenario, Trace
from chassistune.scenarios.registry import plant_spec

TracePlot = Callable[[Scenario, Trace, str], None]


def trace_plot(plant: str) -> TracePlot:
    """The function drawing a trace of `plant` into a PNG file: plot(scenario, trace, path)."""
    return cast(TracePlot, resolve(plant_spec(plant).plot))


def plot_trace(scenario: Scenario, trace: Trace, path: str) -> None:
    """Draw the figure of `simulate --plot` for this trace of `scenario.plant` into `path`."""
    trace_plot(scenario.plant)(scenario, trace, path)
