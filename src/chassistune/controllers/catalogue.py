"""The one catalogue of controllers, keyed by (plant, controller): gains, units, defaults, bounds.

`chassistune list controllers --json`, `--gains`, `tune`, study configs and exported tables all
read it. The ABS PID and the suspension PID share a name, not their bounds. The ABS plants'
entries (abs-wheel, abs-vehicle) are the specs of the control laws (`controllers.laws`, one
module per law, a view of its registry); the quarter-car entries are listed below, explicitly:
they command a force from body signals, not a brake from slip, and share none of the laws'
forms. `register()` adds another quarter-car entry under the same rules.

quarter-car (design.md 3.4, 4): force u acts + on the body and - on the wheel; e = 0 - y. Gain units
are those of the default feedback y = body vertical velocity (then kp is a sky-hook damper, ki a sky
spring since int(vs) = zs, kd a sky inertance with the filter N s/(s + N)). The bounds span the
forces an active suspension actuator delivers: on an ISO class B road at 20 m/s the passive body
velocity, displacement and acceleration have RMS of about 0.05-0.07 m/s, 0.015 m and 0.6-1.7 m/s^2,
so the upper bounds give about 0.5-1.5 kN RMS there and 4x that on class D; every optimum we found
for either preset lies well inside. For other feedback signals the units change (see
docs/suspension.md); Jing and Xu 2023 (iabc-suspension) tuned all three gains on [0, 500]
(PAPER_BOX).
"""

from __future__ import annotations

from chassistune._registry import Registry
from chassistune.controllers import laws
from chassistune.controllers.specs import ControllerSpec, GainSpec, ParamSpec

ABS_WHEEL = laws.ABS_WHEEL
QUARTER_CAR = "quarter-car"
LAW_PLANTS = (laws.ABS_WHEEL, laws.ABS_VEHICLE)
"""Plants whose controllers are the control laws' specs (`controllers.laws`)."""

_BY_PLANT: dict[str, Registry[ControllerSpec]] = {}


def register(spec: ControllerSpec) -> ControllerSpec:
    """Add a controller of `spec.plant`; registering the same (plant, name) twice is refused,
    and so is an ABS entry outside a law (an ABS controller is a law module)."""
    if spec.plant in LAW_PLANTS:
        taken = any(s.name == spec.name for s in laws.for_plant(spec.plant))
        raise ValueError(
            f"controller {spec.name!r} is registered already"
            if taken
            else f"a controller of {spec.plant} is a control law: register it in controllers.laws"
        )
    _BY_PLANT.setdefault(spec.plant, Registry("controller")).register(spec.name, spec)
    return spec


def _registry(plant: str) -> Registry[ControllerSpec]:
    if plant not in LAW_PLANTS:
        return _BY_PLANT.get(plant, Registry("controller"))
    view: Registry[ControllerSpec] = Registry("controller")
    for spec in laws.for_plant(plant):
        view.register(spec.name, spec)
    return view


def get(plant: str, name: str) -> ControllerSpec:
    """The controller `name` of `plant`, or InputError listing the plant's controllers."""
    return _registry(plant).get(name, f" for plant {plant!r}")


def for_plant(plant: str) -> list[ControllerSpec]:
    """All controllers of a plant, in catalogue order (kind order for the laws' plants)."""
    reg = _registry(plant)
    return [reg.get(n) for n in reg.names()]


# -- quarter-car -------------------------------------------------------------------------------

PAPER_BOX: tuple[tuple[float, float], ...] = ((0.0, 500.0),) * 3
"""Jing and Xu 2023 (iabc-suspension) section 4.2: kp, ki, kd in [0, 500]."""

FEEDBACK = ParamSpec(
    "feedback",
    "-",
    "body_velocity",
    "signal y of e = 0 - y",
    choices=("body_velocity", "body_displacement", "body_acceleration", "suspension_travel"),
)
N_FILTER = ParamSpec(
    "n_filter",
    "rad/s",
    100.0,
    "derivative filter coefficient N: kd N s / (s + N) acts on e (Simulink's PID default)",
    positive=True,
)

register(
    ControllerSpec(QUARTER_CAR, "passive", "passive suspension: spring and damper only, u = 0")
)
register(
    ControllerSpec(
        QUARTER_CAR,
        "pid",
        "PID on e = 0 - y, u = kp e + ki int(e) + kd N s/(s + N) e, + on the body, - on the wheel "
        "(iabc-suspension eq. 4 with the stabilizing sign); units for feedback=body_velocity",
        gains=(
            GainSpec(
                "kp",
                "N s/m",
                500.0,
                0.0,
                1e4,
                "proportional gain (sky-hook damping on body velocity)",
            ),
            GainSpec("ki", "N/m", 500.0, 0.0, 1e5, "integral gain (sky spring: int(vs) = zs)"),
            GainSpec("kd", "N s^2/m", 100.0, 0.0, 1e3, "derivative gain (sky inertance, kg)"),
        ),
        params=(FEEDBACK, N_FILTER),
    )
)
register(
    ControllerSpec(
        QUARTER_CAR,
        "skyhook",
        "classic sky-hook damper u = -c_sky zs' (body absolute velocity), beside the passive "
        "damper",
        gains=(GainSpec("c_sky", "N s/m", 1000.0, 0.0, 1e4, "sky-hook damping coefficient"),),
    )
)
