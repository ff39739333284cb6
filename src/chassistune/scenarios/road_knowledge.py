"""Road knowledge, a declared choice of every ABS scenario (docs/abs_laws.md, "Road knowledge"):
what a slip law is told of the slip at which the road's force-slip curve peaks.

- `oracle`: the target slip is the road's peak (the papers' setting: their controllers are
  handed the optimal slip, which no vehicle knows);
- `fixed`: one target slip for every road, the law's extra gain `target_slip` (`TARGET_GAIN`,
  tuned with the others);
- `none`: the law regulates no target slip (`Law.needs_target` False: mixed slip-deceleration,
  extremum seeking, no control), so there is nothing to know.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from chassistune.controllers.laws import registry as laws
from chassistune.controllers.specs import ControllerSpec, GainSpec
from chassistune.errors import InputError

KNOWLEDGE = ("oracle", "fixed", "none")
FIELD = "road_knowledge"

TARGET_GAIN = GainSpec(
    "target_slip",
    "-",
    0.15,
    0.03,
    0.4,
    "the target slip on every road (road knowledge fixed)",
)


def road_knowledge(values: Mapping[str, object], controller: str) -> str:
    """The scenario's road knowledge: `values["road_knowledge"]`, by default `oracle` for a law
    that regulates a target slip and `none` for one that does not; a choice that does not fit
    the law is refused in one line naming the field."""
    needs = laws.get(controller).needs_target
    chosen = str(values.get(FIELD, "oracle" if needs else "none"))
    where = f"params.{FIELD}"
    if chosen not in KNOWLEDGE:
        raise InputError(where, f"must be one of {', '.join(KNOWLEDGE)}, got {chosen!r}")
    if needs and chosen == "none":
        raise InputError(where, f"{controller} regulates a target slip: oracle or fixed")
    if not needs and chosen != "none":
        raise InputError(where, f"{controller} reads no target slip: none")
    if chosen == "fixed" and "target_slip" in values:
        raise InputError(
            "params.target_slip",
            "a fixed road knowledge tunes the target as the gain target_slip; set its value "
            "with --gains target_slip=VALUE",
        )
    return chosen


def controller_spec(spec: ControllerSpec, knowledge: str) -> ControllerSpec:
    """The law's spec under `knowledge`: with `TARGET_GAIN` as its last gain when `fixed`."""
    if knowledge != "fixed":
        return spec
    return dataclasses.replace(spec, gains=(*spec.gains, TARGET_GAIN))


def plant_rows(plant: np.ndarray, target_col: int, gains: np.ndarray, knowledge: str) -> np.ndarray:
    """The kernel's plant vector for gain rows `gains`: `plant` (one row for all) unless the
    target is the gain `target_slip` (the last column), then one row per candidate with its
    target in column `target_col`."""
    if knowledge != "fixed":
        return plant
    rows = np.repeat(np.atleast_2d(plant)[:1], gains.shape[0], axis=0)
    rows[:, target_col] = gains[:, -1]
    return rows
