"""No ABS: the driver's pressure command ramps the brake to q_max and holds it (design.md 4)."""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws.forms import FORM, P_AMPLITUDE
from chassistune.controllers.laws.registry import ABS_VEHICLE, ABS_WHEEL, EcuForm, Law
from chassistune.controllers.laws.shared import AMPLITUDE
from chassistune.controllers.specs import ControllerSpec

WHEEL = ControllerSpec(
    ABS_WHEEL,
    "none",
    "no ABS: the driver's pressure ramps to q_max and holds",
    params=(AMPLITUDE,),
)


@functools.cache
def kernel_forms() -> tuple[Any, Any]:
    """(start, tick) for the kernels: the driver's constant command, held for the whole run; no
    gains, no tick."""
    from numba import njit

    from chassistune.controllers.switching import no_abs_command

    @njit(**FORM)
    def start(g, g0, c):
        return no_abs_command(c[P_AMPLITUDE]), 0.0, 0.0, 0.0

    return start, None


@functools.cache
def ecu_step() -> Any:
    """The law's step in the realistic ECU: the driver's command, its input (amplitude)."""
    from numba import njit

    from chassistune.controllers.switching import no_abs_command

    @njit(**FORM)
    def step(state, inputs, params, table, grid):
        return no_abs_command(inputs[0])

    return step


LAW = Law(
    "none",
    (
        WHEEL,
        ControllerSpec(
            ABS_VEHICLE, "none", WHEEL.description + " (all four wheels)", params=(AMPLITUDE,)
        ),
    ),
    kernel_forms,
    ecu=EcuForm(ecu_step, inputs=("amplitude",)),
    source="no ABS: the driver alone (design.md 3.1)",
    needs_target=False,
)
