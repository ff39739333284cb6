"""A plant's presets: what one says about itself (its name, a description and the roads of its
paper) and the parameter set it names."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Generic, TypeVar

P = TypeVar("P")


@dataclass(frozen=True)
class PresetInfo:
    """A named parameter set of a plant, with the roads of its paper (first = default) and,
    for a braking plant, the unit its brake pressures are in (kPa, or its source's unit)."""

    name: str
    description: str
    roads: tuple[str, ...]
    pressure_unit: str = ""


@dataclass(frozen=True)
class Preset(Generic[P]):
    """A named parameter set of a plant, with controller parameter defaults that belong to it."""

    info: PresetInfo
    params: P
    controller_defaults: Mapping[str, float] = field(default_factory=dict)
