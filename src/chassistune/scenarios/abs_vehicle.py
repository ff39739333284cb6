"""The 7-DOF vehicle ABS scenario and plant (`abs-vehicle`, design.md 3.3; deffao-vehicle-abs).

Resolves preset + road + wheel controller + overrides into the kernel's declared inputs
(`chassistune.sim.abs_vehicle_kernel` layouts), evaluates populations in one kernel call, and
decodes metrics and traces by name.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from chassistune.controllers import laws, vehicle_specs
from chassistune.controllers import yaw_moment_delay as GMA
from chassistune.controllers.specs import ControllerSpec
from chassistune.errors import InputError
from chassistune.params import as_dict, implausible, override, positive, validate
from chassistune.plants.abs_vehicle import (
    RK4_REAL_LIMIT,
    Bound,
    geometry,
    mu_jump_bound,
    split_mu_bound,
    uniform_bound,
    wheel_mode_rate,
)
from chassistune.plants.abs_vehicle_params import (
    MAX_STEER_LIMIT_RAD,
    PRESETS,
    STEERING_MODES,
    SteeringParams,
    VehicleParams,
    steering_on,
)
from chassistune.plants.mf_curve import TIRE_SURFACE
from chassistune.plants.presets import Preset
from chassistune.plants.vehicle_roads import (
    ROAD_MU_JUMP,
    ROAD_SPLIT,
    MuJumpParams,
    SplitMuParams,
    VehicleRoad,
    make_road,
)
from chassistune.scenarios import vehicle_tire
from chassistune.scenarios.abs_wheel import LENGTH_FROM_TIRE, _no_surface, fuzzy_table
from chassistune.scenarios.base import PENALTY, Plant, Scenario, Trace, json_scalar, pick_preset
from chassistune.scenarios.controller_params import kernel_gains, resolve_controller_params
from chassistune.scenarios.registry import ABS_VEHICLE
from chassistune.scenarios.road_knowledge import (
    FIELD,
    TARGET_GAIN,
    controller_spec,
    road_knowledge,
)
from chassistune.scenarios.vehicle_tire import VehicleTire
from chassistune.sim import abs_vehicle_kernel as K
from chassistune.sim import abs_vehicle_layout as VL
from chassistune.sim.batch import run_chunked

PLANT_NAME = ABS_VEHICLE.name


@dataclass(frozen=True)
class VehicleScoring:
    """How runs become costs and yaw metrics (design.md 3.3, 5)."""

    lock_penalty_per_s: float = field(default=100.0, metadata={"nonnegative": True})
    hopeless_factor: float = field(default=3.0, metadata=positive(1.5, 20.0))
    """Stop a candidate early once its path exceeds this many times the bound (must exceed 1:
    every run is at least as long as the bound)."""
    yaw_window_s: float = field(default=1.0, metadata={"positive": True})


OBJECTIVE_COLUMNS = {
    "itae": VL.M_ITAE,
    "iae": VL.M_IAE,
    "ise": VL.M_ISE,
    "distance": VL.M_DIST,
    "time": VL.M_TIME,
    "distance_ratio": VL.M_DIST,
}
PER_BOUND = frozenset({"distance_ratio"})
"""Objectives divided by the road's adhesion-bound distance (design.md 3.3): roads of different
friction compare on one scale, as on the single wheel."""


def road_bound(pp: VehicleParams, road: VehicleRoad, tire: VehicleTire | None = None) -> Bound:
    """The exact bound of design.md 3.3 for this road, or the Magic Formula tire's on it
    (`vehicle_tire.bound`)."""
    if tire is not None:
        return vehicle_tire.bound(pp, road, tire)
    a, b = (t.mu_peak for t in road.surfaces)
    if road.kind == ROAD_MU_JUMP:
        return mu_jump_bound(pp, a, b, road.x_jump_m)
    if road.kind == ROAD_SPLIT:
        return split_mu_bound(pp, a, b)
    return uniform_bound(pp, a)


def _three_digits(x: float, up: bool) -> float:
    """x rounded to three significant digits, up or down (a printed limit that still holds)."""
    unit = 10.0 ** (math.floor(math.log10(x)) - 2)
    return (math.ceil(x / unit) if up else math.floor(x / unit)) * unit


def _passing_step(pp: VehicleParams, lam_1_s: float) -> tuple[float, int]:
    """(dt_s / k, k) for the least whole k with dt_s / k, as printed (six significant digits),
    inside RK4's stability limit at the wheel-mode rate lam_1_s: a whole divisor keeps every
    sample period and t_max whole numbers of steps."""
    k = max(1, math.ceil(lam_1_s * pp.dt_s / RK4_REAL_LIMIT))
    while lam_1_s * float(f"{pp.dt_s / k:.6g}") > RK4_REAL_LIMIT:
        k += 1
    return float(f"{pp.dt_s / k:.6g}"), k


def check_step(pp: VehicleParams, road: VehicleRoad, tire: VehicleTire | None = None) -> None:
    """Refuse a (dt_s, v_stop_m_s) pair past RK4's stability limit of the wheel mode, naming a
    step that passes (`_passing_step`), the largest one and the least v_stop_m_s at this step
    (both rounded to three digits on the passing side). The Magic Formula tire's slope is its
    curve's at zero slip (`vehicle_tire.slope_at_zero_slip`)."""
    mu = max(t.mu_peak for t in road.surfaces)
    if tire is None:
        rise = max(t.mu_peak / t.slip_opt for t in road.surfaces)
    else:
        rise = vehicle_tire.slope_at_zero_slip(pp, tire, mu)
    lam = wheel_mode_rate(pp, rise, mu)
    if lam * pp.dt_s > RK4_REAL_LIMIT:
        dt_pass, k = _passing_step(pp, lam)
        dt_max = _three_digits(RK4_REAL_LIMIT / lam, up=False)
        v_min = _three_digits(pp.v_stop_m_s * lam * pp.dt_s / RK4_REAL_LIMIT, up=True)
        raise InputError(
            "params.dt_s",
            f"dt_s = {pp.dt_s:g} s with v_stop_m_s = "
            f"{pp.v_stop_m_s:g} m/s is past RK4's stability limit of the wheel mode "
            f"(|lambda| dt = {lam * pp.dt_s:.2f} > {RK4_REAL_LIMIT}): dt_s = "
            f"{dt_pass:g} (the step divided by {k}) passes, as does any dt_s <= "
            f"{dt_max:g}, or v_stop_m_s >= {v_min:g}",
        )


