"""Controllers of the quarter-car active suspension, with their gains and bounds (DESIGN 3.4, 4).

Force u acts + on the body and - on the wheel; e = 0 - y. Gain units are those of the default
feedback y = body vertical velocity (then kp is a sky-hook damper, ki a sky spring since
int(vs) = zs, kd a sky inertance with the filter N s/(s + N)). The bounds span the forces an
active suspension actuator delivers: on an ISO class B road at 20 m/s the passive body velocity,
displacement and acceleration have RMS of about 0.05-0.07 m/s, 0.015 m and 0.6-1.7 m/s^2,
so the upper bounds give about 0.5-1.5 kN RMS there and 4x that on class D; every optimum we
found for either preset lies well inside. For other feedback signals the units change (see
docs/suspension.md); seed 001 tuned all three gains on [0, 500] (PAPER_BOX).
"""

from __future__ import annotations

from chassistune.controllers.registry import (
    ControllerSpec,
    GainSpec,
    ParamSpec,
    for_plant,
    register,
)
from chassistune.controllers.registry import get as _get

PLANT = "quarter-car"

PAPER_BOX: tuple[tuple[float, float], ...] = ((0.0, 500.0),) * 3
"""Seed 001 section 4.2: kp, ki, kd in [0, 500]."""

FEEDBACK = ParamSpec(
    "feedback", "-", "body_velocity",
    "signal y of e = 0 - y",
    choices=("body_velocity", "body_displacement", "body_acceleration", "suspension_travel"),
)
N_FILTER = ParamSpec(
    "n_filter", "rad/s", 100.0,
    "derivative filter coefficient N: kd N s / (s + N) acts on e (Simulink's PID default)",
    positive=True,
)

register(ControllerSpec(PLANT, "passive", "passive suspension: spring and damper only, u = 0"))
register(ControllerSpec(
    PLANT, "pid",
    "PID on e = 0 - y, u = kp e + ki int(e) + kd N s/(s + N) e, + on the body, - on the wheel "
    "(seed 001 eq. 4 with the stabilizing sign); units for feedback=body_velocity",
    gains=(
        GainSpec("kp", "N s/m", 500.0, 0.0, 1e4, "proportional gain (sky-hook damping on "
                 "body velocity)"),
        GainSpec("ki", "N/m", 500.0, 0.0, 1e5, "integral gain (sky spring: int(vs) = zs)"),
        GainSpec("kd", "N s^2/m", 100.0, 0.0, 1e3, "derivative gain (sky inertance, kg)"),
    ),
    params=(FEEDBACK, N_FILTER),
))
register(ControllerSpec(
    PLANT, "skyhook",
    "classic sky-hook damper u = -c_sky zs' (body absolute velocity), beside the passive damper",
    gains=(GainSpec("c_sky", "N s/m", 1000.0, 0.0, 1e4, "sky-hook damping coefficient"),),
))


def get(name: str) -> ControllerSpec:
    """The quarter-car controller `name` (`none` is read as `passive`), or InputError."""
    return _get(PLANT, "passive" if name == "none" else name)


def names() -> list[str]:
    """Controller names of the quarter car, in registration order."""
    return [s.name for s in for_plant(PLANT)]
