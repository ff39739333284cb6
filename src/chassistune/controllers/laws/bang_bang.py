"""Bang-bang ABS (sldemo's controller, design.md 4): u = amplitude sign(S_target - S), sampled
every ts_s (`controllers.switching.bang_bang_command`). Single wheel only; in the
realistic ECU the same command of the ECU's slip, not exported (no discrete form)."""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws.forms import FORM, H_KD, H_KI, H_KP, P_AMPLITUDE, SIG_SLIP_ERROR
from chassistune.controllers.laws.registry import ABS_WHEEL, EcuForm, Law
from chassistune.controllers.laws.shared import AMPLITUDE, SAMPLE_PERIOD
from chassistune.controllers.specs import ControllerSpec


@functools.cache
def kernel_forms() -> tuple[Any, Any]:
    """(start, tick) for the kernels: at rest; u0 = amplitude sign(e) at each sample
    (`controllers.switching.bang_bang_command`)."""
    from numba import njit

    from chassistune.controllers.switching import bang_bang_command

    @njit(**FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):
        u0 = bang_bang_command(sig[SIG_SLIP_ERROR], c[P_AMPLITUDE])
        return (u0, held[H_KP], held[H_KI], held[H_KD]), mem

    return None, tick


@functools.cache
def ecu_step() -> Any:
    """The law's step in the realistic ECU: u = amplitude sign(S_target - S) of its inputs
    (slip, target_slip, amplitude)."""
    from numba import njit

    from chassistune.controllers.switching import bang_bang_command

    @njit(**FORM)
    def step(state, inputs, params, table, grid):
        return bang_bang_command(inputs[1] - inputs[0], inputs[2])

    return step


LAW = Law(
    "bang-bang",
    (
        ControllerSpec(
            ABS_WHEEL,
            "bang-bang",
            "sldemo's controller: u = amplitude * sign(S_target - S), sampled every ts_s",
            params=(AMPLITUDE, SAMPLE_PERIOD),
        ),
    ),
    kernel_forms,
    ecu=EcuForm(ecu_step, inputs=("slip", "target_slip", "amplitude")),
    source="MathWorks' Simulink ABS example sldemo_absbrake",
)
