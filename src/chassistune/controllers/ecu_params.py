"""Parameters of the ECU model: sampling, wheel-speed sensor, reference speed, valves.

One frozen dataclass, `EcuParams`; every field carries its unit, default and source in its
metadata (`unit`, `source`) and its docstring. `ecu_params(values)` overrides fields by name
(`--param NAME=VALUE`) and validates them, raising `InputError` naming the field
(`params.NAME`, the domain's field path). The random
parts (tooth-spacing error, edge jitter, accelerometer noise) are drawn here, once per run from
the run's seed, and handed to the compiled step functions of `chassistune.controllers.ecu` as
arrays: the kernels draw nothing.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np
from numpy.typing import NDArray

from chassistune._rng import make_rng
from chassistune.errors import InputError
from chassistune.params import override

SENSORS = ("ideal", "toothed")
SENSOR_STALE = ("hold", "bound")
VREFS = ("true", "slew-limited", "accel")
VALVES = ("continuous", "three-state")
GAIN_SCHEDULES = ("off", "speed")

MAX_DELAY_SAMPLES = 8
"""Longest computation delay (the kernels reserve this many command slots per candidate)."""
MAX_SPACING_ERROR = 0.2
"""Largest accepted spacing-error std (fraction of the pitch); draws are clipped at 0.45 pitch so
that the edges stay in order."""
SPACING_CLIP = 0.45


def _meta(unit: str, source: str, **checks: bool) -> dict[str, Any]:
    return {"unit": unit, "source": source, **checks}


SRC_SERVICE = (
    "service manuals: 'up to 10 activation cycles per second' (Saab 900 ABS, WIS "
    "5-brakes/abs-2e); the 5 ms period, well inside that, is our choice (docs/ecu.md, "
    "section 'Parameters')"
)
SRC_TONE = (
    "48 pulses per wheel turn from the ABS ring of BMW E36/E46 (MSS54 calibration "
    "notes, github.com/saildot4k/MSS54-XDFs wiki 'Gearing and Gear Detection'); 44 teeth "
    "and a 1-2000 Hz sensor range (Hyundai Tiburon 2007 service manual)"
)
SRC_ASSUMED = "our assumption (no primary source found); stated in docs/ecu.md"


@dataclass(frozen=True)
class EcuParams:
    """The ECU between plant and controller (docs/ecu.md). SI units."""

    ecu_ts_s: float = field(default=5e-3, metadata=_meta("s", SRC_SERVICE, positive=True))
    """Control period: the controller runs every ecu_ts_s (zero-order hold in between)."""
    ecu_delay_samples: int = field(
        default=1,
        metadata=_meta(
            "samples",
            "our choice: one sample of computation delay (docs/ecu.md, section 'Parameters')",
            nonnegative=True,
        ),
    )
    """Computation delay: the command computed at tick k is applied at tick k + delay."""
    sensor: str = field(
        default="toothed",
        metadata=_meta("-", "our choice (docs/ecu.md, section 'Toothed-wheel sensor')"),
    )
    """Wheel-speed sensor: `ideal` (true wheel speed) or `toothed` (edge timing)."""
    sensor_teeth: int = field(default=48, metadata=_meta("teeth", SRC_TONE, positive=True))
    """Teeth of the tone wheel; one edge per tooth (pitch 2 pi / teeth)."""
    sensor_timer_s: float = field(
        default=1e-6,
        metadata=_meta(
            "s",
            "our choice: a 1 MHz capture timer (docs/ecu.md, section 'Toothed-wheel sensor')",
            positive=True,
        ),
    )
    """Resolution of the ECU's edge capture timer (edge times are floored to it)."""
    sensor_spacing_error: float = field(
        default=0.0, metadata=_meta("pitch", SRC_ASSUMED, nonnegative=True)
    )
    """Std of each tooth edge's angular position error, as a fraction of the pitch (0: perfect
    wheel); drawn once per run, periodic with the revolution."""
    sensor_jitter_s: float = field(default=0.0, metadata=_meta("s", SRC_ASSUMED, nonnegative=True))
    """Std of the edge-time jitter (added before the timer floors the time); 0: none."""
    sensor_stale: str = field(
        default="hold",
        metadata=_meta(
            "-", "our choice: the plain ECU's hold (docs/ecu.md, section 'Toothed-wheel sensor')"
        ),
    )
    """Without a new edge: `hold` the last estimate, or `bound` it by pitch / (time since the
    last edge) (a wheel that shows no edge cannot turn faster than that)."""
    vref: str = field(
        default="accel",
        metadata=_meta(
            "-",
            "measured (docs/ecu.md): with the slew-limited estimate every controller locks "
            "the wheel in the R13-H test, with `accel` none does on dry and wet; a longitudinal "
            "accelerometer on board is our assumption",
        ),
    )
    """Reference (vehicle) speed: `true`, `slew-limited` or `accel` (the default)."""
    vref_decel_max_m_s2: float = field(
        default=11.77,
        metadata=_meta(
            "m/s^2", "our assumption: 1.2 g, above the deceleration on a dry road", positive=True
        ),
    )
    """a_max of the slew-limited estimate vref_k = max(wheel, vref_k-1 - a_max ts)."""
    accel_bias_m_s2: float = field(default=0.1, metadata=_meta("m/s^2", SRC_ASSUMED))
    """Accelerometer bias (about 10 mg) of the `accel` estimate."""
    accel_noise_m_s2: float = field(
        default=0.05, metadata=_meta("m/s^2", SRC_ASSUMED, nonnegative=True)
    )
    """Accelerometer white-noise std per control sample."""
    vref_agree_m_s: float = field(default=0.3, metadata=_meta("m/s", SRC_ASSUMED, nonnegative=True))
    """The `accel` estimate re-anchors to the wheel speed when they agree within this."""
    vref_free_pressure: float = field(
        default=0.01, metadata=_meta("supply", SRC_ASSUMED, unit_interval=True)
    )
    """A wheel counts as free (re-anchors the `accel` estimate) while the ECU's pressure model
    is at most this fraction of the supply pressure ..."""
    vref_agree_m_s2: float = field(
        default=0.5, metadata=_meta("m/s^2", SRC_ASSUMED, nonnegative=True)
    )
    """... and its acceleration is within this of the measured vehicle acceleration."""
    vref_anchor_s: float = field(
        default=0.02,
        metadata=_meta(
            "s",
            "our assumption, measured in docs/ecu.md (re-anchoring on one sample let the "
            "estimate follow the wheel down on ice)",
            nonnegative=True,
        ),
    )
    """... for at least this long without a break (ceil(vref_anchor_s / ecu_ts_s) samples,
    at least one)."""
    valves: str = field(
        default="three-state",
        metadata=_meta("-", "our choice (docs/ecu.md, section 'Three-state modulator')"),
    )
    """Modulator: `continuous` (the K/(s(Ts+1)) actuator) or `three-state` (build/hold/dump)."""
    valve_build_time_s: float = field(
        default=0.15,
        metadata=_meta(
            "s", "DESIGN 3.1: the driver's demand reaches q_max in 0.15 s", positive=True
        ),
    )
    """Time for the open inlet to fill the brake from the return to the supply pressure; sets
    k_b = 2 sqrt(p_supply - p_return) / build_time in dp/dt = k_b sqrt(p_supply - p)."""
    valve_dump_time_s: float = field(default=0.06, metadata=_meta("s", SRC_ASSUMED, positive=True))
    """Time for the open outlet to empty the brake from supply to return pressure (k_d)."""
    valve_dead_time_s: float = field(
        default=2e-3,
        metadata=_meta("s", "our assumption: solenoid switching in a few ms", nonnegative=True),
    )
    """Delay between a valve command and the valve's motion."""
    valve_min_on_s: float = field(default=2e-3, metadata=_meta("s", SRC_ASSUMED, nonnegative=True))
    """Minimum time a valve state is held (pulses are quantized to 0 or at least this)."""
    abs_cutout_m_s: float = field(
        default=2.0,
        metadata=_meta(
            "m/s",
            "ABS active above 3-5 mph (Dodge Grand Caravan 1998 service manual); 2 m/s, within "
            "that range, is our choice",
            nonnegative=True,
        ),
    )
    """Below this reference speed ABS control stops (latched) and the brake builds to the
    driver's demand."""
    gain_schedule: str = field(
        default="off",
        metadata=_meta(
            "-",
            "our choice: the gains as tuned (docs/ecu.md, section 'Low-speed cut-out and "
            "speed-scheduled gains')",
        ),
    )
    """`speed`: kp and kd scaled by v_ref / v0 (the wheel's gain grows as 1/v); `off`."""
    gain_schedule_floor: float = field(
        default=0.05, metadata=_meta("-", SRC_ASSUMED, unit_interval=True)
    )
    """Smallest scaling factor of the speed schedule."""


