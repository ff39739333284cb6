"""Scenarios of the single-wheel ABS plant `abs-wheel` (DESIGN 3.1): preset + road + controller
+ scoring, fed to the compiled kernel `chassistune.sim.abs_wheel_kernel.simulate_abs_wheel`.

The physics (parameters, presets) is `chassistune.plants.abs_wheel`; roads `plants.roads`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from chassistune.controllers import catalogue
from chassistune.controllers.specs import ControllerSpec
from chassistune.errors import InputError
from chassistune.params import as_dict, override, to_float, validate
from chassistune.plants.abs_wheel import PRESETS, AbsWheelParams, check_consistency
from chassistune.plants.presets import PresetInfo
from chassistune.plants.roads import friction_roads, tire_for_road
from chassistune.plants.tires import TireCurve
from chassistune.scenarios.base import (
    PENALTY,
    Plant,
    Scenario,
    Trace,
    json_scalar,
    pick_preset,
)
from chassistune.scenarios.registry import ABS_WHEEL
from chassistune.sim import abs_wheel_kernel as K
from chassistune.sim.batch import run_chunked

_POS = {"positive": True}
_NONNEG = {"nonnegative": True}


@dataclass(frozen=True)
class Scoring:
    """How runs become costs (DESIGN 5)."""

    lock_penalty_per_s: float = field(default=100.0, metadata=_NONNEG)
    hopeless_factor: float = field(default=3.0, metadata=_POS)
    """Stop a candidate early once its distance exceeds this many times the bound."""


KERNEL_KIND = {"none": K.C_NONE, "pid": K.C_PID, "bang-bang": K.C_BANGBANG,
               "threshold": K.C_THRESHOLD, "fuzzy-pid": K.C_FUZZY_PID,
               "fuzzy-immune-pid": K.C_IMMUNE}
FUZZY_OUTPUTS = {"fuzzy-pid": 3, "fuzzy-immune-pid": 1}
"""How many outputs each fuzzy controller reads from its rule base (two inputs: e, de/dt)."""


def _no_surface() -> tuple[Any, ...]:
    """A placeholder surface of the kernel's table type, for controllers without a rule base."""
    return (np.zeros((1, 2, 2)), np.full((1, 1), -1, dtype=np.int32), np.zeros(0, dtype=np.int64),
            np.zeros(0, dtype=np.int64), np.zeros(0), 0.0, 1.0, 0.0, 1.0)


def fuzzy_table(controller: str, rulebase: str) -> tuple[Any, ...]:
    """The compiled surface of `rulebase` for `controller`, checked for its inputs and outputs."""
    from chassistune.fuzzy.loader import load_rulebase
    from chassistune.fuzzy.surface import compiled

    rb = load_rulebase(rulebase, "params.rulebase")
    need = FUZZY_OUTPUTS[controller]
    if len(rb.inputs) != 2 or len(rb.outputs) != need:
        raise InputError("params.rulebase", f"{controller} needs a rule base with inputs (e, ec) "
                         f"and {need} output(s); {rulebase!r} has {len(rb.inputs)} inputs and "
                         f"{len(rb.outputs)} outputs")
    return compiled(rb).table

METRIC_COLUMNS = {
    "stop_time_s": K.M_TIME,
    "stop_distance_m": K.M_DIST,
    "wheel_lock_time_s": K.M_LOCK_T,
    "slip_iae": K.M_IAE,
    "slip_itae": K.M_ITAE,
    "slip_ise": K.M_ISE,
    "mean_slip": K.M_MEAN_SLIP,
    "peak_slip": K.M_PEAK_SLIP,
    "locked_time_s": K.M_LOCKED_S,
    "slip_clip_max": K.M_CLIP,
    "min_slip_unclipped": K.M_MIN_SLIP,
}
STATUS_NAMES = {K.STATUS_STOPPED: "stopped", K.STATUS_HOPELESS: "hopeless",
                K.STATUS_TIMEOUT: "timeout", K.STATUS_DIVERGED: "diverged"}
