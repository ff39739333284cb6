"""The branch-free arctan and sine of the Magic Formula's vector loop against libm's."""

from __future__ import annotations

import math

import numba
import numpy as np

from chassistune.sim.branchfree_trig import atan_branchfree, sin_3pi_2


@numba.njit
def _many(f, x):  # type: ignore[no-untyped-def]
    out = np.empty(x.size)
    for i in range(x.size):
        out[i] = f(x[i])
    return out


def test_atan_is_within_one_ulp_of_math_atan() -> None:
    """At most 1 ulp (measured: 1) over |x| from 1e-300 to 1e300 and the range reductions'
    edges (0.66, tan(3 pi / 8))."""
    logs = np.logspace(-300.0, 300.0, 200_001)
    edges = [0.66, np.nextafter(0.66, 1.0), 2.414213562373095, 2.4142135623730954]
    x = np.concatenate([np.linspace(-5.0, 5.0, 400_001), logs, -logs, edges, [0.0, np.inf]])
    ours = _many(atan_branchfree, x)
    ref = np.array([math.atan(v) for v in x])
    assert np.all(np.abs(ours - ref) <= np.spacing(np.abs(ref)))
    assert ours[-1] == math.pi / 2.0 and ours[-2] == 0.0
    assert np.isnan(_many(atan_branchfree, np.array([np.nan]))[0])


def test_sin_is_within_3_4e_16_of_math_sin_up_to_3_pi_over_2() -> None:
    y = np.linspace(-1.5 * math.pi, 1.5 * math.pi, 400_001)
    ours = _many(sin_3pi_2, y)
    ref = np.array([math.sin(v) for v in y])
    assert np.max(np.abs(ours - ref)) <= 3.4e-16