def _check_consistency(
    pp: VehicleParams,
    road: VehicleRoad,
    steering: SteeringParams,
    scoring: VehicleScoring,
    tire: VehicleTire | None,
) -> None:
    """Refuse parameter combinations the model does not describe (one InputError naming the
    field)."""
    if steering.max_steer_rad >= MAX_STEER_LIMIT_RAD:
        raise InputError(
            "params.max_steer_rad",
            f"must be below pi/2 = {MAX_STEER_LIMIT_RAD:.4g}"
            f" rad (a wheel turned sideways), got {steering.max_steer_rad:g}",
        )
    if scoring.hopeless_factor <= 1.0:
        raise InputError(
            "params.hopeless_factor",
            f"must exceed 1 (no run is shorter than the bound), got {scoring.hopeless_factor:g}",
        )
    if pp.min_speed_m_s >= pp.v_stop_m_s:
        raise InputError(
            "params.min_speed_m_s",
            f"must be below v_stop_m_s = "
            f"{pp.v_stop_m_s:g} (the slip's speed floor), got {pp.min_speed_m_s:g}",
        )
    if pp.v0_m_s <= pp.v_stop_m_s:
        raise InputError(
            "params.v0_m_s", f"must exceed v_stop_m_s = {pp.v_stop_m_s:g}, got {pp.v0_m_s:g}"
        )
    if pp.t_max_s < 10 * pp.dt_s:
        raise InputError("params.t_max_s", f"must be at least 10 steps, got {pp.t_max_s:g}")
    if pp.t_max_s / pp.dt_s > 5e7:
        raise InputError("params.dt_s", "too many steps (t_max_s / dt_s above 5e7)")
    shortest = pp.v0_m_s * pp.dt_s
    for name in vehicle_tire.LENGTH_FIELDS:
        sigma = getattr(pp, name)
        if 0.0 < sigma < shortest:
            raise InputError(
                f"params.{name}",
                f"must be 0 or at least v0_m_s dt_s = {shortest:g} m (a step no longer than the "
                f"lag's time constant sigma / |u|), got {sigma:g}",
            )
    check_step(pp, road, tire)


