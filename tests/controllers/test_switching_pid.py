"""The PID and switching laws' step functions: their equations, limits and branch-free selects."""

from __future__ import annotations

import math

import numpy as np

from chassistune._branchfree import clip, fmax, fmin
from chassistune.controllers.pid import pid_step
from chassistune.controllers.switching import (
    PH_BUILD,
    PH_DUMP,
    PH_HOLD,
    PH_RECOVER,
    PH_SLOW,
    bang_bang_command,
    threshold_step,
)


def test_branch_free_min_max_are_numbas() -> None:
    values = [0.0, -0.0, 1.0, -2.5, math.inf, -math.inf, math.nan]
    for a in values:
        for b in values:
            assert np.float64(fmax(a, b)).tobytes() == np.float64(max(a, b)).tobytes()
            assert np.float64(fmin(a, b)).tobytes() == np.float64(min(a, b)).tobytes()
    assert clip(2.0, 0.0, 1.0) == 1.0 and clip(-1.0, 0.0, 1.0) == 0.0


def test_pid_command_and_conditional_integration() -> None:
    u, dz, dxf = pid_step(0.1, 0.2, 0.05, 1.0, 3.0, 5.0, 7.0, 100.0, False, False)
    assert u == 1.0 + 3.0 * 0.1 + 5.0 * 0.2 + 7.0 * 100.0 * (0.1 - 0.05)
    assert dz == 0.1 and dxf == 100.0 * (0.1 - 0.05)
    assert pid_step(0.1, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, True, False)[1] == 0.0  # at q_max
    assert pid_step(-0.1, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, True, False)[1] == -0.1  # unwinds
    assert pid_step(-0.1, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, False, True)[1] == 0.0  # at 0


def test_bang_bang_sign() -> None:
    assert [bang_bang_command(e, 2.0) for e in (0.1, -0.1, 0.0)] == [2.0, -2.0, 0.0]
    assert bang_bang_command(math.nan, 2.0) == 0.0


def test_threshold_phases() -> None:
    args = (0.2, 2.0, 15.0, 10.0, 0.05, 0.25)  # target, amplitude, decel, accel, margin, slow

    def step(phase: int, s: float, aw: float) -> tuple[float, int]:
        target, amp, dec, acc, margin, slow = args
        return threshold_step(phase, s, target, aw, amp, dec, acc, margin, slow)

    assert step(PH_BUILD, 0.1, -5.0) == (2.0, PH_BUILD)
    assert step(PH_BUILD, 0.1, -20.0) == (0.0, PH_HOLD)
    assert step(PH_HOLD, 0.3, -20.0) == (-2.0, PH_DUMP)
    assert step(PH_DUMP, 0.3, 1.0) == (0.0, PH_RECOVER)
    assert step(PH_RECOVER, 0.1, 5.0) == (0.5, PH_SLOW)
    assert step(PH_SLOW, 0.1, -20.0) == (0.0, PH_HOLD)
