"""Branch-free scalar selects for compiled loops that must vectorize.

numba lowers `a if c else b` and chains of `min`/`max` to control flow that LLVM's loop
vectorizer may refuse; these helpers emit one LLVM `select` each, so a loop body built from them
stays straight-line. `fmax` and `fmin` reproduce numba's built-in `max`/`min` on two floats bit
for bit (NaN and signed-zero cases included): max(a, b) is `b if b > a else a`, min(a, b) is
`b if b < a else a`. Combine conditions with `&` and `|` (not `and`/`or`, which short-circuit).
"""

from __future__ import annotations

from numba import njit, types
from numba.extending import intrinsic


@intrinsic
def _llvm_select(typingctx, cond, a, b):
    sig = types.float64(types.boolean, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        return builder.select(args[0], args[1], args[2])

    return sig, codegen


@njit(cache=True, nogil=True, inline="always")
def select(cond: bool, a: float, b: float) -> float:  # pragma: no cover - compiled
    """`a if cond else b` for floats, as one LLVM select (both sides are evaluated)."""
    return _llvm_select(cond, a, b)  # type: ignore[call-arg]


@njit(cache=True, nogil=True, inline="always")
def fmax(a: float, b: float) -> float:  # pragma: no cover - compiled
    """numba's max(a, b) on floats: b if b > a else a."""
    return select(b > a, b, a)


@njit(cache=True, nogil=True, inline="always")
def fmin(a: float, b: float) -> float:  # pragma: no cover - compiled
    """numba's min(a, b) on floats: b if b < a else a."""
    return select(b < a, b, a)


@njit(cache=True, nogil=True, inline="always")
def clip(x: float, lo: float, hi: float) -> float:  # pragma: no cover - compiled
    """min(max(x, lo), hi), bit for bit."""
    return fmin(fmax(x, lo), hi)
