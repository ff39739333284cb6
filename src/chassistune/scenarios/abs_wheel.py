"""Scenarios of the single-wheel ABS plant `abs-wheel` (design.md 3.1): preset + road + controller
+ scoring, fed to the compiled kernel `chassistune.sim.abs_wheel_kernel.simulate_abs_wheel`.

The physics (parameters, presets) is `chassistune.plants.abs_wheel`; roads `plants.roads`.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from chassistune.controllers import catalogue, laws
from chassistune.controllers.specs import ControllerSpec
from chassistune.errors import InputError
from chassistune.params import as_dict, implausible, override, to_float, validate
from chassistune.plants.abs_wheel import (
    PRESETS,
    AbsWheelParams,
    bound_time_s,
    check_consistency,
    default_t_max_s,
)
from chassistune.plants.mf_curve import TIRE_SURFACE, MagicFormulaCurve, wheel_tire
from chassistune.plants.mf_relaxation import longitudinal_relaxation_length_m
from chassistune.plants.presets import Preset
from chassistune.plants.roads import tire_for_road
from chassistune.plants.tires import TireCurve
from chassistune.scenarios.abs_wheel_ecu import (
    ECU_PARAM_NAMES,
    EcuSetup,
    ecu_mode,
    ecu_setup,
    law_params,
)
from chassistune.scenarios.base import PENALTY, Plant, Scenario, Trace, json_scalar, pick_preset
from chassistune.scenarios.controller_params import kernel_gains, resolve_controller_params
from chassistune.scenarios.registry import ABS_WHEEL
from chassistune.scenarios.road_knowledge import FIELD, controller_spec, plant_rows, road_knowledge
from chassistune.sim import abs_wheel_ecu_layout as EL
from chassistune.sim import abs_wheel_kernel as K
from chassistune.sim import abs_wheel_layout as KL
from chassistune.sim.abs_wheel_ecu_kernel import simulate_abs_wheel_ecu
from chassistune.sim.batch import run_chunked

_POS = {"positive": True}
_NONNEG = {"nonnegative": True}


@dataclass(frozen=True)
class Scoring:
    """How runs become costs (design.md 5)."""

    lock_penalty_per_s: float = field(default=100.0, metadata=_NONNEG)
    hopeless_factor: float = field(default=3.0, metadata=_POS)
    """Stop a candidate early once its distance exceeds this many times the bound."""


def _no_surface() -> tuple[Any, ...]:
    """A placeholder surface of the kernel's table type, for controllers without a rule base."""
    return (
        np.zeros((1, 2, 2)),
        np.full((1, 1), -1, dtype=np.int32),
        np.zeros(0, dtype=np.int64),
        np.zeros(0, dtype=np.int64),
        np.zeros(0),
        0.0,
        1.0,
        0.0,
        1.0,
    )


def fuzzy_table(controller: str, rulebase: str) -> tuple[Any, ...]:
    """The compiled surface of `rulebase` for `controller`, checked for its inputs and outputs."""
    from chassistune.fuzzy.loader import load_rulebase
    from chassistune.fuzzy.surface import compiled

    rb = load_rulebase(rulebase, "params.rulebase")
    need = laws.get(controller).rulebase_outputs
    if len(rb.inputs) != 2 or len(rb.outputs) != need:
        raise InputError(
            "params.rulebase",
            f"{controller} needs a rule base with inputs (e, ec) "
            f"and {need} output(s); {rulebase!r} has {len(rb.inputs)} inputs and "
            f"{len(rb.outputs)} outputs",
        )
    return compiled(rb).table


METRIC_COLUMNS = {name: KL.METRICS[name] for name in KL.RUN_METRICS}
STATUS_NAMES = dict(enumerate(KL.STATUS_NAMES))
OBJECTIVE_COLUMNS = {
    obj: KL.METRICS[name]
    for obj, name in (
        ("itae", "slip_itae"),
        ("iae", "slip_iae"),
        ("ise", "slip_ise"),
        ("distance", "stop_distance_m"),
        ("time", "stop_time_s"),
        ("distance_ratio", "stop_distance_m"),
    )
}
PER_BOUND = frozenset({"distance_ratio"})
"""Objectives divided by the scenario's adhesion-bound distance (stop distance / bound: scenarios
of different speeds and roads compare on one scale)."""
STATUS_REASONS = {
    "timeout": "t_max_s was reached before the speed fell to v_stop_m_s",
    "hopeless": "the distance passed hopeless_factor times the bound, so the run was cut short",
    "diverged": "the numbers blew up (the gains or parameters are far outside a sane range)",
}
"""Why a run did not stop, by status (for text output; its stop metrics are then null)."""
DIVERGED_SLIP = 1e3
"""A slip clipped by more than this is a numerical blow-up, not braking (slip is in [0, 1] for
any physical state), whatever status the kernel gave the run."""
STOP_METRICS = ("stop_time_s", "stop_distance_m", "distance_ratio")
"""Metrics that only mean something for a run that stopped."""


