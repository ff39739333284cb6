"""The ABS control laws, one module per law (design.md 4), each a `Law` of `registry`.

The built-in laws are registered here, in this order (a law's kind is its position); a new law
is one module whose `LAW` is registered with `registry.register` (a test law registers itself).
"""

from __future__ import annotations

from chassistune.controllers.laws import (
    adrc,
    bang_bang,
    extremum_seeking,
    fuzzy_immune_pid,
    fuzzy_pid,
    mixed_slip_deceleration,
    mpc,
    none,
    pid,
    sliding_mode,
    threshold,
)
from chassistune.controllers.laws.registry import (
    ABS_VEHICLE,
    ABS_WHEEL,
    CForm,
    ContinuousForm,
    DiscreteLaw,
    EcuForm,
    Law,
    by_kind,
    for_plant,
    get,
    kind,
    names,
    register,
    unregister,
)

for _module in (
    none,
    pid,
    bang_bang,
    threshold,
    fuzzy_pid,
    fuzzy_immune_pid,
    sliding_mode,
    mixed_slip_deceleration,
    adrc,
    extremum_seeking,
    mpc,
):
    register(_module.LAW)

__all__ = [
    "ABS_VEHICLE",
    "ABS_WHEEL",
    "CForm",
    "ContinuousForm",
    "DiscreteLaw",
    "EcuForm",
    "Law",
    "by_kind",
    "for_plant",
    "get",
    "kind",
    "names",
    "register",
    "unregister",
]
