"""The tire of an abs-vehicle run: the road's bilinear surfaces, or the Magic Formula tire of a TIR
file on them (`--tire FILE.tir`, docs/tires.md "On the vehicle").

With a TIR file, every surface of the road gets the file's tire with its friction scaled to the
surface (LMUX and LMUY times the surface's peak over the tire's, `mf_peak.scaled_to_road`), both
peaks at the reference load m g / 4; on the road `tire-surface` the file's own surface, unscaled.
The road then carries each surface's Magic Formula braking curve at that load as its bilinear
figures (peak slip, peak and locked friction): the target slip is the curve's peak slip. The
adhesion bound takes the largest total braking force the four tires can give over every load
split summing to m g (`vehicle_mf.braking_capacity_n`), per phase of the road as the bilinear
bound (on split-mu, as there, each side carries half the weight); the step check takes the
curve's slope at zero slip, K_x / F_z, at the heaviest wheel's load.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from chassistune.errors import InputError
from chassistune.plants.abs_vehicle import (
    SF_MU_LOCK,
    SF_MU_PEAK,
    SF_ST,
    Bound,
    load_coefficients,
    mf_surface_row,
    phased_bound,
    surface_row,
)
from chassistune.plants.abs_vehicle_params import VehicleParams
from chassistune.plants.magic_formula import longitudinal_shape
from chassistune.plants.mf_coefficients import MagicFormulaTire
from chassistune.plants.mf_curve import TIRE_SURFACE
from chassistune.plants.mf_peak import scaled_to_road
from chassistune.plants.mf_relaxation import (
    lateral_relaxation_length_m,
    longitudinal_relaxation_length_m,
)
from chassistune.plants.tires import BilinearTire
from chassistune.plants.vehicle_mf import braking_capacity_n
from chassistune.plants.vehicle_roads import ROAD_MU_JUMP, ROAD_SPLIT, ROAD_UNIFORM, VehicleRoad


@dataclass(frozen=True)
class VehicleTire:
    """The Magic Formula tire of a TIR file on each of the road's two surfaces."""

    path: str
    surfaces: tuple[MagicFormulaTire, MagicFormulaTire]
    reference_load_n: float
    rows: np.ndarray
    """The kernel's surface rows of the two surfaces (`abs_vehicle.mf_surface_row`)."""
    file_warnings: tuple[Warning | str, ...] = ()
    """The reader's warnings about the file, for the scenario to show once its input is valid."""


LENGTH_FIELDS = ("relaxation_length_m", "lateral_relaxation_length_m")
"""The vehicle's relaxation lengths (`abs_vehicle_params.VehicleParams`), each a number or
`tire` (`with_file_lengths`)."""


def with_file_lengths(
    pp: VehicleParams, tire: VehicleTire | None, fields: set[str]
) -> VehicleParams:
    """`pp` with the relaxation lengths named in `fields` (given as `tire`) the TIR file's at the
    reference load m g / 4 (`mf_relaxation`: MF 6.1's from the carcass stiffness, else MF 5.2's
    from PTX1-3 or PTY1-2); InputError naming the field without a file or a length in it."""
    lengths = {}
    for name in sorted(fields):
        field = f"params.{name}"
        if tire is None:
            raise InputError(field, "'tire' takes the TIR file's length: needs --tire")
        c = tire.surfaces[0].kernel_array()  # a road scales friction, not the lengths' terms
        if name == "relaxation_length_m":
            sigma = float(longitudinal_relaxation_length_m(c, tire.reference_load_n))
            needs = "LONGITUDINAL_STIFFNESS (MF 6.1) nor a positive PTX1 (MF 5.2)"
        else:
            sigma = float(lateral_relaxation_length_m(c, tire.reference_load_n))
            needs = "LATERAL_STIFFNESS (MF 6.1) nor positive PTY1 and PTY2 (MF 5.2)"
        if not sigma > 0.0:
            raise InputError(
                field,
                f"{tire.path} gives no relaxation length: it has neither {needs}; give the "
                "length in metres",
            )
        lengths[name] = sigma
    return dataclasses.replace(pp, **lengths)


