"""Which parameters may vary, their valid ranges, `mu_scale`, and scenarios built from draws.

Uncertain parameters are the physical ones of the plant, road and actuator (solver settings and
thresholds such as dt_s, t_max_s, v_stop_m_s and lock_ratio are not). Valid ranges come from the
parameter dataclasses' field metadata (positive: (0, inf); non-negative: [0, inf); unit
interval: [0, 1]).

`mu_scale` (abs-wheel and abs-vehicle, default 1) is a road parameter of every tire curve
(`plants.tires`, `plants.vehicle_roads`): it multiplies the whole mu-slip curve. The peak slip,
hence the target slip, stays; the adhesion bound, hence `distance_ratio`, follows the scaled
peak.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from typing import Any

from chassistune.scenarios.base import Scenario
from chassistune.scenarios.registry import get_plant, plant_spec
from chassistune.tuning.robust.spec import ParamRange

NOT_UNCERTAIN = frozenset(
    {
        "dt_s",
        "t_max_s",
        "v_stop_m_s",
        "lock_ratio",
        "load_fraction",
        "duration_s",
        "n0_cycles_per_m",
    }
)
"""Solver settings, thresholds and model conventions: not physical uncertainties."""


def field_range(f: dataclasses.Field[Any]) -> ParamRange:
    """A dataclass field's valid range from its metadata (an open interval, when it states one,
    before its sign)."""
    if "open_interval" in f.metadata:
        lo, hi = f.metadata["open_interval"]
        return ParamRange(lo, hi, lo_open=True, hi_open=True)
    if f.metadata.get("positive"):
        return ParamRange(0.0, math.inf, lo_open=True)
    if f.metadata.get("nonnegative"):
        return ParamRange(0.0, math.inf)
    if f.metadata.get("unit_interval"):
        return ParamRange(0.0, 1.0)
    return ParamRange()


def ranges_of(obj: Any) -> dict[str, ParamRange]:
    """Valid ranges of a parameter dataclass's float fields (minus the NOT_UNCERTAIN ones)."""
    return {
        f.name: field_range(f)
        for f in dataclasses.fields(obj)
        if f.name not in NOT_UNCERTAIN and isinstance(getattr(obj, f.name), float)
    }


def known_ranges(scenario: Scenario) -> dict[str, ParamRange]:
    """Parameters of this scenario's plant, road and actuator that may vary, with valid ranges:
    the fields of the parameter dataclasses its plant's spec names (`PlantSpec.varied`), then
    its positive scale factors (`PlantSpec.varied_scales`)."""
    spec = plant_spec(scenario.plant)
    if not spec.varied:
        raise ValueError(f"no uncertain parameters declared for plant {scenario.plant!r}")
    out: dict[str, ParamRange] = {}
    for attribute in spec.varied:
        out.update(ranges_of(getattr(scenario, attribute)))
    out.update({name: ParamRange(0.0, math.inf, lo_open=True) for name in spec.varied_scales})
    return out


def scenario_builder(
    nominal: Scenario, base: Mapping[str, object]
) -> Callable[[Mapping[str, float]], Scenario]:
    """draw -> the nominal scenario (same plant, preset, road, controller, seed) at the draw."""
    plant = get_plant(nominal.plant)

    def build(draw: Mapping[str, float]) -> Scenario:
        return plant.scenario(
            nominal.preset, nominal.road, nominal.controller.name, {**base, **draw}, nominal.seed
        )

    return build
