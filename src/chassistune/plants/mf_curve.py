"""The Magic Formula tire as a friction curve mu(S) of the single wheel, whose load is constant.

At the load F_z = load_fraction M g, the pure longitudinal force (Pacejka 2012, eqs. 4.E9-4.E18,
`plants.magic_formula.longitudinal_shape`) is a curve of the slip alone; the braking slip is
S = -kappa and the friction mu(S) = -F_x0(-S) / F_z:

    mu(S) = d sin[C arctan{B x - E (B x - arctan B x)}] + v,   x = S_Hx - S,
    d = -D_x / F_z,  v = -S_Vx / F_z,  E = E_x(x < 0) or E_x(x > 0) (the sgn of 4.E14).

The kernels evaluate it as a piecewise cubic fitted once per run (`segment_polynomials`), each
segment's polynomial in its local coordinate f in [0, 1) interpolating the scalar force at the
Chebyshev nodes. A segment is found by arithmetic, not by a search: u = S n1 + o1 below
u = FINE_SEGMENTS, else S n2 + o2; segment floor(u), f = u - floor(u)
(`sim.abs_wheel_tires.magic_formula_mu`). The FINE_SEGMENTS cover S in [0, a), a = 8 times the
peak's slip within [0.02, 0.5] (the curve's steep part: its width scales as 1/B_x, and B_x as
1/mu on a slick road), with a knot on S = S_Hx where E_x changes; COARSE_SEGMENTS cover [a, 1].
The formula itself, two arctangents and a sine in series on the integration's dependency chain
at every stage, cost the kernel 4-5 times the bilinear law; a cubic is one gather per coefficient
and two levels of fused multiply-adds (docs/tires.md). A curve whose fit is off the scalar force
by more than FIT_TOLERANCE on a check grid is refused.

`kernel_data` gives (KIND_MAGIC_FORMULA, (n1, o1, n2, o2), the coefficients segment by segment
(POLY_SIZE values, lowest degree first), no nodes).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from chassistune.errors import InputError
from chassistune.plants.magic_formula import longitudinal_shape
from chassistune.plants.mf_arrays import forces_n
from chassistune.plants.mf_coefficients import MagicFormulaTire
from chassistune.plants.mf_peak import braking_peak, scaled_to_road
from chassistune.plants.tires import KIND_MAGIC_FORMULA, TireCurve

FINE_SEGMENTS = 96
"""Segments of the kernels' piecewise cubic over the curve's steep part (module docstring)."""
COARSE_SEGMENTS = 32
"""Segments over the rest of the slip range."""
SEGMENTS = FINE_SEGMENTS + COARSE_SEGMENTS
DEGREE = 3
"""Degree of each segment's polynomial (the kernels' evaluation is written for 3)."""
POLY_SIZE = (DEGREE + 1) * (SEGMENTS + 1)
"""Coefficients of the piecewise cubic: SEGMENTS + 1 segments (the last one reached only at
S = 1 when that is a knot)."""
FIT_TOLERANCE = 1e-5
"""Largest gap between the piecewise polynomial and the scalar force / F_z a curve may have
(measured on the three sample files at 900-7500 N, on their surfaces and scaled to peaks of
0.05-0.8: at most 9.4e-6, MF61's at 7500 N and mu 0.05, whose peak is at S = 0.003; the others
at most 2.5e-6)."""
_CHECK_POINTS = 16
"""Check points per segment, evenly spaced, for FIT_TOLERANCE."""
_NODES = 0.5 - 0.5 * np.cos((2.0 * np.arange(DEGREE + 1) + 1.0) * np.pi / (2.0 * DEGREE + 2.0))
"""Chebyshev nodes of a segment's interpolation, in its local coordinate f in [0, 1]."""