OBJECTIVE_COLUMNS = {"itae": K.M_ITAE, "iae": K.M_IAE, "ise": K.M_ISE,
                     "distance": K.M_DIST, "time": K.M_TIME}


class AbsWheelScenario(Scenario):
    """A resolved abs-wheel scenario; evaluates populations of gain rows in one kernel call."""

    objectives = tuple(OBJECTIVE_COLUMNS)
    default_objective = "itae"

    def __init__(
        self,
        preset: str,
        road: str,
        controller: ControllerSpec,
        plant_params: AbsWheelParams,
        tire: TireCurve,
        controller_params: dict[str, Any],
        target_slip: float,
        scoring: Scoring,
        seed: int,
    ) -> None:
        self.plant = "abs-wheel"
        self.preset = preset
        self.road = road
        self.controller = controller
        self.plant_params = plant_params
        self.tire = tire
        self.controller_params = controller_params
        self.scoring = scoring
        self.seed = seed
        self.mu_peak, self.slip_at_peak, _ = tire.peak()
        self.target_slip = target_slip
        pp = plant_params
        decel = self.mu_peak * pp.g_m_s2 * pp.load_fraction
        self.bound_distance_m = (pp.v0_m_s**2 - pp.v_stop_m_s**2) / (2.0 * decel)
        self.bound_time_s = (pp.v0_m_s - pp.v_stop_m_s) / decel
        self._kernel_args = self._pack()

    def _pack(self) -> tuple[Any, ...]:
        pp = self.plant_params
        p = np.zeros(K.N_PLANT)
        p[K.P_MASS] = pp.mass_kg
        p[K.P_INERTIA] = pp.wheel_inertia_kg_m2
        p[K.P_RADIUS] = pp.wheel_radius_m
        p[K.P_V0] = pp.v0_m_s
        p[K.P_G] = pp.g_m_s2
        p[K.P_K] = pp.actuator_gain
        p[K.P_TAU] = pp.actuator_tau_s
        p[K.P_KQ] = pp.brake_gain
        p[K.P_QMAX] = pp.q_max
        p[K.P_VSTOP] = pp.v_stop_m_s
        p[K.P_TMAX] = pp.t_max_s
        p[K.P_DT] = pp.dt_s
        p[K.P_LOAD] = pp.load_fraction
        p[K.P_TARGET] = self.target_slip
        p[K.P_HOPELESS_M] = self.scoring.hopeless_factor * self.bound_distance_m
        p[K.P_LOCK_RATIO] = pp.lock_ratio
        p[K.P_NFILTER] = self.controller_params.get("n_filter", 100.0)
        cp = self.controller_params
        c = np.zeros(K.N_CTRL)
        c[K.Q_TS] = cp.get("ts_s", self.plant_params.dt_s)
        c[K.Q_AMPLITUDE] = cp.get("amplitude", 0.0)
        c[K.Q_DECEL] = cp.get("decel_threshold_m_s2", 0.0)
        c[K.Q_ACCEL] = cp.get("accel_threshold_m_s2", 0.0)
        c[K.Q_SLIP_HIGH] = cp.get("slip_margin", 0.0)
        c[K.Q_SLOW] = cp.get("slow_fraction", 0.0)
        kind, coef, xs, ys = self.tire.kernel_data()
        name = self.controller.name
        table = (fuzzy_table(name, str(self.controller_params["rulebase"]))
                 if name in FUZZY_OUTPUTS else _no_surface())
        return p, kind, coef, xs, ys, KERNEL_KIND[name], c, table

    def params(self) -> dict[str, Any]:
        out: dict[str, Any] = as_dict(self.plant_params)
        out.update(as_dict(self.tire) if dataclasses.is_dataclass(self.tire) else {})
        if self.road == "sldemo-table":
            out = {k: v for k, v in out.items() if k not in ("slips", "mus")}
        out["target_slip"] = self.target_slip
        out.update(self.controller_params)
        out.update(as_dict(self.scoring))
        out["seed"] = self.seed
        return out

    def _kernel_gains(self, gains: np.ndarray) -> np.ndarray:
        g = np.asarray(gains, dtype=np.float64)
        if g.ndim == 1:
            g = g[None, :]
        k = len(self.gain_names)
        if g.ndim != 2 or g.shape[1] != k:
            raise InputError("gains", f"expected shape (n, {k}) for {self.controller.name}, got "
                             f"{tuple(np.shape(gains))}")
        if k == 0:  # laws without gains: the kernel reads no column
            return np.zeros((g.shape[0], 1))
        return np.ascontiguousarray(g)

    def raw(self, gains: np.ndarray, workers: int | None = None) -> np.ndarray:
        """The kernel's metrics matrix (n, N_METRICS) for a population of gain rows."""
        p, kind, coef, xs, ys, ckind, c, table = self._kernel_args
        empty = np.zeros((0, K.N_TRACE))

        def call(g: np.ndarray, out: np.ndarray) -> None:
            K.simulate_abs_wheel(g, p, kind, coef, xs, ys, ckind, c, table, empty, out)

        return run_chunked(call, self._kernel_gains(gains), K.N_METRICS, workers)

    def metrics_from_raw(self, raw: np.ndarray) -> dict[str, np.ndarray]:
        out = {name: raw[:, col].copy() for name, col in METRIC_COLUMNS.items()}
        status = raw[:, K.M_STATUS].astype(int)
        out["stopped"] = status == K.STATUS_STOPPED
        names = np.array([STATUS_NAMES[k] for k in range(len(STATUS_NAMES))])
        out["status"] = names[status]
        out["bound_distance_m"] = np.full(raw.shape[0], self.bound_distance_m)
        out["bound_time_s"] = np.full(raw.shape[0], self.bound_time_s)
        out["distance_ratio"] = raw[:, K.M_DIST] / self.bound_distance_m
        return out

    def metrics(self, gains: np.ndarray) -> dict[str, np.ndarray]:
        return self.metrics_from_raw(self.raw(gains))

    def cost_from_raw(self, raw: np.ndarray, objective: str | None = None) -> np.ndarray:
        objective = objective or self.default_objective
        if objective not in OBJECTIVE_COLUMNS:
            raise InputError("objective", f"unknown objective {objective!r} for abs-wheel "
                             f"(known: {', '.join(OBJECTIVE_COLUMNS)})")
        cost = raw[:, OBJECTIVE_COLUMNS[objective]] + (
            self.scoring.lock_penalty_per_s * raw[:, K.M_LOCKED_S]
        )
        bad = (raw[:, K.M_STATUS] != K.STATUS_STOPPED) | ~np.isfinite(cost)
        return np.where(bad, PENALTY, np.minimum(cost, PENALTY))

    def cost(self, gains: np.ndarray, objective: str | None = None) -> np.ndarray:
        return self.cost_from_raw(self.raw(gains), objective)

    def trace(self, gains: np.ndarray) -> Trace:
        p, kind, coef, xs, ys, ckind, c, table = self._kernel_args
        g = self._kernel_gains(np.asarray(gains, dtype=np.float64).reshape(1, -1))
        n_rows = math.ceil(self.plant_params.t_max_s / self.plant_params.dt_s) + 2
        tr = np.zeros((n_rows, K.N_TRACE))
        out = np.zeros((1, K.N_METRICS))
        K.simulate_abs_wheel(g, p, kind, coef, xs, ys, ckind, c, table, tr, out)
        m = int(out[0, K.M_NTRACE])
        cols = {
            "time_s": K.T_TIME, "vehicle_speed_m_s": K.T_V, "wheel_speed_m_s": K.T_WHEEL_V,
            "slip": K.T_SLIP, "target_slip": K.T_TARGET, "pressure": K.T_Q,
            "brake_torque_n_m": K.T_TB, "command": K.T_U, "distance_m": K.T_X, "mu": K.T_MU,
        }
        signals = {name: tr[:m, col].copy() for name, col in cols.items()}
        metrics = {k: json_scalar(v[0]) for k, v in self.metrics_from_raw(out).items()}
        units = {"time_s": "s", "vehicle_speed_m_s": "m/s", "wheel_speed_m_s": "m/s",
                 "slip": "-", "target_slip": "-", "pressure": "preset unit",
                 "brake_torque_n_m": "N m", "command": "-", "distance_m": "m", "mu": "-"}
        return Trace(signals, metrics, units)



