"""Wheel controllers of the vehicle ABS (`abs-vehicle`, design.md 3.3, 4): the `abs-vehicle`
specs of the control laws (`controllers.laws`, where each law declares its vehicle gains, bounds
and defaults), and their per-axle form.
"""

from __future__ import annotations

import dataclasses

from chassistune.controllers.catalogue import for_plant
from chassistune.controllers.catalogue import get as _get
from chassistune.controllers.laws import ABS_VEHICLE
from chassistune.controllers.specs import ControllerSpec

PLANT = ABS_VEHICLE


def per_axle(spec: ControllerSpec) -> ControllerSpec:
    """`spec` with every gain doubled into a front (_f) and a rear (_r) copy."""
    gains = tuple(
        dataclasses.replace(
            g, name=f"{g.name}{suffix}", description=f"{g.description} ({axle} axle)"
        )
        for suffix, axle in (("_f", "front"), ("_r", "rear"))
        for g in spec.gains
    )
    return dataclasses.replace(spec, gains=gains)


def get(name: str) -> ControllerSpec:
    """The abs-vehicle controller `name`."""
    return _get(PLANT, name)


def names() -> list[str]:
    return [s.name for s in for_plant(PLANT)]
