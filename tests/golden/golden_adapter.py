"""Where the golden cases reach below the public API (the one place to update when it moves)."""

from __future__ import annotations

from typing import Any

from chassistune.scenarios.registry import get_plant


def abs_scenario(preset: str, road: str, controller: str) -> Any:
    return get_plant("abs-wheel").scenario(preset, road, controller, {}, 0)


def gain_bounds(scenario: Any) -> list[tuple[float, float]]:
    return [(g.lo, g.hi) for g in scenario.controller.gains]