class AbsWheelScenario(Scenario):
    """A resolved abs-wheel scenario; evaluates populations of gain rows in one kernel call."""

    objectives = tuple(OBJECTIVE_COLUMNS)
    default_objective = "itae"
    status_reasons = STATUS_REASONS

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
        ecu: EcuSetup | None = None,
        knowledge: str = "oracle",
    ) -> None:
        super().__init__("abs-wheel", preset, road, controller, seed)
        self.plant_params = plant_params
        self.tire = tire
        self.controller_params = controller_params
        self.scoring = scoring
        self.ecu = ecu
        """None: the ideal kernel; else the realistic ECU (`--ecu realistic`)."""
        self.mu_peak, self.slip_at_peak, _ = tire.peak()
        self.target_slip = target_slip
        """The oracle's target (the road's peak) or the user's; per candidate when `fixed`."""
        self.road_knowledge = knowledge
        pp = plant_params
        decel = self.mu_peak * pp.g_m_s2 * pp.load_fraction
        self.bound_distance_m = (pp.v0_m_s**2 - pp.v_stop_m_s**2) / (2.0 * decel)
        self.bound_time_s = bound_time_s(pp, self.mu_peak)
        self._kernel_args = self._pack()

    def _pack(self) -> tuple[Any, ...]:
        cp = self.controller_params
        p = KL.pack_plant(
            {
                **as_dict(self.plant_params),
                "target_slip": self.target_slip,
                "hopeless_distance_m": self.scoring.hopeless_factor * self.bound_distance_m,
                "n_filter": cp.get("n_filter", 100.0),
            }
        )
        c = KL.pack_controller({"ts_s": self.plant_params.dt_s, **cp})
        kind, coef, xs, ys = self.tire.kernel_data()
        name = self.controller.name
        table = (
            fuzzy_table(name, str(self.controller_params["rulebase"]))
            if laws.get(name).rulebase_outputs
            else _no_surface()
        )
        return p, kind, coef, xs, ys, laws.kind(name), c, table

    @property
    def pressure_unit(self) -> str:
        return PRESETS[self.preset].info.pressure_unit

    def params(self) -> dict[str, Any]:
        out: dict[str, Any] = as_dict(self.plant_params)
        if isinstance(self.tire, MagicFormulaCurve):
            out["tire"] = self.tire.path
        elif dataclasses.is_dataclass(self.tire):
            out.update(as_dict(self.tire))
        if self.road == "sldemo-table":
            out = {k: v for k, v in out.items() if k not in ("slips", "mus")}
        if self.road_knowledge != "fixed":
            out["target_slip"] = self.target_slip
        out["road_knowledge"] = self.road_knowledge
        out.update(self.controller_params)
        out.update(as_dict(self.scoring))
        out["seed"] = self.seed
        if self.ecu is not None:
            out.update(self.ecu.echo())
        return out

    def _plant(self, p: np.ndarray, gains: np.ndarray) -> np.ndarray:
        """The plant vector for gain rows `gains` (`road_knowledge.plant_rows`)."""
        return plant_rows(p, KL.PLANT["target_slip"], gains, self.road_knowledge)

    def raw(self, gains: np.ndarray, workers: int | None = None) -> np.ndarray:
        """The kernel's metrics matrix (n, N_METRICS) for a population of gain rows."""
        if self.ecu is not None:
            return self._raw_ecu(gains, workers)
        p, kind, coef, xs, ys, ckind, c, table = self._kernel_args
        empty = np.zeros((0, len(KL.TRACE)))

        def call(g: np.ndarray, out: np.ndarray) -> None:
            K.simulate_abs_wheel(
                g, self._plant(p, g), kind, coef, xs, ys, ckind, c, table, empty, out
            )

        return run_chunked(call, kernel_gains(gains, self.controller), len(KL.METRICS), workers)

    def _ecu_call(self, gains: np.ndarray, trace: np.ndarray, out: np.ndarray) -> None:
        """The realistic kernel on gain rows."""
        assert self.ecu is not None
        p, kind, coef, xs, ys, *_ = self._kernel_args
        lp = law_params(
            self.controller.name,
            self.gain_names,
            gains,
            self.controller_params,
            self.target_slip,
            self.ecu.params.ecu_ts_s,
            self.plant_params.wheel_radius_m,
        )
        simulate_abs_wheel_ecu(
            lp,
            self._plant(p, gains),
            self.ecu.vector,
            kind,
            coef,
            xs,
            ys,
            self.ecu.table,
            self.ecu.grid,
            self.ecu.noise,
            trace,
            out,
        )

    def _raw_ecu(self, gains: np.ndarray, workers: int | None) -> np.ndarray:
        empty = np.zeros((0, len(EL.TRACE)))
        return run_chunked(
            lambda g, out: self._ecu_call(g, empty, out),
            kernel_gains(gains, self.controller),
            len(EL.METRICS),
            workers,
        )

    def metrics_from_raw(self, raw: np.ndarray) -> dict[str, np.ndarray]:
        """Metrics by name; stop metrics NaN (JSON null) for runs that did not stop; status
        `diverged` for any numerical blow-up (`DIVERGED_SLIP`)."""
        out = KL.decode_metrics(raw) if self.ecu is None else EL.decode_metrics(raw)
        blown = ~out["stopped"] & ~(np.abs(out["slip_clip_max"]) <= DIVERGED_SLIP)
        out["status"] = np.where(blown, "diverged", out["status"])
        out["bound_distance_m"] = np.full(raw.shape[0], self.bound_distance_m)
        out["bound_time_s"] = np.full(raw.shape[0], self.bound_time_s)
        out["distance_ratio"] = out["stop_distance_m"] / self.bound_distance_m
        for name in STOP_METRICS:
            out[name] = np.where(out["stopped"], out[name], np.nan)
        return out

    def metrics(self, gains: np.ndarray) -> dict[str, np.ndarray]:
        return self.metrics_from_raw(self.raw(gains))

    def cost_from_raw(self, raw: np.ndarray, objective: str | None = None) -> np.ndarray:
        objective = self.pick_objective(objective)
        cost = raw[:, OBJECTIVE_COLUMNS[objective]] + (
            self.scoring.lock_penalty_per_s * raw[:, KL.METRICS["locked_time_s"]]
        )
        if objective in PER_BOUND:
            cost = cost / self.bound_distance_m
        stopped = KL.STATUS_NAMES.index("stopped")
        bad = (raw[:, KL.METRICS["status"]] != stopped) | ~np.isfinite(cost)
        return np.where(bad, PENALTY, np.minimum(cost, PENALTY))

    def cost(self, gains: np.ndarray, objective: str | None = None) -> np.ndarray:
        return self.cost_from_raw(self.raw(gains), objective)

    def trace(self, gains: np.ndarray) -> Trace:
        p, kind, coef, xs, ys, ckind, c, table = self._kernel_args
        g = kernel_gains(np.asarray(gains, dtype=np.float64).reshape(1, -1), self.controller)
        n_rows = math.ceil(self.plant_params.t_max_s / self.plant_params.dt_s) + 2
        if self.ecu is not None:
            tr = np.zeros((n_rows, len(EL.TRACE)))
            out = np.zeros((1, len(EL.METRICS)))
            self._ecu_call(np.asarray(gains, dtype=np.float64).reshape(1, -1), tr, out)
            metrics = {k: json_scalar(v[0]) for k, v in self.metrics_from_raw(out).items()}
            return Trace(EL.decode_trace(tr, out[0]), metrics, self.units(EL.TRACE.units))
        tr = np.zeros((n_rows, len(KL.TRACE)))
        out = np.zeros((1, len(KL.METRICS)))
        K.simulate_abs_wheel(g, self._plant(p, g), kind, coef, xs, ys, ckind, c, table, tr, out)
        metrics = {k: json_scalar(v[0]) for k, v in self.metrics_from_raw(out).items()}
        return Trace(KL.decode_trace(tr, out[0]), metrics, self.units(KL.TRACE.units))


