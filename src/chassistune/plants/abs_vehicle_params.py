"""7-DOF vehicle ABS parameters, steering, the preset `paper-deffao` (design.md 3.3; Tian 2025,
deffao-vehicle-abs Table 2) and the measured cars of `plants.cars` (docs/cars.md), kept apart
from the compiled tire and load solver (`plants.abs_vehicle`) so that listing presets and
parameters imports no numba."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from chassistune.params import nonnegative, positive, unit_interval
from chassistune.plants.cars import CARS, read_car
from chassistune.plants.presets import Preset, PresetInfo
from chassistune.units import PRESSURE

MAX_STEER_LIMIT_RAD = 0.5 * math.pi
"""max_steer_rad must stay below 90 degrees (refused at or above it: the wheel would turn
sideways)."""


@dataclass(frozen=True)
class VehicleParams:
    """Vehicle, brake and solver parameters, SI (q in the preset's pressure unit, Tb = kq q)."""

    mass_kg: float = field(default=1110.0, metadata=positive(300.0, 5000.0))
    """Total mass, used in every equation (deffao-vehicle-abs Table 2)."""
    front_unsprung_kg: float = field(default=60.0, metadata=nonnegative(0.0, 500.0))
    """Paper deffao-vehicle-abs's m1: recorded, unused by the planar model."""
    rear_unsprung_kg: float = field(default=60.0, metadata=nonnegative(0.0, 500.0))
    """Paper deffao-vehicle-abs's m2: recorded, unused by the planar model."""
    yaw_inertia_kg_m2: float = field(default=1440.0, metadata=positive(100.0, 20_000.0))
    """Printed 1.44 kg m^2 in deffao-vehicle-abs Table 2, read as 1440."""
    wheel_inertia_kg_m2: float = field(default=0.6, metadata=positive(0.1, 50.0))
    wheel_radius_m: float = field(default=0.4, metadata=positive(0.15, 1.0))
    cg_to_front_m: float = field(default=1.04, metadata=positive(0.3, 4.0))
    cg_to_rear_m: float = field(default=1.56, metadata=positive(0.3, 4.0))
    cg_height_m: float = field(default=0.5, metadata=nonnegative(0.0, 2.0))
    track_front_m: float = field(default=1.5, metadata=positive(0.8, 2.6))
    track_rear_m: float = field(default=1.5, metadata=positive(0.8, 2.6))
    cornering_stiffness_n_rad: float = field(
        default=60_000.0, metadata=positive(5e3, 5e5, unit="N/rad")
    )
    v0_m_s: float = field(default=120.0 / 3.6, metadata=positive(1.0, 70.0))
    g_m_s2: float = field(default=9.8, metadata=positive(9.7, 9.9))
    actuator_gain: float = field(default=100.0, metadata=positive(1.0, 1e4, unit=f"{PRESSURE}/s"))
    """K of the actuator T dr/dt = K u - r: the pressure rate per unit of the (dimensionless)
    command u (docs/design.md 3.1)."""
    actuator_tau_s: float = field(default=0.01, metadata=positive(1e-3, 0.5))
    brake_gain: float = field(default=1.0, metadata=positive(0.1, 1000.0, unit=f"N m/{PRESSURE}"))
    """kq in N m per pressure unit: the mean of the four wheels' brake gains."""
    front_brake_share: float = field(default=0.5, metadata=unit_interval(0.5, 0.85))
    """The front axle's share s of the brake torque at equal pressure (CommonRoad's T_sb): a
    front wheel's brake gain is 2 s kq, a rear one's 2 (1 - s) kq; 0.5, no brake balance, gives
    every wheel kq (paper-deffao)."""
    q_max: float = field(default=2500.0, metadata=positive(10.0, 1e5, unit=PRESSURE))
    v_stop_m_s: float = field(default=2.0, metadata=positive(0.01, 10.0))
    t_max_s: float = field(default=60.0, metadata=positive(0.1, 600.0))
    dt_s: float = field(default=1e-3, metadata=positive(1e-5, 0.01))
    lock_ratio: float = field(default=0.01, metadata=unit_interval(0.001, 0.2))
    """A wheel counts as locked while w R < lock_ratio |V|."""
    min_speed_m_s: float = field(default=0.1, metadata=positive(0.01, 1.0))
    """Floor of |V| in the slip definitions."""
    relaxation_length_m: float = field(default=0.0, metadata=nonnegative(0.0, 1.0))
    """sigma_kappa of every wheel: 0, the tires read the kinematic slip; positive, a lagged slip
    (docs/tires.md, "Transient slip on the vehicle"); `tire` on the command line: the TIR
    file's own, at the reference load m g / 4."""
    lateral_relaxation_length_m: float = field(default=0.0, metadata=nonnegative(0.0, 1.0))
    """sigma_alpha of every wheel, the lateral slip's lag as `relaxation_length_m`."""

    @property
    def wheelbase_m(self) -> float:
        return self.cg_to_front_m + self.cg_to_rear_m


@dataclass(frozen=True)
class SteeringParams:
    """Front steering: `fixed` at 0 or a counter-steering `driver` (design.md 3.3):
    d(delta)/dt = (clip(-k_psi psi - k_r r, +-delta_max) - delta) / tau; `auto` (the default)
    is the driver on split-mu, where braking with the wheel held straight spins the car, and
    fixed on every other road, where nothing yaws the car (`steering_on`)."""

    steering: str = "auto"
    heading_gain: float = field(default=1.0, metadata=nonnegative(0.0, 10.0, unit="rad/rad"))
    yaw_rate_gain_s: float = field(default=0.2, metadata=nonnegative(0.0, 2.0))
    max_steer_rad: float = field(default=0.1, metadata=nonnegative(0.0, 0.7))
    """Refused at or above pi/2 (MAX_STEER_LIMIT_RAD)."""
    steer_tau_s: float = field(default=0.15, metadata=positive(0.02, 2.0))


STEERING_MODES = ("auto", "fixed", "driver")


def steering_on(mode: str, split_mu: bool) -> str:
    """The steering a run uses: `auto` is the driver on a split-mu road and fixed elsewhere."""
    if mode != "auto":
        return mode
    return "driver" if split_mu else "fixed"


VEHICLE_ROADS = ("dry-concrete", "mu-jump", "split-mu", "ice")
"""The roads of paper-deffao, first the default; the measured cars run on the same."""
DEFFAO_UNIT = "deffao-vehicle-abs unit"


def car_preset(name: str) -> Preset[VehicleParams]:
    """The measured car `name` (plants.cars): its data where the model has a field for it,
    paper-deffao's values elsewhere (docs/cars.md)."""
    car = read_car(name)
    g = VehicleParams().g_m_s2
    return Preset(
        PresetInfo(name, car.description(g), VEHICLE_ROADS, DEFFAO_UNIT),
        VehicleParams(**car.values(g)),
    )


PRESETS: dict[str, Preset[VehicleParams]] = {
    "paper-deffao": Preset(
        PresetInfo(
            "paper-deffao",
            "Tian 2025 Table 2: m = 1110 kg total, Iz = 1440 kg m^2 (printed 1.44), J = 0.6 kg "
            "m^2, R = 0.4 m, lf/lr = 1.04/1.56 m, v0 = 120 km/h, g = 9.8; ours: h = 0.5 m, "
            "tracks 1.5 m, C = 60 kN/rad, kq = 1, q_max = 2500 on all wheels, K = 100, T = 0.01 s",
            VEHICLE_ROADS,
            DEFFAO_UNIT,
        ),
        VehicleParams(),
    ),
    **{name: car_preset(name) for name in CARS},
}