_CHOICES: dict[str, tuple[str, ...]] = {
    "sensor": SENSORS,
    "sensor_stale": SENSOR_STALE,
    "vref": VREFS,
    "valves": VALVES,
    "gain_schedule": GAIN_SCHEDULES,
}


def check_ecu(p: EcuParams, where: str = "params.") -> EcuParams:
    """Choices, integer ranges and the cross-checks of `p` (ranges of floats: `validate`)."""
    for name, choices in _CHOICES.items():
        value = getattr(p, name)
        if value not in choices:
            raise InputError(
                f"{where}{name}", f"must be one of {', '.join(choices)}, got {value!r}"
            )
    if p.sensor_teeth < 1 or p.sensor_teeth > 10_000_000:
        raise InputError(f"{where}sensor_teeth", f"must be in 1..1e7, got {p.sensor_teeth}")
    if p.ecu_delay_samples > MAX_DELAY_SAMPLES:
        raise InputError(
            f"{where}ecu_delay_samples",
            f"must be at most {MAX_DELAY_SAMPLES}, got {p.ecu_delay_samples}",
        )
    if p.sensor_spacing_error > MAX_SPACING_ERROR:
        raise InputError(
            f"{where}sensor_spacing_error",
            f"must be at most {MAX_SPACING_ERROR} "
            f"of the pitch (edges must stay in order), got "
            f"{p.sensor_spacing_error:g}",
        )
    if p.valve_dead_time_s >= p.ecu_ts_s:
        raise InputError(
            f"{where}valve_dead_time_s",
            f"must be below ecu_ts_s = {p.ecu_ts_s:g}, got {p.valve_dead_time_s:g}",
        )
    if p.valve_min_on_s > 0.5 * p.ecu_ts_s:
        raise InputError(
            f"{where}valve_min_on_s",
            f"must be at most ecu_ts_s / 2 = "
            f"{0.5 * p.ecu_ts_s:g} (a pulse and its hold must both fit in a "
            f"period), got {p.valve_min_on_s:g}",
        )
    return p


