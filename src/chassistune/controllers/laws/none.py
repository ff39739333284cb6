"""No ABS: the driver's pressure command ramps the brake to q_max and holds it (design.md 4)."""

from __future__ import annotations

from numba import njit

from chassistune.controllers.laws.forms import FORM, P_AMPLITUDE
from chassistune.controllers.laws.registry import ABS_VEHICLE, ABS_WHEEL, Law
from chassistune.controllers.laws.shared import AMPLITUDE
from chassistune.controllers.specs import ControllerSpec
from chassistune.controllers.switching import no_abs_command

WHEEL = ControllerSpec(
    ABS_WHEEL,
    "none",
    "no ABS: the driver's pressure ramps to q_max and holds",
    params=(AMPLITUDE,),
)


@njit(**FORM)
def start(g, g0, c):
    """The driver's constant command, held for the whole run; no gains."""
    return no_abs_command(c[P_AMPLITUDE]), 0.0, 0.0, 0.0


LAW = Law(
    "none",
    (
        WHEEL,
        ControllerSpec(
            ABS_VEHICLE, "none", WHEEL.description + " (all four wheels)", params=(AMPLITUDE,)
        ),
    ),
    start,
)