class AbsWheelPlant(Plant[AbsWheelScenario]):
    """The single-wheel ABS plant."""

    spec = ABS_WHEEL

    def controllers(self) -> list[ControllerSpec]:
        return catalogue.for_plant(ABS_WHEEL.name)

    def parameter_sets(self, preset: str | None = None) -> dict[str, Any]:
        pre = PRESETS[pick_preset(self.name, preset, self.default_preset, PRESETS)]
        road = pre.info.roads[0]
        return {
            "plant": pre.params,
            f"road ({road}; others have their own values)": tire_for_road(road, {})[0],
            "scoring": Scoring(),
        }

    def build(
        self,
        preset: str,
        pre: Preset[AbsWheelParams],
        road: str,
        controller: str,
        values: dict[str, object],
        seed: int,
    ) -> AbsWheelScenario:
        knowledge = road_knowledge(values, controller)
        spec = controller_spec(catalogue.get(ABS_WHEEL.name, controller), knowledge)
        mode = ecu_mode(values)
        from_tire = values.get("relaxation_length_m") == LENGTH_FROM_TIRE
        numeric = {
            k: v for k, v in values.items() if not (from_tire and k == "relaxation_length_m")
        }
        plant_params, used = override(pre.params, numeric)
        used |= {"ecu", FIELD}
        tire, used_tire = _tire(road, values, plant_params)
        if from_tire:
            sigma = _tire_relaxation_length_m(tire)
            plant_params = dataclasses.replace(plant_params, relaxation_length_m=sigma)
            used.add("relaxation_length_m")
        scoring, used_scoring = override(Scoring(), values)
        used |= used_tire | used_scoring
        # default command: reaches q_max in 0.15 s through the integrating actuator
        amplitude = plant_params.q_max / (0.15 * plant_params.actuator_gain)
        ctrl_values = resolve_controller_params(
            spec, values, used, pre.controller_defaults, amplitude
        )
        target = tire.peak()[2]
        if "target_slip" in values:
            target = to_float(values["target_slip"], "params.target_slip")
            if not 0.0 < target < 1.0:
                raise InputError("params.target_slip", f"must be in (0, 1), got {target:g}")
            used.add("target_slip")
        if "t_max_s" not in values:
            plant_params = dataclasses.replace(
                plant_params, t_max_s=default_t_max_s(plant_params, tire.peak()[0])
            )
        if mode == "realistic":
            used |= ECU_PARAM_NAMES & set(values)
        unknown = sorted(set(values) - used)
        if unknown:
            known = sorted(
                {f.name for f in dataclasses.fields(AbsWheelParams)}
                | {f.name for f in dataclasses.fields(tire)}
                | {f.name for f in dataclasses.fields(Scoring)}
                | set(spec.param_names)
                | {"target_slip", "ecu", "tire", FIELD}
                | (ECU_PARAM_NAMES if mode == "realistic" else set())
            )
            raise InputError(
                f"params.{unknown[0]}",
                f"unknown parameter for abs-wheel with "
                f"{spec.name} on {road} (known: {', '.join(known)})",
            )
        check_consistency(plant_params, set(values))
        plant_params = validate(plant_params, "params.")
        ecu = (
            ecu_setup(values, spec.name, ctrl_values, plant_params, seed)
            if mode == "realistic"
            else None
        )
        scenario = AbsWheelScenario(
            preset,
            road,
            spec,
            plant_params,
            tire,
            ctrl_values,
            target,
            scoring,
            seed,
            ecu,
            knowledge,
        )
        for warning in implausible(plant_params) + implausible(tire):  # valid input only
            warnings.warn(warning, stacklevel=2)
        return scenario


