"""arctan and sine as straight-line arithmetic, for vector loops: numba lowers `math.atan` to a
call of libm's atan (LLVM has no intrinsic for it), which keeps a loop scalar, and without
Intel's SVML (`numba -s`) `math.sin` is scalarized too.

    atan(x): Cephes' atan (Moshier, Cephes Mathematical Library, atan.c): |x| reduced to
        [0, 0.66] by atan x = pi/2 + atan(-1/x) above tan(3 pi/8) and pi/4 + atan((x-1)/(x+1))
        above 0.66, with selects and one division, then x + x z P(z)/Q(z), z = x^2 (degrees 4
        and 5); measured against math.atan: at most 1 ulp (tests/sim/test_branchfree_trig.py).
    sin_3pi_2(y): sin y for |y| <= 3 pi / 2, reduced to [-pi/2, pi/2] by sin y = sin(+-pi - y),
        then the Taylor series to y^21 (the next term is below 1.3e-18 there); measured against
        math.sin: within 3.4e-16 absolute (relative near +-pi, where sin y is small: pi - y
        carries float(pi)'s error).
"""

from __future__ import annotations

from numba import njit

from chassistune._branchfree import select

_P = (
    -8.750608600031904122785e-1,
    -1.615753718733365076637e1,
    -7.500855792314704667340e1,
    -1.228866684490136173410e2,
    -6.485021904942025371773e1,
)
_Q = (
    2.485846490142306297962e1,
    1.650270098316988542046e2,
    4.328810604912902668951e2,
    4.853903996359136964868e2,
    1.945506571482613964425e2,
)
_T3P8 = 2.41421356237309504880
"""tan(3 pi / 8)."""
_MOREBITS = 6.123233995736765886130e-17
"""pi/2 - float(pi/2)."""
_PI = 3.141592653589793
_PIO2 = 1.5707963267948966
_PIO4 = 0.7853981633974483


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def atan_branchfree(x):
    """arctan x (module docstring), branch-free."""
    a = abs(x)
    big = a > _T3P8
    mid = a > 0.66
    num = select(big, -1.0, select(mid, a - 1.0, a))
    den = select(big, a, select(mid, a + 1.0, 1.0))
    r = num / den
    z = r * r
    p = (((_P[0] * z + _P[1]) * z + _P[2]) * z + _P[3]) * z + _P[4]
    q = ((((z + _Q[0]) * z + _Q[1]) * z + _Q[2]) * z + _Q[3]) * z + _Q[4]
    base = select(big, _PIO2, select(mid, _PIO4, 0.0))
    extra = select(big, _MOREBITS, select(mid, 0.5 * _MOREBITS, 0.0))
    y = base + (r * (z * p / q) + r + extra)
    return select(x < 0.0, -y, y)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def sin_3pi_2(y):
    """sin y for |y| <= 3 pi / 2 (module docstring), branch-free."""
    r = select(y > _PIO2, _PI - y, select(y < -_PIO2, -_PI - y, y))
    z = r * r
    p = 1.0 / 51090942171709440000.0  # 1/21!, then 1/19!, ... 1/3!, 1 with alternate signs
    p = p * z - 1.0 / 121645100408832000.0
    p = p * z + 1.0 / 355687428096000.0
    p = p * z - 1.0 / 1307674368000.0
    p = p * z + 1.0 / 6227020800.0
    p = p * z - 1.0 / 39916800.0
    p = p * z + 1.0 / 362880.0
    p = p * z - 1.0 / 5040.0
    p = p * z + 1.0 / 120.0
    p = p * z - 1.0 / 6.0
    return r * (p * z + 1.0)