def ecu_params(
    values: Mapping[str, object], base: EcuParams | None = None, where: str = "params."
) -> tuple[EcuParams, set[str]]:
    """`base` (defaults) with the fields named in `values` replaced and checked; names used.
    Errors name the field as `where` + field name."""
    p, used = override(base or EcuParams(), values, where)
    return check_ecu(p, where), used


def field_table() -> list[dict[str, Any]]:
    """Name, default, unit and source of every field (docs and `list` output)."""
    return [
        {
            "name": f.name,
            "default": f.default,
            "unit": f.metadata["unit"],
            "source": f.metadata["source"],
        }
        for f in fields(EcuParams)
    ]


def orifice_gains(p: EcuParams, p_supply: float, p_return: float) -> tuple[float, float]:
    """(k_b, k_d) of dp/dt = k_b sqrt(p_supply - p), -k_d sqrt(p - p_return).

    From the exact solution sqrt(p_supply - p(t)) = sqrt(p_supply - p0) - k_b t / 2, a full
    build from p_return takes 2 sqrt(p_supply - p_return) / k_b (likewise the dump).
    """
    if not p_supply > p_return:
        raise InputError(
            "p_supply", f"must exceed the return pressure {p_return:g}, got {p_supply:g}"
        )
    root = math.sqrt(p_supply - p_return)
    return 2.0 * root / p.valve_build_time_s, 2.0 * root / p.valve_dump_time_s


@dataclass(frozen=True)
class EcuNoise:
    """The run's pre-drawn random inputs of the compiled ECU steps."""

    spacing_rad: NDArray[np.float64]
    """Edge angle error of each tooth (length teeth, or a single 0 for a perfect wheel)."""
    jitter_s: NDArray[np.float64]
    """Edge-time jitter, used cyclically by edge number (a single 0 when off)."""
    accel_noise_m_s2: NDArray[np.float64]
    """Accelerometer noise per control sample, used cyclically (a single 0 when off)."""


def draw_noise(p: EcuParams, seed: int, n_edges: int = 4096, n_samples: int = 16384) -> EcuNoise:
    """Draw the spacing errors, jitters and accelerometer noise from `seed` (fixed order).

    Spacing errors are zero-mean normal with std `sensor_spacing_error` pitches, demeaned and
    clipped at 0.45 pitch (edges stay in order); jitter and accelerometer noise are normal.
    """
    rng = make_rng(np.random.SeedSequence([seed, 15]))
    pitch = 2.0 * math.pi / p.sensor_teeth
    zero = np.zeros(1)
    spacing = zero
    if p.sensor_spacing_error > 0.0:
        d = rng.normal(0.0, p.sensor_spacing_error, p.sensor_teeth)
        d -= d.mean()
        spacing = np.clip(d, -SPACING_CLIP, SPACING_CLIP) * pitch
    jitter = rng.normal(0.0, p.sensor_jitter_s, n_edges) if p.sensor_jitter_s > 0.0 else zero
    accel = rng.normal(0.0, p.accel_noise_m_s2, n_samples) if p.accel_noise_m_s2 > 0.0 else zero
    return EcuNoise(spacing, jitter, accel)
