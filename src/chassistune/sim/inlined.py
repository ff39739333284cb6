"""How the vehicle kernel's helpers compile: each a function of its own that LLVM inlines into
its callers (numba's `forceinline`: LLVM's alwaysinline), so that the vector loops still see
straight-line code. numba's own inlining (inline="always") copies and re-types a helper's IR at
every call site, nested helpers at every call site of their callers: most of the kernel's
compile time."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

from numba.extending import register_jitable

INLINE: dict[str, Any] = {
    "cache": True,
    "nogil": True,
    "error_model": "numpy",
    "forceinline": True,
    "_nrt": False,
}
"""numba options of a helper LLVM inlines: without numba's runtime, as the kernel's entry point
(`abs_vehicle_lane.NO_REFCOUNT`), whichever caller compiles it first, Python included
(`forceinline` and `_nrt` are not in numba's type stubs)."""

INDEXING: dict[str, Any] = {
    "cache": True,
    "nogil": True,
    "error_model": "numpy",
    "inline": "always",
}
"""numba options of a helper that indexes a lane's rows by an argument (a row, a wheel): numba
inlines it, so that the row is a constant wherever LLVM optimizes a function alone; a helper
optimized with the row unknown keeps the index's check for a negative value (numba's
wraparound), which LLVM can no longer drop once inlined: the vector loop would not vectorize."""

F = TypeVar("F", bound=Callable[..., Any])


def inlined(fn: F) -> F:
    """`fn` in compiled code as a call LLVM inlines, typed once per argument types: a constant
    argument (a row, a wheel's index, a flag) is not a literal of its own, which would compile a
    copy per value (`numba.njit(**INLINE)` where a helper needs its literal: the key of a
    continuous form). Still a Python function."""
    return register_jitable(**INLINE)(fn)
