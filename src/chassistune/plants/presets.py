"""What a plant's preset says about itself: its name, a description and the roads of its paper."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class PresetInfo:
    """A named parameter set of a plant, with the roads of its paper (first = default)."""

    name: str
    description: str
    roads: tuple[str, ...]