LENGTH_FROM_TIRE = "tire"
"""`--param relaxation_length_m=tire`: the TIR file's own length (`_tire_relaxation_length_m`)."""


def _tire_relaxation_length_m(tire: TireCurve) -> float:
    """MF 6.1's sigma_kappa = |K_xkappa / C_x| of the TIR file at the wheel's load
    (`mf_relaxation.longitudinal_relaxation_length_m`; docs/tires.md, transient slip)."""
    field = "params.relaxation_length_m"
    if not isinstance(tire, MagicFormulaCurve):
        raise InputError(field, f"{LENGTH_FROM_TIRE!r} takes the TIR file's length: needs --tire")
    sigma = float(longitudinal_relaxation_length_m(tire.tire.kernel_array(), tire.fz_n))
    if not sigma > 0.0:
        raise InputError(
            field,
            f"{tire.path} gives no relaxation length: it has neither LONGITUDINAL_STIFFNESS "
            "(MF 6.1) nor a positive PTX1 (MF 5.2); give the length in metres",
        )
    return sigma


def _tire(
    road: str, values: dict[str, object], plant_params: AbsWheelParams
) -> tuple[TireCurve, set[str]]:
    """The road's tire curve, or the Magic Formula tire of the TIR file `values["tire"]` at the
    wheel's load on it (`mf_curve.wheel_tire`; on the file's own surface on road TIRE_SURFACE),
    and the names of `values` used."""
    if "tire" not in values:
        if road == TIRE_SURFACE:
            raise InputError("road", f"{TIRE_SURFACE} is a TIR file's surface: needs --tire")
        return tire_for_road(road, values)
    own = road == TIRE_SURFACE
    road_curve, used = (None, set()) if own else tire_for_road(road, values)
    pp = plant_params
    fz_n = pp.load_fraction * pp.mass_kg * pp.g_m_s2
    return wheel_tire(str(values["tire"]), road, road_curve, fz_n), used | {"tire"}


PLANT = AbsWheelPlant()
