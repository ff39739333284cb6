"""Parameters several ABS laws share, and the vehicle form of a single-wheel law's spec.

The vehicle ABS (`abs-vehicle`, design.md 3.3, 4) runs the single wheel's law once per wheel on
the slip error of the surface under it; one gain set is shared by the four wheels (as Tian 2025
tunes it) unless `axle_gains = "per-axle"`, which doubles every gain into a front (`_f`) and a
rear (`_r`) copy (`scenarios.abs_vehicle`).
"""

from __future__ import annotations

import dataclasses

from chassistune.controllers.laws.registry import ABS_VEHICLE
from chassistune.controllers.specs import ControllerSpec, GainSpec, ParamSpec

AMPLITUDE = ParamSpec(
    "amplitude",
    "-",
    None,
    "pressure command magnitude (rate K*amplitude); default reaches q_max in 0.15 s",
    positive=True,
)

SAMPLE_PERIOD = ParamSpec(
    "ts_s",
    "s",
    1e-3,
    "sample period of the switching law (rounded to whole integration steps, at least one)",
    positive=True,
)

N_FILTER = ParamSpec("n_filter", "rad/s", 100.0, "derivative filter coefficient N", positive=True)

RULEBASE_NOTE = "built-in rule base name or a TOML file (`chassistune fuzzy show NAME`)"

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


def per_wheel(
    wheel: ControllerSpec,
    gains: tuple[GainSpec, ...] | None = None,
    params: tuple[ParamSpec, ...] | None = None,
) -> ControllerSpec:
    """The vehicle's spec of a single-wheel law: one law per wheel, with the vehicle's own gains
    (default: the wheel's) and parameters (default: the wheel's and `VEHICLE_PARAMS`)."""
    return ControllerSpec(
        ABS_VEHICLE,
        wheel.name,
        wheel.description + "; one law per wheel",
        gains=wheel.gains if gains is None else gains,
        params=wheel.params + VEHICLE_PARAMS if params is None else params,
    )


def rescaled(
    gains: tuple[GainSpec, ...],
    defaults: dict[str, float],
    bounds: dict[str, tuple[float, float]],
) -> tuple[GainSpec, ...]:
    """`gains` with the defaults and bounds given by name (the others unchanged)."""
    return tuple(
        dataclasses.replace(g, default=defaults[g.name], lo=bounds[g.name][0], hi=bounds[g.name][1])
        if g.name in defaults
        else g
        for g in gains
    )
