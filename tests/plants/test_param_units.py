"""One unit per parameter: a plant parameter that a kernel's layout also declares carries the
same unit in both (the `list params` unit of its dataclass field, the layout's slot unit)."""

from __future__ import annotations

import dataclasses

import pytest

from chassistune.export.closed_loop import LOOP
from chassistune.layout import Layout
from chassistune.params import unit_of
from chassistune.plants.abs_vehicle_params import SteeringParams, VehicleParams
from chassistune.plants.abs_wheel import AbsWheelParams
from chassistune.sim.abs_vehicle_layout import PLANT_LAYOUT
from chassistune.sim.abs_wheel_layout import PLANT
from chassistune.units import PRESSURE

PAIRS = [
    (AbsWheelParams, PLANT),
    (AbsWheelParams, LOOP),
    (VehicleParams, PLANT_LAYOUT),
    (SteeringParams, PLANT_LAYOUT),
]


@pytest.mark.parametrize(("params", "layout"), PAIRS, ids=lambda x: getattr(x, "__name__", ""))
def test_a_parameter_has_one_unit_in_its_dataclass_and_its_layouts(
    params: type, layout: Layout
) -> None:
    units = layout.units
    shared = [f for f in dataclasses.fields(params) if f.name in units]
    assert shared
    assert {f.name: unit_of(f) for f in shared} == {f.name: units[f.name] for f in shared}


def test_the_actuator_gain_is_a_pressure_rate_per_unit_command() -> None:
    """T dr/dt = K u - r with a dimensionless command u: K is in pressure units per second."""
    for params in (AbsWheelParams, VehicleParams):
        (gain,) = [f for f in dataclasses.fields(params) if f.name == "actuator_gain"]
        assert unit_of(gain) == f"{PRESSURE}/s"
