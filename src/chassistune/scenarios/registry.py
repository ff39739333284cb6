"""Plants by name: their specs (light, listed without importing any kernel) and their scenario
builders (imported on first use so that the CLI starts fast).

The built-in plants are listed here, explicitly; `register()` adds another (a test's toy plant,
a user's model) under the same rules: a name once, its builder as an object or "module:attr".
"""

from __future__ import annotations

from chassistune._registry import Registry
from chassistune.plants.presets import PresetInfo
from chassistune.scenarios.base import Plant, PlantSpec
from chassistune.scenarios.report_view import Panel, PlantView

ABS_KEY_METRICS = ("stop_distance_m", "distance_ratio", "stop_time_s", "slip_itae", "locked_time_s")
"""The metrics reported for both ABS plants (the single wheel and the 7-DOF vehicle)."""


VEHICLE_LOCKED_TIME = "summed over the four wheels"
"""What the vehicle's `locked_time_s` is: each wheel's time locked while moving, added up (all
four locked for 1 s count 4 s)."""


def abs_view(*panels: Panel, locked_unit: str = "s") -> PlantView:
    """The reports' view of an ABS plant: `panels` beside the run without ABS, and the
    generalization matrices of stop distance over the bound and locked time (in
    `locked_unit`)."""
    return PlantView(
        baseline="none",
        baseline_label="no ABS",
        panels=panels,
        generalization_metrics=(
            ("distance_ratio", "stop distance / bound"),
            ("locked_time_s", f"locked time [{locked_unit}]"),
        ),
    )


ABS_WHEEL = PlantSpec(
    name="abs-wheel",
    version=1,
    description="single-wheel (quarter-car) ABS: bilinear/Burckhardt tire, K/(s(Ts+1)) brake",
    default_preset="paper-derlsp-ao",
    key_metrics=ABS_KEY_METRICS,
    plot="chassistune.plots.abs_wheel:plot_trace",
    presets="chassistune.plants.abs_wheel:PRESETS",
    roads="chassistune.plants.roads:friction_roads",
    view=abs_view(
        Panel("slip", "slip S [-]"),
        Panel("vehicle_speed_m_s", "vehicle speed v [m/s]"),
        Panel("brake_torque_n_m", "brake torque [N m]"),
        Panel("distance_m", "distance [m]"),
    ),
    refinable=True,
    exportable=True,
    varied=("plant_params", "tire"),
)
ABS_VEHICLE = PlantSpec(
    name="abs-vehicle",
    version=1,
    description="7-DOF vehicle ABS (deffao-vehicle-abs): four braked wheels, load transfer, "
    "combined-slip tires, uniform, mu-jump and split-mu roads, optional driver",
    default_preset="paper-deffao",
    key_metrics=ABS_KEY_METRICS,
    plot="chassistune.plots.abs_vehicle:plot_trace",
    metric_notes=(("locked_time_s", VEHICLE_LOCKED_TIME),),
    presets="chassistune.plants.abs_vehicle_params:PRESETS",
    roads="chassistune.plants.vehicle_roads:road_names",
    view=abs_view(
        Panel("slip_fl", "front-left slip [-]"),
        Panel("speed_m_s", "vehicle speed v [m/s]"),
        Panel("yaw_rate_rad_s", "yaw rate [rad/s]"),
        Panel("distance_m", "distance [m]"),
        locked_unit=f"s, {VEHICLE_LOCKED_TIME}",
    ),
    refinable=True,
    export_refusal="its wheel laws with a discrete form ({laws}) run once per wheel, but the "
    "export records its test vectors in a single wheel's closed loop (`closed_loop`) and the "
    "vehicle has no discrete closed loop to record them in; export the single wheel "
    "(abs-wheel), whose law the vehicle repeats per wheel",
    varied=("plant_params",),
    varied_scales=("mu_scale",),
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
    view=PlantView(
        baseline="passive",
        baseline_label="passive",
        panels=(
            Panel("body_acc_m_s2", "body acceleration [m/s^2]", "passive_body_acc_m_s2"),
            Panel("susp_travel_m", "suspension travel [m]", "passive_susp_travel_m"),
            Panel("tire_defl_m", "tire deflection [m]", "passive_tire_defl_m"),
        ),
        generalization_metrics=(
            ("body_acc_rms", "body acc. RMS [m/s^2]"),
            ("susp_travel_rms", "travel RMS [m]"),
        ),
        window_s=5.0,
    ),
    varied=("vehicle", "road_params"),
)
"""Not `refinable`: its road is white noise drawn per step, so a finer step is another road (its
rms figures move by ~15 %), and its tuning objective, `rms-ratio-exact`, does not depend on the
step at all."""

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