@dataclass(frozen=True)
class MagicFormulaCurve(TireCurve):
    """The longitudinal pure-slip Magic Formula of `tire` at the constant load fz_n, as mu(S);
    `path` names the TIR file it was read from (for the parameter echo)."""

    tire: MagicFormulaTire
    fz_n: float
    path: str = ""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.fz_n) and self.fz_n > 0.0):
            raise InputError("tire", f"the wheel load must be positive, got {self.fz_n:g} N")
        gap = fit_gap(self)
        if not gap <= FIT_TOLERANCE:
            raise InputError(
                "tire",
                f"{self.path or 'the tire'}: its curve at {self.fz_n:g} N is too steep for the "
                f"kernels' piecewise polynomial (off by {gap:.2g}, more than {FIT_TOLERANCE:g})",
            )

    def kernel_data(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        zones, coef = segment_polynomials(self)
        return KIND_MAGIC_FORMULA, zones, coef, np.zeros(0)

    def mu(self, slip: np.ndarray | float) -> np.ndarray:
        """-F_x0(kappa = -S) / F_z by the scalar force functions (alpha = 0, where the combined
        force is the pure one)."""
        return _exact_mu(self, np.clip(np.asarray(slip, dtype=np.float64), 0.0, 1.0))

    def peak(self) -> tuple[float, float, float]:
        """The braking peak in closed form (`mf_peak.braking_peak`) when it lies inside the slip
        range; else `TireCurve.peak`'s rule for a curve rising up to a locked wheel."""
        kappa, force_n = braking_peak(self.tire, self.fz_n)
        if kappa > -1.0:
            return -force_n / self.fz_n, -kappa, -kappa
        return super().peak()

    def on_road(self, road_mu_peak: float) -> MagicFormulaCurve:
        """The tire on a road of peak friction road_mu_peak (`mf_peak.scaled_to_road`: LMUX and
        LMUY times the road's peak over the tire's, at this load)."""
        return dataclasses.replace(self, tire=scaled_to_road(self.tire, road_mu_peak, self.fz_n))


def _zones(curve: MagicFormulaCurve) -> np.ndarray:
    """(n1, o1, n2, o2) of u = S n1 + o1 (fine) and S n2 + o2 (coarse; module docstring): a
    knot on S_Hx and u(0) in [0, 1); the coarse zone from u = FINE_SEGMENTS to SEGMENTS."""
    kappa_peak = braking_peak(curve.tire, curve.fz_n)[0]
    a = min(0.5, max(0.02, -8.0 * kappa_peak)) if kappa_peak > -1.0 else 0.5
    n1 = FINE_SEGMENTS / a
    shx = longitudinal_shape(curve.tire.kernel_array(), 0.0, curve.fz_n)[4]
    o1 = math.ceil(shx * n1) - shx * n1
    a_knot = (FINE_SEGMENTS - o1) / n1
    n2 = COARSE_SEGMENTS / (1.0 - a_knot)
    return np.array([n1, o1, n2, FINE_SEGMENTS - a_knot * n2])


def segment_polynomials(curve: MagicFormulaCurve) -> tuple[np.ndarray, np.ndarray]:
    """((n1, o1, n2, o2), coefficients) of the curve's piecewise cubic (module docstring):
    segment i covers u in [i, i + 1), its DEGREE + 1 coefficients in f = u - i at
    [i (DEGREE + 1), (i + 1)(DEGREE + 1)), interpolating `mu` unclipped at _NODES."""
    n1, o1, n2, o2 = zones = _zones(curve)
    u = np.arange(SEGMENTS + 1)[None, :] + _NODES[:, None]
    slip = np.where(u < FINE_SEGMENTS, (u - o1) / n1, (u - o2) / n2)
    coef = np.linalg.solve(np.vander(_NODES, DEGREE + 1, increasing=True), _exact_mu(curve, slip))
    return zones, np.ascontiguousarray(coef.T).ravel()


def polynomial_mu(zones: np.ndarray, coef: np.ndarray, slip: np.ndarray) -> np.ndarray:
    """The piecewise cubic at slips in [0, 1], in numpy: the kernels' law
    (`sim.abs_wheel_tires.magic_formula_mu`) without its fused multiply-adds (within a few
    ulps of it; the fit check needs 1e-5)."""
    n1, o1, n2, o2 = (float(z) for z in zones)
    s = np.asarray(slip, dtype=np.float64)
    u = s * n1 + o1
    u = np.where(u < FINE_SEGMENTS, u, s * n2 + o2)
    i = np.minimum(np.maximum(u, 0.0).astype(np.int64), SEGMENTS)
    f = u - i
    c = np.asarray(coef, dtype=np.float64).reshape(-1, DEGREE + 1)[i]
    return c[:, 0] + f * (c[:, 1] + f * (c[:, 2] + f * c[:, 3]))


def fit_gap(curve: MagicFormulaCurve) -> float:
    """Largest |piecewise cubic - mu| over _CHECK_POINTS points per segment (evenly in each)."""
    zones, coef = segment_polynomials(curve)
    n1, o1, n2, o2 = zones
    u = np.linspace(0.0, SEGMENTS, _CHECK_POINTS * SEGMENTS + 1)
    s = np.clip(np.where(u < FINE_SEGMENTS, (u - o1) / n1, (u - o2) / n2), 0.0, 1.0)
    return float(np.max(np.abs(polynomial_mu(zones, coef, s) - _exact_mu(curve, s))))


def _exact_mu(curve: MagicFormulaCurve, slip: np.ndarray) -> np.ndarray:
    """-F_x0(kappa = -S) / F_z by the scalar force functions, unclipped."""
    return -forces_n(curve.tire, -slip, 0.0, curve.fz_n)[0] / curve.fz_n


TIRE_SURFACE = "tire-surface"
"""The road of a run with a TIR file and no other road: the file's own measurement surface."""


def wheel_tire(path: str, road: str, road_curve: TireCurve | None, fz_n: float) -> TireCurve:
    """The Magic Formula tire of the TIR file at `path` at the wheel load fz_n: on its own
    surface when `road` is TIRE_SURFACE (road_curve None), else on the road whose curve is
    road_curve (its peak; `MagicFormulaCurve.on_road`). A malformed file is one error naming its
    line (`plants.tir`)."""
    from chassistune.plants.tir import read_tir

    curve = MagicFormulaCurve(read_tir(path), fz_n, path)
    if road == TIRE_SURFACE:
        return curve
    if road_curve is None:
        raise InputError("road", f"{road}: no friction curve to scale the tire to")
    return curve.on_road(road_curve.peak()[0])