class AbsWheelPlant(Plant):
    """The single-wheel ABS plant."""

    spec = ABS_WHEEL

    def presets(self) -> dict[str, PresetInfo]:
        return {n: p.info for n, p in PRESETS.items()}

    def roads(self) -> dict[str, str]:
        return friction_roads()

    def controllers(self) -> list[ControllerSpec]:
        return catalogue.for_plant(ABS_WHEEL.name)

    def scenario(
        self,
        preset: str | None = None,
        road: str | None = None,
        controller: str = "none",
        params: Mapping[str, object] | None = None,
        seed: int = 0,
    ) -> AbsWheelScenario:
        preset = pick_preset(self.name, preset, self.default_preset, PRESETS)
        pre = PRESETS[preset]
        road = road or pre.info.roads[0]
        spec = catalogue.get(ABS_WHEEL.name, controller)
        values = dict(params or {})
        plant_params, used = override(pre.params, values)
        tire, used_tire = tire_for_road(road, values)
        scoring, used_scoring = override(Scoring(), values)
        used |= used_tire | used_scoring
        ctrl_values: dict[str, Any] = {}
        for ps in spec.params:
            if isinstance(ps.default, str):
                ctrl_values[ps.name] = str(values.get(ps.name, ps.default))
                used.add(ps.name)
                continue
            if ps.name in values:
                ctrl_values[ps.name] = to_float(values[ps.name], f"params.{ps.name}")
                used.add(ps.name)
            elif ps.name in pre.controller_defaults:
                ctrl_values[ps.name] = pre.controller_defaults[ps.name]
            elif isinstance(ps.default, float):
                ctrl_values[ps.name] = ps.default
            if ps.positive and ps.name in ctrl_values and not ctrl_values[ps.name] > 0:
                raise InputError(f"params.{ps.name}", f"must be positive, got "
                                 f"{ctrl_values[ps.name]:g}")
        if "amplitude" in spec.param_names and "amplitude" not in ctrl_values:
            # default command: reaches q_max in 0.15 s through the integrating actuator
            ctrl_values["amplitude"] = plant_params.q_max / (0.15 * plant_params.actuator_gain)
        target = tire.peak()[2]
        if "target_slip" in values:
            target = to_float(values["target_slip"], "params.target_slip")
            if not 0.0 < target < 1.0:
                raise InputError("params.target_slip", f"must be in (0, 1), got {target:g}")
            used.add("target_slip")
        unknown = sorted(set(values) - used)
        if unknown:
            known = sorted(
                {f.name for f in dataclasses.fields(AbsWheelParams)}
                | {f.name for f in dataclasses.fields(tire)}
                | {f.name for f in dataclasses.fields(Scoring)}
                | set(spec.param_names) | {"target_slip"}
            )
            raise InputError(f"params.{unknown[0]}", f"unknown parameter for abs-wheel with "
                             f"{spec.name} on {road} (known: {', '.join(known)})")
        check_consistency(plant_params)
        return AbsWheelScenario(preset, road, spec, validate(plant_params, "params."), tire,
                                ctrl_values, target, scoring, seed)


PLANT = AbsWheelPlant()
