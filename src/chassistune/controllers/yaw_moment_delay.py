"""Yaw-moment build-up delay (GMA, "Giermomentaufbauverzoegerung"): the production ABS feature for
split-mu braking (Reif (ed.), "Brakes, Brake Control and Driver Assistance Systems", Bosch
Professional Automotive Information, Springer Vieweg 2014, the ABS chapter on split-mu: the
high-mu front wheel's pressure is built up with a delay, so that the yaw moment of the unequal
brake forces grows slowly enough for the driver to counter-steer). Our model of it, an option of
every law on the 7-DOF vehicle (`--param yaw_moment_delay=on`): at the end of each step the two
front pressures may differ by at most

    |q_fl - q_fr| <= r_gma q_max t,

the higher one held at the lower one plus that bound (as the inlet valve holding it would),
with r_gma [1/s] the gain `yaw_moment_rate_1_s`, tuned with the law's. The bound grows from 0
at the start of braking; on a road that brakes both front wheels alike it never binds.
"""

from __future__ import annotations

from dataclasses import replace

from chassistune.controllers.specs import ControllerSpec, GainSpec

FIELD = "yaw_moment_delay"
CHOICES = ("off", "on")

RATE_GAIN = GainSpec(
    "yaw_moment_rate_1_s",
    "1/s",
    2.0,
    0.2,
    20.0,
    "r_gma: the front pressures' largest difference grows at r_gma q_max per second",
)


def controller_spec(spec: ControllerSpec, on: bool) -> ControllerSpec:
    """The law's spec with `RATE_GAIN` as a gain when the delay is on."""
    return replace(spec, gains=(*spec.gains, RATE_GAIN)) if on else spec
