"""Plants by name. Modules are imported on first use so that the CLI starts fast."""

from __future__ import annotations

import importlib

from chassistune.errors import InputError
from chassistune.plants.base import Plant

_MODULES: dict[str, str] = {
    "abs-wheel": "chassistune.plants.abs_wheel",
    "abs-vehicle": "chassistune.scenarios.abs_vehicle",
    "quarter-car": "chassistune.plants.quarter_car",
}


def plant_names() -> list[str]:
    return list(_MODULES)


def get_plant(name: str) -> Plant:
    """The plant `name` (its module's `PLANT`), or InputError listing the known ones."""
    if name not in _MODULES:
        raise InputError("plant", f"unknown plant {name!r} (known: {', '.join(_MODULES)})")
    plant: Plant = importlib.import_module(_MODULES[name]).PLANT
    return plant
