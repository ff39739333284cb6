"""What `export` exports: a source (tune result, stored study run, or named gains) resolved to one
discrete controller with its parameter vector, lookup table and scenario.

Sources:
- a `tune.json` (`chassistune tune --out`): plant, preset, first road, controller, best gains and
  every parameter echoed in it;
- `DIR#RUN`, a finished run of a study store (RUN the run key `scenario|optimizer|seed`);
- none: `--plant` (abs-wheel) and `--controller` with the registry defaults for the gains not
  given, the plant's default preset and road.
`--param` overrides apply in every case. Two names belong to the export, not the scenario:
`ecu_ts_s` (the sample time; default the controller's own `ts_s` when it has one, else
DEFAULT_ECU_TS_S) and `fuzzy_table_points` (default `discrete.DEFAULT_TABLE_POINTS`). The sample
time is rounded to a whole number of integration steps, as the kernel rounds `ts_s`.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from chassistune.controllers import discrete
from chassistune.errors import InputError
from chassistune.fuzzy.loader import load_rulebase
from chassistune.params import to_float
from chassistune.scenarios.abs_wheel import AbsWheelScenario
from chassistune.scenarios.abs_wheel_ecu import table_points
from chassistune.scenarios.registry import get_plant

DEFAULT_ECU_TS_S = 5e-3
"""Sample time of a continuous controller's discrete form (issue 15: 5 ms loops are typical)."""

EXPORT_PARAMS = ("ecu_ts_s", "fuzzy_table_points")
PLANTS = ("abs-wheel",)


@dataclass(frozen=True, eq=False)
class ExportedController:
    """One discrete controller ready to print: law, parameter values, table, scenario."""

    law: discrete.DiscreteLaw
    scenario: AbsWheelScenario
    gains: dict[str, float]
    params: NDArray[np.float64]  # in law.params order
    table: NDArray[np.float64]  # (n_out, n0, n1); a placeholder without a rule base
    grid: NDArray[np.float64]  # (lo0, step0, lo1, step1)
    breakpoints: tuple[NDArray[np.float64], ...]  # per table input; empty without a table
    table_inputs: tuple[str, ...]  # rule base input names (rows, columns)
    table_outputs: tuple[str, ...]  # rule base output names
    rulebase: str | None
    source: str  # where the gains came from, one line

    @property
    def controller(self) -> str:
        return self.law.controller

    @property
    def ts_s(self) -> float:
        return float(self.params[self.law.params.index("ts_s")])

    @property
    def model_name(self) -> str:
        """A C identifier naming the exported model."""
        return "chassistune_" + self.controller.replace("-", "_")

    def param_dict(self) -> dict[str, float]:
        return dict(zip(self.law.params, self.params.tolist(), strict=True))

    def pid_form(self) -> dict[str, Any] | None:
        """The law as Simulink's Discrete PID Controller (P, I, D, N, methods named), or None.

        The fuzzy laws give the base (fuzzy-pid) or nominal (fuzzy-immune-pid) gains and say
        which gain the table schedules."""
        p = self.param_dict()
        if self.controller == "pid":
            return {"P": p["kp"], "I": p["ki"], "D": p["kd"], "N": p["n_filter"],
                    "Form": "Parallel", "IntegratorMethod": "Forward Euler",
                    "FilterMethod": "Backward Euler", "Scheduled": "none"}
        if self.controller == "fuzzy-pid":
            return {"P": p["kp0"], "I": p["ki0"], "D": p["kd0"], "N": p["n_filter"],
                    "Form": "Parallel", "IntegratorMethod": "Forward Euler",
                    "FilterMethod": "Backward Euler",
                    "Scheduled": "P = kp0 + ku_p*kp(ke*e, kec*d), I = ki0 + ku_i*ki(...), "
                                 "D = kd0 + ku_d*kd(...), d the filtered derivative"}
        if self.controller == "fuzzy-immune-pid":
            return {"P": p["k_immune"], "I": p["ki"], "D": p["kd"], "N": None,
                    "Form": "Parallel, incremental (velocity) implementation",
                    "IntegratorMethod": "Backward Euler",
                    "FilterMethod": "none (backward difference, no filter)",
                    "Scheduled": "P = k_immune*(1 - eta*f(ke*e, kec*(e - e_prev)/Ts))"}
        return None


@dataclass(frozen=True)
class _Origin:
    """What a source names: the scenario (first road), the tuned gains and the parameters."""

    plant: str
    preset: str | None
    road: str | None
    controller: str
    gains: dict[str, Any]
    params: dict[str, Any]
    label: str


def _from_tune_json(path: Path) -> _Origin:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        params = dict(data["params"])
        params.pop("seed", None)
        return _Origin(data["plant"], data["preset"], data["roads"][0], data["controller"],
                       dict(data["best_gains"]), params, str(path))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError("source", f"cannot read {str(path)!r} as a tune result: {exc}") from None
    except (KeyError, IndexError, TypeError):
        raise InputError("source", f"{str(path)!r} is not a tune.json (needs plant, preset, "
                         "roads, controller, best_gains, params)") from None


