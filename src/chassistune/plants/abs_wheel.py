"""Single-wheel ABS plant (DESIGN 3.1; Tian et al. `derlsp-ao-abs` eqs. 1-12, Ding 2023
`fuzzy-immune-abs`, MathWorks sldemo_absbrake): parameters and presets.

The equations of motion (DESIGN 3.1) are integrated by the compiled kernel
`chassistune.sim.abs_wheel_kernel`; the tire curves and roads are `plants.tires`, `plants.roads`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from chassistune.errors import InputError
from chassistune.plants.presets import PresetInfo

_POS = {"positive": True}

FT = 0.3048
SLUG = 14.593902937
FT_LBF = 1.3558179483


@dataclass(frozen=True)
class AbsWheelParams:
    """Plant and solver parameters, SI (pressure q in the preset's own unit, Tb = brake_gain q)."""

    mass_kg: float = field(default=100.0, metadata=_POS)
    wheel_inertia_kg_m2: float = field(default=12.0, metadata=_POS)
    wheel_radius_m: float = field(default=0.5, metadata=_POS)
    v0_m_s: float = field(default=30.0, metadata=_POS)
    g_m_s2: float = field(default=9.81, metadata=_POS)
    actuator_gain: float = field(default=100.0, metadata=_POS)
    actuator_tau_s: float = field(default=0.01, metadata=_POS)
    brake_gain: float = field(default=1.0, metadata=_POS)
    q_max: float = field(default=1500.0, metadata=_POS)
    v_stop_m_s: float = field(default=0.5, metadata=_POS)
    t_max_s: float = field(default=60.0, metadata=_POS)
    dt_s: float = field(default=1e-3, metadata=_POS)
    load_fraction: float = field(default=1.0, metadata=_POS)
    """Wheel load as a fraction of M g: 1 here; 0.25 only in `sldemo` (MathWorks' quirk)."""
    lock_ratio: float = field(default=0.01, metadata={"unit_interval": True})
    """The wheel counts as locked while w R < lock_ratio v."""


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
    )


@dataclass(frozen=True)
class Preset:
    """A named parameter set, with controller parameter defaults that belong to it."""

    info: PresetInfo
    params: AbsWheelParams
    controller_defaults: Mapping[str, float] = field(default_factory=dict)


PRESETS: dict[str, Preset] = {
    "paper-derlsp-ao": Preset(
        PresetInfo(
            "paper-derlsp-ao",
            "Tian et al. (derlsp-ao-abs): M = 100 kg quarter mass, I = 12 kg m^2, R = 0.5 m, "
            "v0 = 30 m/s, K/(s(Ts+1))",
            ("dry-concrete", "wet-asphalt", "ice"),
        ),
        AbsWheelParams(),
    ),
    "paper-fuzzy-immune": Preset(
        PresetInfo(
            "paper-fuzzy-immune",
            "Ding 2023 (fuzzy-immune-abs): R = 0.28 m, J = 25 kg m^2 (as printed), "
            "q in kPa, kq = 25 N m/kPa, M = 300 kg (our assumption)",
            ("asphalt-0.8", "dirt-0.2"),
        ),
        AbsWheelParams(
            mass_kg=300.0, wheel_inertia_kg_m2=25.0, wheel_radius_m=0.28, brake_gain=25.0,
            q_max=800.0,
        ),
    ),
    "sldemo": Preset(
        PresetInfo(
            "sldemo",
            "MathWorks sldemo_absbrake in SI, with its quarter-load-on-whole-mass quirk",
            ("sldemo-table",),
        ),
        _sldemo_params(),
        {"amplitude": 1.0},
    ),
}


def check_consistency(pp: AbsWheelParams) -> None:
    """Checks across fields: a stop speed below v0 and an RK4 step the plant tolerates."""
    if pp.v0_m_s <= pp.v_stop_m_s:
        raise InputError("params.v0_m_s", f"must exceed v_stop_m_s = {pp.v_stop_m_s:g}, "
                         f"got {pp.v0_m_s:g}")
    if pp.dt_s > 0.01:
        raise InputError("params.dt_s", f"must be at most 0.01 s for a stable RK4 step, got "
                         f"{pp.dt_s:g}")
    if pp.t_max_s < 10 * pp.dt_s:
        raise InputError("params.t_max_s", f"must be at least 10 steps, got {pp.t_max_s:g}")
    if pp.t_max_s / pp.dt_s > 5e7:
        raise InputError("params.dt_s", "too many steps (t_max_s / dt_s above 5e7)")
