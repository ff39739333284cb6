"""Quarter-car parameters and presets (design.md 3.4; Jing and Xu 2023, `iabc-suspension` Table 1),
apart from the compiled model (`plants.quarter_car`) so that listing presets imports no numba.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from chassistune.params import positive
from chassistune.plants.presets import Preset, PresetInfo

G_M_S2 = 9.80665


@dataclass(frozen=True)
class QuarterCarParams:
    """Vehicle: 2-DOF quarter car of `iabc-suspension` Table 1 (SI). The plausible ranges span
    a quarter of a small car to a loaded truck's axle end, and the paper's stiff damper."""

    sprung_mass_kg: float = field(default=320.0, metadata=positive(50.0, 3000.0))
    unsprung_mass_kg: float = field(default=45.0, metadata=positive(5.0, 500.0))
    spring_n_m: float = field(default=17000.0, metadata=positive(1e3, 1e6))
    damper_n_s_m: float = field(default=12000.0, metadata=positive(100.0, 5e4))
    tire_stiffness_n_m: float = field(default=200000.0, metadata=positive(5e4, 5e6))

    @property
    def damping_ratio(self) -> float:
        """Body-mode damping ratio of the passive suspension, cs / (2 sqrt(ks ms))."""
        return self.damper_n_s_m / (2.0 * math.sqrt(self.spring_n_m * self.sprung_mass_kg))

    @property
    def static_tire_load_n(self) -> float:
        """(ms + mu) g."""
        return (self.sprung_mass_kg + self.unsprung_mass_kg) * G_M_S2


PRESETS: dict[str, Preset[QuarterCarParams]] = {
    "paper-iabc": Preset(
        PresetInfo(
            "paper-iabc",
            "Jing and Xu 2023 (iabc-suspension) Table 1 as printed: ms = 320 kg, mu = 45 kg, "
            "ks = 17 kN/m, kt = 200 kN/m, cs = 12000 N s/m (damping ratio 2.57, about ten times "
            "a car's), 20 m/s",
            ("iso-b", "iso-c"),
        ),
        QuarterCarParams(),
    ),
    "typical": Preset(
        PresetInfo(
            "typical",
            "paper-iabc with a car's damper cs = 1200 N s/m (damping ratio 0.26)",
            ("iso-b", "iso-c"),
        ),
        QuarterCarParams(damper_n_s_m=1200.0),
    ),
}