def locked_slip_shown(signals: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Each wheel's slip as shown: 1 where the wheel stands still (w = 0) while the car moves,
    else the recorded slip. The recorded one is the ECU's, (u - w R)/|V| clipped to [0, 1]
    (docs/vehicle.md): a locked wheel sliding sideways or backwards (u <= 0, a spinning car)
    records 0 there."""
    moving = signals["speed_m_s"] > 0.0
    return {
        f"slip_{w}": np.where(
            (signals[f"wheel_speed_{w}_m_s"] == 0.0) & moving, 1.0, signals[f"slip_{w}"]
        )
        for w in VL.WHEELS
    }


class AbsVehicleScenario(Scenario):
    """A resolved abs-vehicle scenario; evaluates populations of gain rows in one kernel call."""

    objectives = tuple(OBJECTIVE_COLUMNS)
    default_objective = "itae"

    def __init__(
        self,
        preset: str,
        road: VehicleRoad,
        road_params: dict[str, object],
        controller: ControllerSpec,
        plant_params: VehicleParams,
        steering: SteeringParams,
        controller_params: dict[str, Any],
        scoring: VehicleScoring,
        seed: int,
        knowledge: str = "oracle",
        tire: VehicleTire | None = None,
    ) -> None:
        super().__init__(PLANT_NAME, preset, road.name, controller, seed)
        self.road_knowledge = knowledge
        """`scenarios.road_knowledge`: with `fixed` the last gain is every wheel's target."""
        self.road_spec = road
        self.road_params = road_params
        self.plant_params = plant_params
        self.steering = steering
        self.controller_params = controller_params
        self.scoring = scoring
        self.tire = tire
        """The Magic Formula tire of a TIR file on the road's surfaces, or None (bilinear)."""
        bound = road_bound(plant_params, road, tire)
        self.bound_distance_m = bound.distance_m
        self.bound_time_s = bound.time_s
        self.target_slips = tuple(t.slip_opt for t in road.surfaces)
        self._kernel_args = self._pack()

    def _gain_column(self, name: str) -> int:
        """The column of gain `name` in a gain row, -1 where the law has none of that name."""
        names = self.controller.gain_names
        return names.index(name) if name in names else -1

    def _pack(self) -> tuple[Any, ...]:
        pp, st, cp = self.plant_params, self.steering, self.controller_params
        road = self.road_spec
        values = {
            "mass_kg": pp.mass_kg,
            "yaw_inertia_kg_m2": pp.yaw_inertia_kg_m2,
            "wheel_inertia_kg_m2": pp.wheel_inertia_kg_m2,
            "wheel_radius_m": pp.wheel_radius_m,
            "v0_m_s": pp.v0_m_s,
            "actuator_gain": pp.actuator_gain,
            "actuator_tau_s": pp.actuator_tau_s,
            "brake_gain": pp.brake_gain,
            "front_brake_share": pp.front_brake_share,
            "q_max": pp.q_max,
            "v_stop_m_s": pp.v_stop_m_s,
            "t_max_s": pp.t_max_s,
            "dt_s": pp.dt_s,
            "lock_ratio": pp.lock_ratio,
            "min_speed_m_s": pp.min_speed_m_s,
            "hopeless_m": self.scoring.hopeless_factor * self.bound_distance_m,
            "n_filter": cp.get("n_filter", 100.0),
            "road_kind": road.kind,
            "x_jump_global_m": pp.cg_to_front_m + road.x_jump_m,
            "split_y_m": road.split_y_m,
            "split_by_road": 1.0 if road.split_by == "road" else 0.0,
            "driver": 1.0 if st.steering == "driver" else 0.0,
            "heading_gain": st.heading_gain,
            "yaw_rate_gain_s": st.yaw_rate_gain_s,
            "max_steer_rad": st.max_steer_rad,
            "steer_tau_s": st.steer_tau_s,
            "select_low": 1.0 if cp.get("rear") == "select-low" else 0.0,
            "axle_gains": 1.0 if cp.get("axle_gains") == "per-axle" else 0.0,
            "yaw_window_s": self.scoring.yaw_window_s,
            "target_gain_column": self._gain_column(TARGET_GAIN.name),
            "gma_gain_column": self._gain_column(GMA.RATE_GAIN.name),
        }
        for w in VL.WHEELS:
            values[f"relaxation_length_{w}_m"] = pp.relaxation_length_m
            values[f"lateral_relaxation_length_{w}_m"] = pp.lateral_relaxation_length_m
        p = VL.PLANT_LAYOUT.pack(values)
        geo = geometry(pp)
        surfs = vehicle_tire.surface_rows(road, self.tire, pp.cornering_stiffness_n_rad)
        c = VL.CONTROLLER_LAYOUT.pack(
            {n: cp.get(n, 0.0) for n in VL.CONTROLLER_LAYOUT.names}
            | {"ts_s": cp.get("ts_s", pp.dt_s)}
        )
        base = self.controller.name
        table = (
            fuzzy_table(base, str(cp["rulebase"]))
            if laws.get(base).rulebase_outputs
            else _no_surface()
        )
        return p, geo, surfs, laws.kind(base), c, table

    @property
    def fuzzy_surface(self) -> tuple[Any, ...]:
        """The compiled rule-base surface the wheel laws read (a placeholder for other laws)."""
        table: tuple[Any, ...] = self._kernel_args[5]
        return table

    @property
    def pressure_unit(self) -> str:
        return PRESETS[self.preset].info.pressure_unit

    def params(self) -> dict[str, Any]:
        out: dict[str, Any] = as_dict(self.plant_params)
        out.update(as_dict(self.steering))
        out.update(self.road_params)
        if self.tire is not None:
            out["tire"] = self.tire.path
        if self.road_knowledge == "oracle":
            out["target_slips"] = list(self.target_slips)
        out[FIELD] = self.road_knowledge
        out[GMA.FIELD] = "on" if self._gain_column(GMA.RATE_GAIN.name) >= 0 else "off"
        out.update(self.controller_params)
        out.update(as_dict(self.scoring))
        out["seed"] = self.seed
        return out

    def _kernel_gains(self, gains: np.ndarray) -> np.ndarray:
        return kernel_gains(gains, self.controller)

    def raw(self, gains: np.ndarray, workers: int | None = None) -> np.ndarray:
        """The kernel's metrics matrix (n, N_METRICS) for a population of gain rows."""
        p, geo, surfs, ckind, c, table = self._kernel_args
        empty = np.zeros((0, VL.N_TRACE))

        def call(g: np.ndarray, out: np.ndarray) -> None:
            K.simulate_abs_vehicle(g, p, geo, surfs, ckind, c, table, empty, out, K.scratch())

        return run_chunked(call, self._kernel_gains(gains), VL.N_METRICS, workers)

    def metrics_from_raw(self, raw: np.ndarray) -> dict[str, np.ndarray]:
        names = tuple(n for n in VL.METRIC_LAYOUT.names if n not in ("status", "spun", "n_trace"))
        out: dict[str, np.ndarray] = VL.METRIC_LAYOUT.decode(raw, names)
        status = raw[:, VL.M_STATUS].astype(int)
        out["stopped"] = status == VL.STATUS_STOPPED
        out["status"] = np.array(VL.STATUS_NAMES)[status]
        out["spun"] = raw[:, VL.M_SPUN] != 0.0
        out["bound_distance_m"] = np.full(raw.shape[0], self.bound_distance_m)
        out["bound_time_s"] = np.full(raw.shape[0], self.bound_time_s)
        out["distance_ratio"] = raw[:, VL.M_DIST] / self.bound_distance_m
        return out

    def metrics(self, gains: np.ndarray) -> dict[str, np.ndarray]:
        return self.metrics_from_raw(self.raw(gains))

    def cost_from_raw(self, raw: np.ndarray, objective: str | None = None) -> np.ndarray:
        objective = objective or self.default_objective
        if objective not in OBJECTIVE_COLUMNS:
            raise InputError(
                "objective",
                f"unknown objective {objective!r} for abs-vehicle "
                f"(known: {', '.join(OBJECTIVE_COLUMNS)})",
            )
        cost = raw[:, OBJECTIVE_COLUMNS[objective]] + (
            self.scoring.lock_penalty_per_s * raw[:, VL.M_LOCKED]
        )
        if objective in PER_BOUND:
            cost = cost / self.bound_distance_m
        bad = (raw[:, VL.M_STATUS] != VL.STATUS_STOPPED) | ~np.isfinite(cost)
        return np.where(bad, PENALTY, np.minimum(cost, PENALTY))

    def cost(self, gains: np.ndarray, objective: str | None = None) -> np.ndarray:
        return self.cost_from_raw(self.raw(gains), objective)

    def trace(self, gains: np.ndarray) -> Trace:
        p, geo, surfs, ckind, c, table = self._kernel_args
        g = self._kernel_gains(np.asarray(gains, dtype=np.float64).reshape(1, -1))
        n_rows = math.ceil(self.plant_params.t_max_s / self.plant_params.dt_s) + 2
        lagged = self.lagged
        tr = np.zeros((n_rows, VL.N_TRACE_LAGGED if lagged else VL.N_TRACE))
        out = np.zeros((1, VL.N_METRICS))
        K.simulate_abs_vehicle(g, p, geo, surfs, ckind, c, table, tr, out, K.scratch())
        rows = int(out[0, VL.M_NTRACE])
        signals = VL.TRACE_LAYOUT.decode(tr[:rows, : VL.N_TRACE])
        units = dict(VL.TRACE_LAYOUT.units)
        if lagged:  # the slips the tires read (`abs_vehicle_lag`)
            signals |= VL.LAG_TRACE_LAYOUT.decode(tr[:rows, VL.N_TRACE :])
            units |= VL.LAG_TRACE_LAYOUT.units
        metrics = {k: json_scalar(v[0]) for k, v in self.metrics_from_raw(out).items()}
        return Trace(signals, metrics, self.units(units), locked_slip_shown(signals))

    @property
    def lagged(self) -> bool:
        """Whether the tires read lagged slips (a relaxation length: docs/tires.md)."""
        pp = self.plant_params
        return pp.relaxation_length_m > 0.0 or pp.lateral_relaxation_length_m > 0.0


class AbsVehiclePlant(Plant):
    """The 7-DOF vehicle ABS plant."""

    spec = ABS_VEHICLE

    def controllers(self) -> list[ControllerSpec]:
        return [vehicle_specs.get(n) for n in vehicle_specs.names()]

    def parameter_sets(self, preset: str | None = None) -> dict[str, Any]:
        pre = PRESETS[pick_preset(PLANT_NAME, preset, self.default_preset, PRESETS)]
        return {
            "plant": pre.params,
            "steering": SteeringParams(),
            "scoring": VehicleScoring(),
            "road mu-jump": MuJumpParams(),
            "road split-mu": SplitMuParams(),
        }

    def param_names(self) -> list[str]:
        """Every `--param` name of the plant, road and solver (controllers add their own)."""
        names: list[str] = []
        for cls in (VehicleParams, SteeringParams, VehicleScoring, MuJumpParams, SplitMuParams):
            names += [f.name for f in dataclasses.fields(cls)]
        return sorted({*names, "slip_opt", "mu_peak", "mu_lock", "mu_scale"})

    def build(
        self,
        preset: str,
        pre: Preset[VehicleParams],
        road_name: str,
        controller: str,
        values: dict[str, object],
        seed: int,
    ) -> AbsVehicleScenario:
        spec = vehicle_specs.get(controller)
        knowledge = road_knowledge(values, controller)
        gma = str(values.get(GMA.FIELD, "off"))
        if gma not in GMA.CHOICES:
            raise InputError(f"params.{GMA.FIELD}", f"must be off or on, got {gma!r}")
        from_tire = {n for n in vehicle_tire.LENGTH_FIELDS if values.get(n) == LENGTH_FROM_TIRE}
        numeric = {k: v for k, v in values.items() if k not in from_tire}
        plant_params, used = override(pre.params, numeric)
        used |= {FIELD, GMA.FIELD} | from_tire
        steering, used_steering = override(SteeringParams(), values)
        if steering.steering not in STEERING_MODES:
            raise InputError(
                "params.steering", f"must be auto, fixed or driver, got {steering.steering!r}"
            )
        own_surface = road_name == TIRE_SURFACE
        road_spec, used_road, road_params = (
            (None, set(), {}) if own_surface else make_road(road_name, values)
        )
        plant_params = validate(plant_params, "params.")
        road_spec, tire = vehicle_tire.on_surfaces(road_name, road_spec, values, plant_params)
        plant_params = vehicle_tire.with_file_lengths(plant_params, tire, from_tire)
        used |= {"tire"} if tire is not None else set()
        split_mu = road_spec.kind == ROAD_SPLIT
        steering = dataclasses.replace(steering, steering=steering_on(steering.steering, split_mu))
        scoring, used_scoring = override(VehicleScoring(), values)
        used |= used_steering | used_road | used_scoring
        # the driver's demand without ABS: reaches q_max in 0.15 s through the actuator
        amplitude = plant_params.q_max / (0.15 * plant_params.actuator_gain)
        ctrl_values = resolve_controller_params(spec, values, used, {}, amplitude)
        unknown = sorted(set(values) - used)
        if unknown:
            known = sorted(set(self.param_names()) | set(spec.param_names) | {FIELD, GMA.FIELD})
            raise InputError(
                f"params.{unknown[0]}",
                f"unknown parameter for abs-vehicle with "
                f"{spec.name} on {road_name} (known: {', '.join(known)})",
            )
        if ctrl_values.get("axle_gains") == "per-axle":
            spec = vehicle_specs.per_axle(spec)
        spec = GMA.controller_spec(spec, gma == "on")
        spec = controller_spec(spec, knowledge)  # one fixed target for all four wheels
        _check_consistency(plant_params, road_spec, steering, scoring, tire)
        scenario = AbsVehicleScenario(
            preset,
            road_spec,
            road_params,
            spec,
            plant_params,
            steering,
            ctrl_values,
            scoring,
            seed,
            knowledge,
            tire,
        )
        tire_warnings = tire.file_warnings if tire is not None else ()
        for warning in (
            *tire_warnings,
            *implausible(plant_params),
            *implausible(steering),
            *implausible(scoring),
        ):
            warnings.warn(warning, stacklevel=3)  # valid input only
        return scenario


PLANT = AbsVehiclePlant()
