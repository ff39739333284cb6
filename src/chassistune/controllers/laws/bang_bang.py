"""Bang-bang ABS (sldemo's controller, design.md 4): u = amplitude sign(S_target - S), sampled
every ts_s (`controllers.switching.bang_bang_command`). Single wheel only; no discrete ECU form."""

from __future__ import annotations

from numba import njit

from chassistune.controllers.laws.forms import FORM, H_KD, H_KI, H_KP, P_AMPLITUDE, SIG_SLIP_ERROR
from chassistune.controllers.laws.registry import ABS_WHEEL, Law
from chassistune.controllers.laws.shared import AMPLITUDE, SAMPLE_PERIOD
from chassistune.controllers.specs import ControllerSpec
from chassistune.controllers.switching import bang_bang_command


@njit(**FORM)
def start(g, g0, c):
    """Nothing held before the first sample; no gains."""
    return 0.0, 0.0, 0.0, 0.0


@njit(**FORM)
def tick(sig, held, mem, g, g0, c, table, ts, first):
    """u0 = amplitude sign(e) (`controllers.switching.bang_bang_command`)."""
    u0 = bang_bang_command(sig[SIG_SLIP_ERROR], c[P_AMPLITUDE])
    return (u0, held[H_KP], held[H_KI], held[H_KD]), mem


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
    start,
    tick,
)
