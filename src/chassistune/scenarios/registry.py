"""Plants by name: their specs (light, listed without importing any kernel) and their scenario
builders (imported on first use so that the CLI starts fast).

The built-in plants are listed here, explicitly; `register()` adds another (a test's toy plant,
a user's model) under the same rules: a name once, its builder as an object or "module:attr".
"""

from __future__ import annotations

from chassistune._registry import Registry
from chassistune.plants.presets import PresetInfo
from chassistune.scenarios.base import Plant, PlantSpec

ABS_KEY_METRICS = ("stop_distance_m", "distance_ratio", "stop_time_s", "slip_itae", "locked_time_s")
"""The metrics reported for both ABS plants (the single wheel and the 7-DOF vehicle)."""

ABS_WHEEL = PlantSpec(
    name="abs-wheel",
    version=1,
    description="single-wheel (quarter-car) ABS: bilinear/Burckhardt tire, K/(s(Ts+1)) brake",
    default_preset="paper-derlsp-ao",
    key_metrics=ABS_KEY_METRICS,
    plot="chassistune.plots.abs_wheel:plot_trace",
    presets="chassistune.plants.abs_wheel:PRESETS",
    roads="chassistune.plants.roads:friction_roads",
)
ABS_VEHICLE = PlantSpec(
    name="abs-vehicle",
    version=1,
    description="7-DOF vehicle ABS (deffao-vehicle-abs): four braked wheels, load transfer, "
    "combined-slip tires, uniform, mu-jump and split-mu roads, optional driver",
    default_preset="paper-deffao",
    key_metrics=ABS_KEY_METRICS,
    plot="chassistune.plots.abs_vehicle:plot_trace",
    presets="chassistune.plants.abs_vehicle_params:PRESETS",
    roads="chassistune.plants.vehicle_roads:road_names",
)
QUARTER_CAR = PlantSpec(
    name="quarter-car",
    version=1,
    description="2-DOF quarter-car active suspension on an ISO 8608 random road "
    "(Jing and Xu 2023, iabc-suspension)",
    default_preset="paper-iabc",
    key_metrics=(
        "objective_exact",
        "body_acc_rms",
        "susp_travel_rms",
        "tire_defl_rms",
        "force_rms",
    ),
    plot="chassistune.plots.quarter_car:plot_trace",
    presets="chassistune.plants.quarter_car_params:PRESETS",
    roads="chassistune.plants.roads:roughness_roads",
)

SPECS: Registry[PlantSpec] = Registry("plant")
BUILDERS: Registry[Plant] = Registry("plant")


def register(spec: PlantSpec, builder: Plant | str) -> None:
    """Add a plant: its spec and its scenario builder (a Plant, or "module:attr" of one)."""
    if spec.name in SPECS:
        raise ValueError(f"plant {spec.name!r} is registered already")
    SPECS.register(spec.name, spec)
    BUILDERS.register(spec.name, builder)


def unregister(name: str) -> None:
    """Remove a plant (tests that register a temporary one clean up with it)."""
    SPECS.unregister(name)
    BUILDERS.unregister(name)


register(ABS_WHEEL, "chassistune.scenarios.abs_wheel:PLANT")
register(QUARTER_CAR, "chassistune.scenarios.quarter_car:PLANT")
register(ABS_VEHICLE, "chassistune.scenarios.abs_vehicle:PLANT")


def plant_names() -> list[str]:
    return SPECS.names()


def plant_spec(name: str) -> PlantSpec:
    """The spec of plant `name`, or InputError listing the known plants (imports no kernel)."""
    return SPECS.get(name)


def plant_presets(name: str) -> dict[str, PresetInfo]:
    """The presets of plant `name` by name: from its spec when it declares them (no kernel is
    imported), else from its builder."""
    spec = plant_spec(name)
    return spec.preset_infos() if spec.presets else get_plant(name).presets()


def plant_roads(name: str) -> dict[str, str]:
    """Road name -> description for plant `name`: from its spec when it declares them, else from
    its builder."""
    spec = plant_spec(name)
    return spec.road_descriptions() if spec.roads else get_plant(name).roads()


def get_plant(name: str) -> Plant:
    """The scenario builder of plant `name`, or InputError listing the known plants."""
    return BUILDERS.get(name)
