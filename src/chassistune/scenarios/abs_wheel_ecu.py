"""The ECU mode of the abs-wheel scenarios (docs/ecu.md): `ecu = ideal` (the ideal
kernel, bit for bit) or `realistic` (`sim.abs_wheel_ecu_kernel` with the `EcuParams` given as
parameters and the discrete laws of `controllers.discrete`).

`ecu_setup` reads the mode and the ECU parameters from a scenario's parameter values and packs
what the realistic kernel needs; `law_params` turns a population of gain rows into the discrete
law's parameter rows.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

import numpy as np
from numpy.typing import NDArray

from chassistune.controllers import discrete, laws
from chassistune.controllers.ecu_params import EcuParams, draw_noise, ecu_params, orifice_gains
from chassistune.errors import InputError
from chassistune.params import to_float
from chassistune.plants.abs_wheel import AbsWheelParams
from chassistune.sim import abs_wheel_ecu_layout as EL

ECU_MODES = ("ideal", "realistic")
ECU_PARAM_NAMES = frozenset({f.name for f in fields(EcuParams)} | {"fuzzy_table_points"})
"""Parameters read in realistic mode only (in ideal mode they are unknown parameters)."""

_VREF_CODES = {"true": 0, "slew-limited": 1, "accel": 2}


@dataclass(frozen=True)
class EcuSetup:
    """A resolved realistic ECU: its parameters and the kernel's inputs."""

    params: EcuParams
    table_points: int
    vector: NDArray[np.float64]
    table: NDArray[np.float64]
    grid: NDArray[np.float64]
    noise: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]

    def echo(self) -> dict[str, Any]:
        """The ECU parameters by name (the scenario's parameter echo)."""
        out: dict[str, Any] = {f.name: getattr(self.params, f.name) for f in fields(EcuParams)}
        out["fuzzy_table_points"] = self.table_points
        out["ecu"] = "realistic"
        return out


def ecu_mode(values: Mapping[str, object]) -> str:
    """The `ecu` parameter: ideal (default) or realistic."""
    mode = str(values.get("ecu", "ideal"))
    if mode not in ECU_MODES:
        raise InputError("params.ecu", f"must be one of {', '.join(ECU_MODES)}, got {mode!r}")
    return mode


def table_points(values: Mapping[str, object]) -> int:
    """`fuzzy_table_points` (nodes per input of the ECU lookup table), checked."""
    if "fuzzy_table_points" not in values:
        return discrete.DEFAULT_TABLE_POINTS
    n = to_float(values["fuzzy_table_points"], "params.fuzzy_table_points")
    if not (n == math.floor(n) and 2 <= n <= 1025):
        raise InputError(
            "params.fuzzy_table_points", f"must be a whole number from 2 to 1025, got {n:g}"
        )
    return int(n)


def ecu_setup(
    values: Mapping[str, object],
    controller: str,
    ctrl_values: Mapping[str, Any],
    plant: AbsWheelParams,
    seed: int,
) -> EcuSetup:
    """The realistic ECU of a scenario from its parameter values (names in ECU_PARAM_NAMES).

    ecu_ts_s must be a whole number of integration steps (the limit test needs the ticks on
    step boundaries)."""
    p, _ = ecu_params(
        {k: v for k, v in values.items() if k in ECU_PARAM_NAMES and k != "fuzzy_table_points"}
    )
    if laws.get(controller).ecu is None:
        raise InputError("controller", f"{controller!r} has no form in the realistic ECU")
    m = round(p.ecu_ts_s / plant.dt_s)
    if m < 1 or abs(m * plant.dt_s - p.ecu_ts_s) > 1e-9 * p.ecu_ts_s:
        raise InputError(
            "params.ecu_ts_s",
            f"must be a whole number of steps dt_s = {plant.dt_s:g}, got {p.ecu_ts_s:g}",
        )
    kb, kd = orifice_gains(p, plant.q_max, 0.0)
    amplitude = ctrl_values.get("amplitude", plant.q_max / (0.15 * plant.actuator_gain))
    vector = EL.pack_ecu(
        {
            "law": laws.kind(controller),
            "steps_per_tick": m,
            "delay_samples": p.ecu_delay_samples,
            "toothed": p.sensor == "toothed",
            "teeth": p.sensor_teeth,
            "timer_s": p.sensor_timer_s,
            "stale_bound": p.sensor_stale == "bound",
            "vref_mode": _VREF_CODES[p.vref],
            "vref_decel_max_m_s2": p.vref_decel_max_m_s2,
            "accel_bias_m_s2": p.accel_bias_m_s2,
            "vref_agree_m_s": p.vref_agree_m_s,
            "free_pressure": p.vref_free_pressure * plant.q_max,
            "vref_agree_m_s2": p.vref_agree_m_s2,
            "anchor_samples": max(1, math.ceil(p.vref_anchor_s / p.ecu_ts_s - 1e-9)),
            "three_state": p.valves == "three-state",
            "kb": kb,
            "kd": kd,
            "dead_time_s": p.valve_dead_time_s,
            "min_on_s": p.valve_min_on_s,
            "cutout_m_s": p.abs_cutout_m_s,
            "scheduled": p.gain_schedule == "speed",
            "schedule_floor": p.gain_schedule_floor,
            "amplitude": amplitude,
        }
    )
    points = table_points(values)
    law = discrete.law(controller)
    table, grid = discrete.no_table()
    if law is not None and law.table_outputs:
        from chassistune.fuzzy.loader import load_rulebase

        table, grid, _ = discrete.ecu_table(
            load_rulebase(str(ctrl_values["rulebase"]), "params.rulebase"), points
        )
    noise = draw_noise(p, seed)
    return EcuSetup(
        p, points, vector, table, grid, (noise.spacing_rad, noise.jitter_s, noise.accel_noise_m_s2)
    )


def law_params(
    controller: str,
    gain_names: tuple[str, ...],
    gains: NDArray[np.float64],
    ctrl_values: Mapping[str, Any],
    target_slip: float,
    ts_s: float,
    wheel_radius_m: float,
) -> NDArray[np.float64]:
    """The discrete law's parameter rows (n, P) for gain rows (n, k); one zero column for the
    laws without a discrete form (none, bang-bang: the kernel reads the ECU vector)."""
    law = discrete.law(controller)
    if law is None:
        return np.zeros((gains.shape[0], 1))
    fixed = {k: float(v) for k, v in ctrl_values.items() if not isinstance(v, str)}
    fixed.setdefault("n_filter", 100.0)
    fixed.update(target_slip=target_slip, ts_s=ts_s, wheel_radius_m=wheel_radius_m)
    cols = [
        gains[:, gain_names.index(n)] if n in gain_names else np.full(gains.shape[0], fixed[n])
        for n in law.params
    ]
    return np.ascontiguousarray(np.stack(cols, axis=1))
