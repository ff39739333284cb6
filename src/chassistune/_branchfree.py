"""Branch-free scalar selects for compiled loops that must vectorize.

numba lowers `a if c else b` and chains of `min`/`max` to control flow that LLVM's loop
vectorizer may refuse; these helpers emit one LLVM `select` each, so a loop body built from them
stays straight-line. `fmax` and `fmin` reproduce numba's built-in `max`/`min` on two floats bit
for bit (NaN and signed-zero cases included): max(a, b) is `b if b > a else a`, min(a, b) is
`b if b < a else a`. Combine conditions with `&` and `|` (not `and`/`or`, which short-circuit).

`fma(a, b, c)` is a b + c rounded once (llvm.fma: vfmadd on x86 with FMA, the same number on
every CPU and in vector and scalar code alike); the kernels never let the compiler contract on
its own (no fastmath), so a fused operation appears only where it is written.

`add`, `mul` and `fmadd` are a + b, a b and a b + c on floats or, element by element, on tuples
of floats, nested or not (a float operand is used for every element): the state of a compiled
plant can then be one tuple and an integration stage one call, emitting the very `fadd`/`fmul`/
`llvm.fma` that the scalar expressions give (no reassociation: every number is what the scalar
code computes).

`select`, `fmax`, `fmin` and `clip` are calls, not inlined at numba's IR level (LLVM inlines
them: the same instructions), so that numba types and compiles each once instead of copying and
re-typing its IR at each of its many call sites in the kernels.
`stack_copy(t)` copies a tuple of floats to the stack and returns a pointer: `p[i]` with a
data-dependent i is then one load (a gather in a vector loop) from memory that the compiler knows
nothing else writes, where indexing the tuple itself compiles to a switch and indexing an
argument array may alias the loop's stores.
"""

from __future__ import annotations

from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic


@intrinsic
def _llvm_select(typingctx, cond, a, b):
    sig = types.float64(types.boolean, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        return builder.select(args[0], args[1], args[2])

    return sig, codegen


@njit(cache=True, nogil=True)
def select(cond: bool, a: float, b: float) -> float:  # pragma: no cover - compiled
    """`a if cond else b` for floats, as one LLVM select (both sides are evaluated)."""
    return _llvm_select(cond, a, b)  # type: ignore[call-arg]


@njit(cache=True, nogil=True)
def fmax(a: float, b: float) -> float:  # pragma: no cover - compiled
    """numba's max(a, b) on floats: b if b > a else a."""
    return select(b > a, b, a)


@njit(cache=True, nogil=True)
def fmin(a: float, b: float) -> float:  # pragma: no cover - compiled
    """numba's min(a, b) on floats: b if b < a else a."""
    return select(b < a, b, a)


@njit(cache=True, nogil=True)
def clip(x: float, lo: float, hi: float) -> float:  # pragma: no cover - compiled
    """min(max(x, lo), hi), bit for bit."""
    return fmin(fmax(x, lo), hi)


@intrinsic
def _stack_copy(typingctx, tup):
    if not (isinstance(tup, types.UniTuple) and tup.dtype == types.float64):
        return None
    sig = types.CPointer(types.float64)(tup)

    def codegen(context, builder, signature, args):
        slot = cgutils.alloca_once(builder, ir.ArrayType(ir.DoubleType(), tup.count))
        for i in range(tup.count):
            index = [ir.Constant(ir.IntType(32), 0), ir.Constant(ir.IntType(32), i)]
            ptr = builder.gep(slot, index)
            builder.store(builder.extract_value(args[0], i), ptr)
        return builder.bitcast(slot, ir.DoubleType().as_pointer())

    return sig, codegen


@njit(cache=True, nogil=True, inline="always")
def stack_copy(tup):  # pragma: no cover - compiled
    """A pointer to a stack copy of a tuple of float64 (valid in the calling kernel; call it
    once, outside loops: each call makes its own copy)."""
    return _stack_copy(tup)  # type: ignore[call-arg]


@intrinsic
def _llvm_fma(typingctx, a, b, c):
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        return _emit_fma(builder, *args)

    return sig, codegen


@njit(cache=True, nogil=True, inline="always")
def fma(a: float, b: float, c: float) -> float:  # pragma: no cover - compiled
    """a b + c with one rounding (IEEE fusedMultiplyAdd)."""
    return _llvm_fma(a, b, c)  # type: ignore[call-arg]


def _elementwise_type(args):
    """The result type of an element-by-element operation on these argument types (floats, or
    tuples, nested or not, of one structure with floats at the leaves), or None."""
    tuples = [a for a in args if isinstance(a, types.BaseTuple)]
    if not tuples:
        return types.float64 if all(a == types.float64 for a in args) else None
    n = len(tuples[0])
    if any(len(a) != n for a in tuples) or any(
        a != types.float64 for a in args if not isinstance(a, types.BaseTuple)
    ):
        return None
    parts = [_elementwise_type([_part(a, i) for a in args]) for i in range(n)]
    return None if None in parts else types.Tuple(parts)


def _part(ty, i):
    """Element i of a tuple type; a float stands for every element."""
    return ty[i] if isinstance(ty, types.BaseTuple) else ty


def _elementwise_codegen(emit):
    """Codegen applying emit(builder, *floats) to floats or to each leaf of the tuples."""

    def apply(context, builder, ret, tys, vals):
        if not isinstance(ret, types.BaseTuple):
            return emit(builder, *vals)
        out = ir.Constant(context.get_value_type(ret), ir.Undefined)
        for i in range(len(ret)):
            parts = [
                builder.extract_value(v, i) if isinstance(t, types.BaseTuple) else v
                for t, v in zip(tys, vals, strict=True)
            ]
            leaf = apply(context, builder, _part(ret, i), [_part(t, i) for t in tys], parts)
            out = builder.insert_value(out, leaf, i)
        return out

    def codegen(context, builder, signature, args):
        return apply(context, builder, signature.return_type, signature.args, args)

    return codegen


def _emit_fma(builder, a, b, c):
    d = ir.DoubleType()
    fn = builder.module.declare_intrinsic("llvm.fma", [d], ir.FunctionType(d, [d, d, d]))
    return builder.call(fn, [a, b, c])


def _binary_intrinsic(emit):
    """An intrinsic applying emit(builder, x, y) to two floats or, leaf by leaf, tuples."""

    def typer(typingctx, a, b):
        ret = _elementwise_type((a, b))
        return None if ret is None else (ret(a, b), _elementwise_codegen(emit))

    return intrinsic(typer)


_llvm_add = _binary_intrinsic(lambda builder, x, y: builder.fadd(x, y))
_llvm_mul = _binary_intrinsic(lambda builder, x, y: builder.fmul(x, y))


@intrinsic
def _llvm_fma_elementwise(typingctx, a, b, c):
    ret = _elementwise_type((a, b, c))
    return None if ret is None else (ret(a, b, c), _elementwise_codegen(_emit_fma))


@njit(cache=True, nogil=True, inline="always")
def add(a, b):  # pragma: no cover - compiled
    """a + b, on floats or element by element on (nested) tuples of floats."""
    return _llvm_add(a, b)


@njit(cache=True, nogil=True, inline="always")
def mul(a, b):  # pragma: no cover - compiled
    """a b, on floats or element by element on (nested) tuples of floats."""
    return _llvm_mul(a, b)


@njit(cache=True, nogil=True, inline="always")
def fmadd(a, b, c):  # pragma: no cover - compiled
    """`fma` on floats or element by element on (nested) tuples of floats."""
    return _llvm_fma_elementwise(a, b, c)  # type: ignore[call-arg]
