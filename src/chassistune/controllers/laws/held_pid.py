"""The continuous form of every law that declares none (`registry.Law.continuous`): the PID of
`controllers.pid` (design.md 4) on the held values (u0, kp, ki, kd) of `forms.HELD`, which the
PID keeps fixed for a run and a sampled law sets at each sample (u0, with zero gains).
"""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws.forms import FORM
from chassistune.controllers.laws.registry import ContinuousForm


@functools.cache
def held_pid_forms() -> tuple[Any, Any]:
    """(initial, rate) of the continuous PID (`controllers.pid.pid_step`) with the held values
    (u0, kp, ki, kd): the filter state starts at e(0), so that the derivative does not kick."""
    from numba import njit

    from chassistune.controllers.pid import pid_step

    @njit(**FORM)
    def initial(target):
        return 0.0, target

    @njit(**FORM)
    def rate(e, x, held, c, n_filter, at_max, at_min):
        z, xf = x
        u0, kp, ki, kd = held
        u, dz, dxf = pid_step(e, z, xf, u0, kp, ki, kd, n_filter, at_max, at_min)
        return u, (dz, dxf)

    return initial, rate


HELD_PID = ContinuousForm(("z", "xf"), held_pid_forms)
"""The held PID's state: the integral z of the slip error and the derivative filter xf."""
