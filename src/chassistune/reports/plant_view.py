"""The one place the reports ask how to present a plant: its spec's `view`."""

from __future__ import annotations

from chassistune.scenarios.registry import SPECS
from chassistune.scenarios.report_view import PlantView


def plant_view(plant: str) -> PlantView:
    """The report's view of `plant` (an empty view for a plant no longer registered)."""
    return SPECS.get(plant).view if plant in SPECS else PlantView()
