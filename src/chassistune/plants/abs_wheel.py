"""Single-wheel ABS plant (design.md 3.1; Tian et al. `derlsp-ao-abs` eqs. 1-12, Ding 2023
`fuzzy-immune-abs`, MathWorks sldemo_absbrake): parameters and presets.

The equations of motion (design.md 3.1) are integrated by the compiled kernel
`chassistune.sim.abs_wheel_kernel`; the tire curves and roads are `plants.tires`, `plants.roads`.
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass, field

from chassistune.errors import InputError
from chassistune.params import nonnegative, positive, unit_interval
from chassistune.plants.cars import CARS, read_car
from chassistune.plants.presets import Preset, PresetInfo
from chassistune.units import PRESSURE

FT = 0.3048
SLUG = 14.593902937
FT_LBF = 1.3558179483

T_MAX_PER_BOUND_TIME = 3.0
"""Without an explicit t_max_s, a run may last this many bound times (at least t_max_s)."""


@dataclass(frozen=True)
class AbsWheelParams:
    """Plant and solver parameters, SI (pressure q in the preset's own unit, Tb = brake_gain q).

    Plausible ranges: a quarter of a motorcycle to a heavy truck's wheel load, wheel inertias from
    a car wheel (about 1 kg m^2) to the papers' 12 and 25 kg m^2, road speeds up to 70 m/s.
    """

    mass_kg: float = field(default=100.0, metadata=positive(20.0, 5000.0))
    wheel_inertia_kg_m2: float = field(default=12.0, metadata=positive(0.1, 50.0))
    wheel_radius_m: float = field(default=0.5, metadata=positive(0.15, 1.0))
    v0_m_s: float = field(default=30.0, metadata=positive(1.0, 70.0))
    g_m_s2: float = field(default=9.81, metadata=positive(9.7, 9.9))
    actuator_gain: float = field(default=100.0, metadata=positive(1.0, 1e4, unit=f"{PRESSURE}/s"))
    """K of the actuator T dr/dt = K u - r: the pressure rate per unit of the (dimensionless)
    command u (docs/design.md 3.1)."""
    actuator_tau_s: float = field(default=0.01, metadata=positive(1e-3, 0.5))
    brake_gain: float = field(default=1.0, metadata=positive(0.1, 1000.0, unit=f"N m/{PRESSURE}"))
    q_max: float = field(default=1500.0, metadata=positive(10.0, 1e5, unit=PRESSURE))
    v_stop_m_s: float = field(default=0.5, metadata=positive(0.01, 10.0))
    t_max_s: float = field(default=60.0, metadata=positive(1.0, 600.0))
    """Default: the larger of 60 s and 3 bound times of the road (`default_t_max_s`)."""
    dt_s: float = field(default=1e-3, metadata=positive(1e-5, 0.01))
    load_fraction: float = field(default=1.0, metadata=positive(0.2, 1.0))
    """Wheel load as a fraction of M g: 1 here; 0.25 only in `sldemo` (MathWorks' quirk)."""
    lock_ratio: float = field(default=0.01, metadata=unit_interval(0.001, 0.2))
    """The wheel counts as locked while w R < lock_ratio v."""
    relaxation_length_m: float = field(default=0.0, metadata=nonnegative(0.0, 1.0))
    """sigma of the tire's lagged slip, sigma dS'/dt = v (S - S') (docs/tires.md, transient
    slip); 0: the static tire, which reads the kinematic slip S itself."""


def bound_time_s(pp: AbsWheelParams, mu_peak: float) -> float:
    """Time to brake from v0 to v_stop at the road's peak deceleration mu_peak g load_fraction."""
    return (pp.v0_m_s - pp.v_stop_m_s) / (mu_peak * pp.g_m_s2 * pp.load_fraction)


def default_t_max_s(pp: AbsWheelParams, mu_peak: float) -> float:
    """The time limit when none is given: enough for a slow stop on a slippery road."""
    return max(pp.t_max_s, T_MAX_PER_BOUND_TIME * bound_time_s(pp, mu_peak))


FINE_DT_S = 2.5e-4
"""The default step of the paper-fuzzy-immune and sldemo presets: at 1 ms the
PID's stop distance and slip ITAE are off by up to 4.3e-3 (paper-fuzzy-immune) and 3.1e-3
(sldemo) against dt/100, at 0.25 ms by at most 3.0e-4 (`chassistune bench`,
abs_max_rel_err_presets). paper-derlsp-ao keeps 1 ms (6.7e-4 on dry concrete and wet asphalt)."""


def _sldemo_params() -> AbsWheelParams:
    return AbsWheelParams(
        mass_kg=50 * SLUG,
        wheel_inertia_kg_m2=5 * SLUG * FT**2,
        wheel_radius_m=1.25 * FT,
        v0_m_s=88 * FT,
        g_m_s2=32.18 * FT,
        actuator_gain=100.0,
        actuator_tau_s=0.01,
        brake_gain=FT_LBF,
        q_max=1500.0,
        load_fraction=0.25,
        dt_s=FINE_DT_S,
    )


BRAKE_FIELDS = ("actuator_gain", "actuator_tau_s", "brake_gain", "q_max")
"""The brake and actuator: not car data (CommonRoad's cars take a brake torque), so a car's wheel
keeps the paper preset's (docs/cars.md, "One wheel of the car")."""
CAR_WHEEL_BASE = "paper-derlsp-ao"
"""The paper preset a car's single wheel takes every field from that is not car data."""
CAR_WHEEL_DT_S = FINE_DT_S
"""The step of the car wheels: their wheel mode is about 13 times as fast as paper-derlsp-ao's
(R^2 Fz / J: 0.344 m, 1.7 kg m^2, 3.8 kN against 0.5 m, 12 kg m^2, 1 kN; docs/cars.md)."""


def car_wheel_preset(name: str) -> Preset[AbsWheelParams]:
    """A front wheel of the measured car `name` (plants.cars) on paper-derlsp-ao's brake,
    speed and roads (docs/cars.md, "One wheel of the car")."""
    car = read_car(name)
    values = car.front_wheel_values()
    return Preset(
        PresetInfo(
            name,
            f"a front wheel of the {car.title} (CommonRoad vehicle {car.source['vehicle_id']}): "
            f"M = m b / (2 L) = {values['mass_kg']:.1f} kg, "
            f"R = {values['wheel_radius_m']} m, J = {values['wheel_inertia_kg_m2']} kg m^2; "
            f"brake, actuator, v0 and roads of {CAR_WHEEL_BASE}; "
            f"dt = {CAR_WHEEL_DT_S * 1e3:g} ms",
            ("dry-concrete", "wet-asphalt", "ice"),
            "derlsp-ao-abs unit",
        ),
        AbsWheelParams(**values, dt_s=CAR_WHEEL_DT_S),
    )


PRESETS: dict[str, Preset[AbsWheelParams]] = {
    "paper-derlsp-ao": Preset(
        PresetInfo(
            "paper-derlsp-ao",
            "Tian et al. (derlsp-ao-abs): M = 100 kg quarter mass, I = 12 kg m^2, R = 0.5 m, "
            "v0 = 30 m/s, K/(s(Ts+1))",
            ("dry-concrete", "wet-asphalt", "ice"),
            "derlsp-ao-abs unit",
        ),
        AbsWheelParams(),
    ),
    "paper-fuzzy-immune": Preset(
        PresetInfo(
            "paper-fuzzy-immune",
            "Ding 2023 (fuzzy-immune-abs): R = 0.28 m, J = 25 kg m^2 (as printed), "
            "q in kPa, kq = 25 N m/kPa, M = 300 kg (our assumption)",
            ("asphalt-0.8", "dirt-0.2"),
            "kPa",
        ),
        AbsWheelParams(
            mass_kg=300.0,
            wheel_inertia_kg_m2=25.0,
            wheel_radius_m=0.28,
            brake_gain=25.0,
            q_max=800.0,
            dt_s=FINE_DT_S,
        ),
    ),
    "sldemo": Preset(
        PresetInfo(
            "sldemo",
            "MathWorks sldemo_absbrake in SI, with its quarter-load-on-whole-mass quirk",
            ("sldemo-table",),
            "sldemo unit",
        ),
        _sldemo_params(),
        {"amplitude": 1.0},
    ),
    **{name: car_wheel_preset(name) for name in CARS},
}


def check_consistency(pp: AbsWheelParams, given: Collection[str] = ()) -> None:
    """Checks across fields: a stop speed below v0, an RK4 step the plant tolerates and a
    relaxation length the step resolves; the field blamed is the one the user set (`given`) when
    only one of a pair was."""
    if pp.v0_m_s <= pp.v_stop_m_s:
        if "v_stop_m_s" in given and "v0_m_s" not in given:
            raise InputError(
                "params.v_stop_m_s", f"must be below v0_m_s = {pp.v0_m_s:g}, got {pp.v_stop_m_s:g}"
            )
        raise InputError(
            "params.v0_m_s", f"must exceed v_stop_m_s = {pp.v_stop_m_s:g}, got {pp.v0_m_s:g}"
        )
    if pp.dt_s > 0.01:
        raise InputError(
            "params.dt_s", f"must be at most 0.01 s for a stable RK4 step, got {pp.dt_s:g}"
        )
    if pp.t_max_s < 10 * pp.dt_s:
        raise InputError("params.t_max_s", f"must be at least 10 steps, got {pp.t_max_s:g}")
    if pp.t_max_s / pp.dt_s > 5e7:
        blame = "dt_s" if "dt_s" in given and "t_max_s" not in given else "t_max_s"
        raise InputError(
            f"params.{blame}",
            f"too many steps: t_max_s / dt_s = {pp.t_max_s / pp.dt_s:.3g} is above 5e7",
        )
    shortest = pp.v0_m_s * pp.dt_s
    if 0.0 < pp.relaxation_length_m < shortest:
        raise InputError(
            "params.relaxation_length_m",
            f"must be 0 or at least v0_m_s dt_s = {shortest:g} m (a step no longer than the lag's "
            f"time constant sigma / v), got {pp.relaxation_length_m:g}",
        )
