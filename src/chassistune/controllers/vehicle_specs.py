"""Wheel controllers of the vehicle ABS (`abs-vehicle`, design.md 3.3, 4): gains, bounds, defaults.

The laws are the single wheel's, one per wheel on the slip error of the surface under it; one gain
set is shared by the four wheels (as Tian 2025 tunes it) unless `axle_gains = "per-axle"`, which
doubles every gain into a front (`_f`) and a rear (`_r`) copy.

Vehicle defaults of their own. With J = 0.6 kg m^2 the rear wheels carry about 1230 N while
braking: the single wheel's PID 5000/0/230 makes them lock-cycle (mu-jump 98.35 m, no better than
no ABS), so the vehicle PID defaults to kp 1200, ki 0, kd 20 (design.md 3.3). The fuzzy PID's
defaults are rescaled the same way: its gains span kp0 + [0, 1] ku_p (deffao outputs are
magnitudes in [0, 1]), centred on the vehicle PID: kp in [700, 1700], kd in [15, 25], ki 0.
"""

from __future__ import annotations

import dataclasses

from chassistune.controllers.catalogue import ABS_WHEEL, AMPLITUDE, for_plant, register
from chassistune.controllers.catalogue import get as _get
from chassistune.controllers.specs import ControllerSpec, GainSpec, ParamSpec

PLANT = "abs-vehicle"

AXLE_GAINS = ParamSpec(
    "axle_gains",
    "-",
    "shared",
    "one gain set for the four wheels, or one per axle (_f, _r)",
    choices=("shared", "per-axle"),
)
REAR = ParamSpec(
    "rear",
    "-",
    "individual",
    "rear axle: individual wheel channels, or select-low (one channel on the "
    "larger-slip wheel, both rear brakes at the same pressure)",
    choices=("individual", "select-low"),
)
VEHICLE_PARAMS = (AXLE_GAINS, REAR)

PID_GAINS = (
    GainSpec(
        "kp",
        "1/(slip)",
        1200.0,
        0.0,
        5000.0,
        "proportional gain (an integral gain on pressure: the actuator integrates)",
    ),
    GainSpec("ki", "1/(slip s)", 0.0, 0.0, 5000.0, "integral gain"),
    GainSpec(
        "kd", "s/(slip)", 20.0, 0.0, 100.0, "derivative gain (a proportional gain on pressure)"
    ),
)
FUZZY_DEFAULTS = {"ku_p": 1000.0, "ku_i": 0.0, "ku_d": 10.0, "kp0": 700.0, "ki0": 0.0, "kd0": 15.0}
FUZZY_BOUNDS = {
    "ku_p": (0.0, 5000.0),
    "ku_i": (0.0, 5000.0),
    "ku_d": (0.0, 100.0),
    "kp0": (0.0, 5000.0),
    "ki0": (0.0, 5000.0),
    "kd0": (0.0, 100.0),
}


def _rescaled(spec: ControllerSpec) -> tuple[GainSpec, ...]:
    """The single wheel's fuzzy PID gains with the vehicle's defaults and bounds."""
    out = []
    for g in spec.gains:
        if g.name in FUZZY_DEFAULTS:
            lo, hi = FUZZY_BOUNDS[g.name]
            g = dataclasses.replace(g, default=FUZZY_DEFAULTS[g.name], lo=lo, hi=hi)
        out.append(g)
    return tuple(out)


def wheel_spec(name: str) -> ControllerSpec:
    """The single wheel's controller `name`, which the vehicle's law repeats per wheel."""
    return _get(ABS_WHEEL, name)


def _register() -> None:
    none = wheel_spec("none")
    register(
        ControllerSpec(PLANT, "none", none.description + " (all four wheels)", params=(AMPLITUDE,))
    )
    pid = wheel_spec("pid")
    register(
        ControllerSpec(
            PLANT,
            "pid",
            pid.description + "; one law per wheel",
            gains=PID_GAINS,
            params=pid.params + VEHICLE_PARAMS,
        )
    )
    fuzzy = wheel_spec("fuzzy-pid")
    register(
        ControllerSpec(
            PLANT,
            "fuzzy-pid",
            fuzzy.description + "; one law per wheel",
            gains=_rescaled(fuzzy),
            params=fuzzy.params + VEHICLE_PARAMS,
        )
    )
    threshold = wheel_spec("threshold")
    register(
        ControllerSpec(
            PLANT,
            "threshold",
            threshold.description + "; one law per wheel",
            params=(*threshold.params, REAR),
        )
    )


_register()


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
