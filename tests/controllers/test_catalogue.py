"""The one controller catalogue: every plant's controllers, keyed by (plant, controller)."""

from __future__ import annotations

import pytest

from chassistune.controllers import catalogue
from chassistune.controllers.specs import ControllerSpec
from chassistune.errors import InputError
from chassistune.scenarios.registry import get_plant, plant_names


@pytest.mark.parametrize("plant", plant_names())
def test_every_plant_accepts_exactly_its_catalogue_entries(plant: str) -> None:
    specs = catalogue.for_plant(plant)
    assert specs and get_plant(plant).controllers() == specs
    for spec in specs:
        assert spec.plant == plant and catalogue.get(plant, spec.name) is spec
        assert all(g.lo < g.hi for g in spec.gains)


def test_same_name_different_plants_are_different_entries() -> None:
    abs_pid, qc_pid = catalogue.get("abs-wheel", "pid"), catalogue.get("quarter-car", "pid")
    assert abs_pid is not qc_pid and abs_pid.bounds() != qc_pid.bounds()


def test_unknown_controller_lists_the_plants_controllers() -> None:
    with pytest.raises(InputError) as err:
        catalogue.get("quarter-car", "lqr")
    assert err.value.field == "controller"
    assert err.value.problem == (
        "unknown controller 'lqr' for plant 'quarter-car' (known: passive, pid, skyhook)"
    )
    with pytest.raises(InputError, match="for plant 'half-car' \\(known: none\\)"):
        catalogue.get("half-car", "pid")


def test_a_pair_is_registered_once() -> None:
    with pytest.raises(ValueError, match="registered already"):
        catalogue.register(ControllerSpec("abs-wheel", "pid", "a second PID"))