def _from_study_run(study_dir: str, key: str) -> _Origin:
    from chassistune.studies.store import open_study

    with open_study(study_dir, "source") as store:
        for rec in store.records():
            if rec.spec.key == key:
                if not rec.completed:
                    raise InputError("source", f"run {key!r} of {study_dir!r} failed: "
                                     f"{rec.error}")
                s = rec.spec
                return _Origin(s.plant, s.preset, s.roads[0], s.controller, rec.best_gains,
                               dict(s.params), f"{study_dir}#{key}")
    raise InputError("source", f"no finished run {key!r} in {study_dir!r}")


def _origin(source: str | None, plant: str | None, controller: str | None) -> _Origin:
    if source is None:
        if controller is None:
            raise InputError("controller", "give a SOURCE or a --controller")
        return _Origin(plant or "abs-wheel", None, None, controller, {}, {},
                       f"registry defaults of {controller}")
    if plant is not None or controller is not None:
        raise InputError("controller", "a SOURCE names its plant and controller; "
                         "drop --plant/--controller")
    study, sep, key = source.partition("#")
    if sep:
        return _from_study_run(study, key)
    if Path(source).is_file():
        return _from_tune_json(Path(source))
    raise InputError("source", f"{source!r} is neither a tune.json file nor DIR#RUN")


def _law_params(law: discrete.DiscreteLaw, sc: AbsWheelScenario, gains: NDArray[np.float64],
                ts_s: float) -> NDArray[np.float64]:
    """The law's parameter vector from the scenario's gains and parameters."""
    values: dict[str, float] = dict(zip(sc.gain_names, gains.tolist(), strict=True))
    values.update({k: float(v) for k, v in sc.controller_params.items() if not isinstance(v, str)})
    values["target_slip"] = sc.target_slip
    values["ts_s"] = ts_s
    values["wheel_radius_m"] = sc.plant_params.wheel_radius_m
    return np.array([values[name] for name in law.params])


def resolve(
    source: str | None,
    plant: str | None,
    controller: str | None,
    gains: Mapping[str, object],
    params: Mapping[str, object],
    preset: str | None = None,
    road: str | None = None,
) -> ExportedController:
    """The exported controller of a source (module docstring); bad input raises InputError.

    `preset` and `road` override the source's (a tune over several roads exports its first)."""
    overrides = dict(params)
    export_values = {k: overrides.pop(k) for k in EXPORT_PARAMS if k in overrides}
    origin = _origin(source, plant, controller)
    if origin.plant not in PLANTS:
        raise InputError("plant" if source is None else "source",
                         f"no discrete controllers for plant {origin.plant!r} "
                         f"(exportable: {', '.join(PLANTS)})")
    law = discrete.law(origin.controller)
    if law is None:
        raise InputError("controller" if source is None else "source",
                         f"{origin.controller!r} has no discrete form to export "
                         f"(exportable: {', '.join(discrete.LAWS)})")
    sc = get_plant(origin.plant).scenario(preset or origin.preset, road or origin.road,
                                          origin.controller, {**origin.params, **overrides})
    if not isinstance(sc, AbsWheelScenario):  # pragma: no cover - PLANTS holds abs-wheel only
        raise InputError("plant", f"cannot export from plant {origin.plant!r}")
    g = sc.gains_array({**origin.gains, **{k: to_float(v, f"gains.{k}") for k, v in
                                           gains.items()}})
    if not np.all(np.isfinite(g)):
        raise InputError("gains", "every gain must be finite")
    dt = sc.plant_params.dt_s
    ts = _sample_time(export_values, sc.controller_params, dt)
    rulebase = str(sc.controller_params["rulebase"]) if law.table_outputs else None
    if rulebase is None and "fuzzy_table_points" in export_values:
        raise InputError("params.fuzzy_table_points", f"{law.controller} reads no lookup table")
    table, grid = discrete.no_table()
    bp: tuple[NDArray[np.float64], ...] = ()
    table_inputs: tuple[str, ...] = ()
    table_outputs: tuple[str, ...] = ()
    if rulebase is not None:
        rb = load_rulebase(rulebase, "params.rulebase")
        points = table_points(export_values)
        table, grid, bp = discrete.ecu_table(rb, points)
        table_inputs = tuple(v.name for v in rb.inputs)
        table_outputs = rb.output_names
    return ExportedController(
        law=law, scenario=sc, gains=dict(zip(sc.gain_names, g.tolist(), strict=True)),
        params=_law_params(law, sc, g, ts), table=table, grid=grid, breakpoints=bp,
        table_inputs=table_inputs, table_outputs=table_outputs, rulebase=rulebase,
        source=origin.label,
    )


def _sample_time(values: Mapping[str, object], ctrl: Mapping[str, Any], dt: float) -> float:
    """The sample time: ecu_ts_s, else the controller's ts_s, else the default; whole steps."""
    if "ecu_ts_s" in values:
        ts = to_float(values["ecu_ts_s"], "params.ecu_ts_s")
        if not ts > 0:
            raise InputError("params.ecu_ts_s", f"must be positive, got {ts:g}")
    else:
        ts = float(ctrl.get("ts_s", DEFAULT_ECU_TS_S))
    return max(1, round(ts / dt)) * dt