def reference_load_n(pp: VehicleParams) -> float:
    """m g / 4, the load at which a surface's friction scales the tire and its curve is read."""
    return pp.mass_kg * pp.g_m_s2 / 4.0


def on_surfaces(
    road_name: str, road: VehicleRoad | None, values: Mapping[str, object], pp: VehicleParams
) -> tuple[VehicleRoad, VehicleTire | None]:
    """The road with the tire of `values["tire"]` (a TIR file) on its surfaces, and that tire;
    the road unchanged and None without a file. `road` is None on TIRE_SURFACE."""
    if "tire" not in values:
        if road is None:
            raise InputError("road", f"{TIRE_SURFACE} is a TIR file's surface: needs --tire")
        return road, None
    from chassistune.plants.tir import read_tir

    path = str(values["tire"])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tire = read_tir(path, lateral=True)
    fz = reference_load_n(pp)
    if road is None:
        tires = (tire, tire)
    else:
        a, b = (scaled_to_road(tire, s.mu_peak, fz) for s in road.surfaces)
        tires = (a, b)
    rows = np.stack([mf_surface_row(t, fz, pp.cornering_stiffness_n_rad) for t in tires])
    curves = (_curve(rows[0]), _curve(rows[1]))
    if road is None:
        road = VehicleRoad(TIRE_SURFACE, ROAD_UNIFORM, (TIRE_SURFACE,) * 2, curves)
    else:
        road = dataclasses.replace(road, surfaces=curves)
    return road, VehicleTire(path, tires, fz, rows, tuple(w.message for w in caught))


def _curve(row: np.ndarray) -> BilinearTire:
    """A surface row's braking figures (peak slip, peak and locked friction) as a surface."""
    return BilinearTire(float(row[SF_ST]), float(row[SF_MU_PEAK]), float(row[SF_MU_LOCK]))


def surface_rows(road: VehicleRoad, tire: VehicleTire | None, stiffness_n_rad: float) -> np.ndarray:
    """The kernel's surface rows (`plants.abs_vehicle` SF_* columns) of the road's two surfaces."""
    if tire is not None:
        return tire.rows
    return np.stack(
        [surface_row(t.slip_opt, t.mu_peak, t.mu_lock, stiffness_n_rad) for t in road.surfaces]
    )


def bound(pp: VehicleParams, road: VehicleRoad, tire: VehicleTire) -> Bound:
    """The adhesion bound with the Magic Formula tire (module docstring): the braking capacity
    per phase, all wheels on the first surface, then (mu-jump) the front axle on the second, then
    all on the second; split-mu each side's two wheels at half the weight (the bilinear bound's
    equal side loads)."""
    a, b = tire.surfaces
    m_g = pp.mass_kg * pp.g_m_s2

    def deceleration(*tires: MagicFormulaTire) -> float:
        return braking_capacity_n(tires, m_g) / pp.mass_kg

    phases: tuple[tuple[float, float], ...]
    if road.kind == ROAD_MU_JUMP:
        phases = (
            (road.x_jump_m, deceleration(a, a, a, a)),
            (pp.wheelbase_m, deceleration(b, b, a, a)),
            (float("inf"), deceleration(b, b, b, b)),
        )
    elif road.kind == ROAD_SPLIT:  # each side at half the weight, as the bilinear bound
        side_n = 0.5 * m_g
        total_n = braking_capacity_n((a, a), side_n) + braking_capacity_n((b, b), side_n)
        phases = ((float("inf"), total_n / pp.mass_kg),)
    else:
        phases = ((float("inf"), deceleration(a, a, a, a)),)
    return phased_bound(pp, phases)


def slope_at_zero_slip(pp: VehicleParams, tire: VehicleTire, mu_peak_max: float) -> float:
    """The steepest braking curve's K_x / F_z over the surfaces at the load `wheel_mode_rate`
    takes, the heaviest wheel's braking at mu_peak_max g."""
    fz0, a, _ = load_coefficients(pp)
    fz = float(np.max(fz0 - a * mu_peak_max * pp.g_m_s2))
    return max(float(longitudinal_shape(t.kernel_array(), 0.0, fz)[6]) / fz for t in tire.surfaces)
