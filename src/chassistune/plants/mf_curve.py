"""The Magic Formula tire as a friction curve mu(S) of the single wheel, whose load is constant.

At the load F_z = load_fraction M g, the pure longitudinal force (Pacejka 2012, eqs. 4.E9-4.E18,
`plants.magic_formula.longitudinal_shape`) is a curve of the slip alone with constants B_x, C_x,
D_x, S_Hx, S_Vx and E_x, whose one slip dependence is the factor (1 - PEX4 sgn(kappa_x)) (4.E14):
two values of E_x, for kappa_x = kappa + S_Hx below and above 0 (at kappa_x = 0 the force is S_Vx
whatever E_x). The braking slip is S = -kappa and the friction mu(S) = -F_x0(-S) / F_z:

    mu(S) = d sin[C arctan{B x - E (B x - arctan B x)}] + v,   x = S_Hx - S,
    d = -D_x / F_z,  v = -S_Vx / F_z,  E = E(x < 0) or E(x > 0).

`kernel_data` gives (KIND_MAGIC_FORMULA, (B, C, d, v), (E(x < 0), E(x > 0), S_Hx), zeros): the
kernels' `tire_law_mu` reads the last three from the table's node slots (a Magic Formula tire has
no table), with a branch-free arctan and sine (`sim.branchfree_trig`) for C in (0, 3].
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

MAX_SHAPE_FACTOR = 3.0
"""Largest C_x the kernels take (`sim.branchfree_trig.sin_3pi_2`); real tires have 1.3-2."""


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
        shape_c = longitudinal_shape(self.tire.kernel_array(), 0.0, self.fz_n)[1]
        if not 0.0 < shape_c <= MAX_SHAPE_FACTOR:
            raise InputError(
                "tire",
                f"{self.path or 'the tire'}: C_x = PCX1 LCX = {shape_c:g} is outside "
                f"(0, {MAX_SHAPE_FACTOR:g}] (the kernels' sine covers |C_x arctan| <= 3 pi / 2)",
            )

    def kernel_data(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        c = self.tire.kernel_array()
        shx = longitudinal_shape(c, 0.0, self.fz_n)[4]
        bx, cx, dx, e_below, _, svx, _ = longitudinal_shape(c, -1.0 - abs(shx), self.fz_n)
        e_above = longitudinal_shape(c, 1.0 + abs(shx), self.fz_n)[3]
        coef = np.array([bx, cx, -dx / self.fz_n, -svx / self.fz_n])
        return KIND_MAGIC_FORMULA, coef, np.array([e_below, e_above, shx]), np.zeros(3)

    def mu(self, slip: np.ndarray | float) -> np.ndarray:
        """-F_x0(kappa = -S) / F_z by the scalar force functions (alpha = 0, where the combined
        force is the pure one)."""
        s = np.clip(np.asarray(slip, dtype=np.float64), 0.0, 1.0)
        return np.asarray(-forces_n(self.tire, -s, 0.0, self.fz_n)[0] / self.fz_n)

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
