"""What `export` exports: a source (tune result, stored study run, or named gains) resolved to one
discrete controller with its parameter vector, lookup table and scenario.

Sources:
- a `tune.json` (`chassistune tune --out`): plant, preset, first road, controller, best gains and
  every parameter echoed in it;
- `DIR#RUN`, a finished run of a study store (RUN the run key `scenario|optimizer|seed`);
- none: `--plant` (abs-wheel) and `--controller` with the registry defaults for the gains not
  given, the plant's default preset and road.
`--param` overrides apply in every case. Two names belong to the export: `ecu_ts_s` (the sample
time) and `fuzzy_table_points` (default `discrete.DEFAULT_TABLE_POINTS`). The sample time is, in
this order: `--param ecu_ts_s`, the source's `ecu_ts_s` (a source tuned with `--ecu realistic`),
the source's controller `ts_s` (the sample period a sampled law was tuned at), else the realistic
ECU's default (`EcuParams.ecu_ts_s`, 5 ms); it is rounded to a whole number of integration steps.

The exported scenario is the source's plant, road, gains and parameters in the realistic ECU
mode with an IDEAL ECU (`IDEAL_ECU`: true wheel speed and vehicle speed, the continuous actuator,
no delay, no cut-out, no schedule): the kernel (`sim.abs_wheel_ecu_kernel`) then runs exactly the
exported discrete law on exact inputs, the loop `closed_loop` re-simulates with any controller
(the C through ctypes) and `simulate --from EXPORT.json` re-runs it. The ECU's sensor, reference
and valve models are not part of the exported controller (an ECU has its own).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from chassistune.controllers import discrete, laws
from chassistune.controllers.ecu_params import EcuParams
from chassistune.errors import InputError
from chassistune.fuzzy.loader import load_rulebase
from chassistune.params import to_float
from chassistune.scenarios.abs_wheel import AbsWheelScenario
from chassistune.scenarios.abs_wheel_ecu import ECU_PARAM_NAMES, law_params, table_points
from chassistune.scenarios.registry import get_plant, plant_names, plant_spec

DEFAULT_ECU_TS_S = EcuParams().ecu_ts_s
"""Sample time without one from the source: the realistic ECU's (5 ms, a production ECU's loop)."""

EXPORT_PARAMS = ("ecu_ts_s", "fuzzy_table_points")
IDEAL_ECU: dict[str, object] = {
    "ecu": "realistic",
    "sensor": "ideal",
    "vref": "true",
    "valves": "continuous",
    "ecu_delay_samples": 0,
    "abs_cutout_m_s": 0.0,
    "gain_schedule": "off",
    "valve_dead_time_s": 0.0,
    "valve_min_on_s": 0.0,
}
"""The ECU of the exported scenario (module docstring): the law alone between plant and brake."""


def exportable_plants() -> list[str]:
    """The registered plants whose spec says their controllers export (`PlantSpec.exportable`)."""
    return [name for name in plant_names() if plant_spec(name).exportable]


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
    ts_origin: str = ""  # where the sample time came from (`_sample_time`)

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
        form = _PID_FORMS.get(self.controller)
        if form is None:
            return None
        gains = {k: None if n is None else p[n] for k, n in zip("PIDN", form.gains, strict=True)}
        return {
            **gains,
            "Form": form.form,
            "IntegratorMethod": form.integrator,
            "FilterMethod": form.filter,
            "Scheduled": form.scheduled,
        }


@dataclass(frozen=True)
class _PidForm:
    """A law as Simulink's Discrete PID Controller: the parameters giving P, I, D and N (None:
    no filter), the form and methods, and what its table schedules."""

    gains: tuple[str, str, str, str | None]
    scheduled: str
    form: str = "Parallel"
    integrator: str = "Forward Euler"
    filter: str = "Backward Euler"


_PID_FORMS = {
    "pid": _PidForm(("kp", "ki", "kd", "n_filter"), "none"),
    "fuzzy-pid": _PidForm(
        ("kp0", "ki0", "kd0", "n_filter"),
        "P = kp0 + ku_p*kp(ke*e, kec*d), I = ki0 + ku_i*ki(...), "
        "D = kd0 + ku_d*kd(...), d the filtered derivative",
    ),
    "fuzzy-immune-pid": _PidForm(
        ("k_immune", "ki", "kd", None),
        "P = k_immune*(1 - eta*f(ke*e, kec*(e - e_prev)/Ts))",
        form="Parallel, incremental (velocity) implementation",
        integrator="Backward Euler",
        filter="none (backward difference, no filter)",
    ),
}
"""The laws with a Discrete PID Controller form, by controller name."""


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
    from chassistune.tuning.saved import read_tune_json

    data = read_tune_json(str(path), "source")
    params = dict(data["params"])
    params.pop("seed", None)
    return _Origin(
        data["plant"],
        data["preset"],
        data["roads"][0],
        data["controller"],
        dict(data["best_gains"]),
        params,
        str(path),
    )


def _from_study_run(study_dir: str, key: str) -> _Origin:
    from chassistune.studies.store import open_study

    with open_study(study_dir, "source") as store:
        for rec in store.records():
            if rec.spec.key == key:
                if not rec.completed:
                    raise InputError("source", f"run {key!r} of {study_dir!r} failed: {rec.error}")
                s = rec.spec
                return _Origin(
                    s.plant,
                    s.preset,
                    s.roads[0],
                    s.controller,
                    rec.best_gains,
                    dict(s.params),
                    f"{study_dir}#{key}",
                )
    raise InputError("source", f"no finished run {key!r} in {study_dir!r}")


def _origin(source: str | None, plant: str | None, controller: str | None) -> _Origin:
    if source is None:
        if controller is None:
            raise InputError("controller", "give a SOURCE or a --controller")
        return _Origin(
            plant or "abs-wheel",
            None,
            None,
            controller,
            {},
            {},
            f"registry defaults of {controller}",
        )
    if plant is not None or controller is not None:
        raise InputError(
            "controller", "a SOURCE names its plant and controller; drop --plant/--controller"
        )
    study, sep, key = source.partition("#")
    if sep:
        return _from_study_run(study, key)
    if Path(source).is_file():
        return _from_tune_json(Path(source))
    raise InputError("source", f"{source!r} is neither a tune.json file nor DIR#RUN")


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
    field = "plant" if source is None else "source"
    spec = plant_spec(origin.plant)
    if spec.export_refusal:
        discrete_laws = [s.name for s in laws.for_plant(origin.plant) if laws.get(s.name).discrete]
        why = spec.export_refusal.format(laws=", ".join(discrete_laws))
        raise InputError(field, f"cannot export from plant {origin.plant!r}: {why}")
    if not spec.exportable:
        raise InputError(
            field,
            f"no discrete controllers for plant {origin.plant!r} "
            f"(exportable: {', '.join(exportable_plants())})",
        )
    law = laws.get(origin.controller).discrete if origin.controller in laws.names() else None
    if law is None:
        exportable = [n for n in laws.names() if laws.get(n).discrete is not None]
        raise InputError(
            "controller" if source is None else "source",
            f"{origin.controller!r} has no discrete form to export "
            f"(exportable: {', '.join(exportable)})",
        )
    fixed = sorted((ECU_PARAM_NAMES | {"ecu"}) & set(overrides))
    if fixed:
        raise InputError(
            f"params.{fixed[0]}",
            "the export's ECU is ideal (true speeds, the "
            "continuous actuator, no delay); of the ECU parameters only ecu_ts_s "
            "and fuzzy_table_points apply",
        )
    values = {**origin.params, **overrides}
    if "tire" in values:
        raise InputError(
            "params.tire",
            "the export's closed loop (its C test vectors) has no Magic Formula tire: "
            "export on a road's tire curve",
        )
    if str(values.get("gain_schedule", "off")) != "off":
        raise InputError(
            "params.gain_schedule",
            "the exported controller has fixed gains; a "
            "speed schedule needs the ECU's reference speed (export with "
            "gain_schedule=off)",
        )
    base = {k: v for k, v in values.items() if k not in ECU_PARAM_NAMES and k != "ecu"}
    plain = get_plant(origin.plant).scenario(
        preset or origin.preset, road or origin.road, origin.controller, base
    )
    if not isinstance(plain, AbsWheelScenario):  # pragma: no cover - abs-wheel only is exportable
        raise InputError("plant", f"cannot export from plant {origin.plant!r}")
    dt = plain.plant_params.dt_s
    ts, ts_origin = _sample_time(
        export_values, values, plain.controller_params, dt, source is not None
    )
    rulebase = str(plain.controller_params["rulebase"]) if law.table_outputs else None
    if rulebase is None and "fuzzy_table_points" in export_values:
        raise InputError("params.fuzzy_table_points", f"{law.controller} reads no lookup table")
    points = table_points(
        {k: v for k, v in {**values, **export_values}.items() if k == "fuzzy_table_points"}
    )
    ecu = {**IDEAL_ECU, "ecu_ts_s": ts, **({"fuzzy_table_points": points} if rulebase else {})}
    sc = get_plant(origin.plant).scenario(
        plain.preset, plain.road, origin.controller, {**base, **ecu}
    )
    if not isinstance(sc, AbsWheelScenario):  # pragma: no cover - abs-wheel only is exportable
        raise InputError("plant", f"cannot export from plant {origin.plant!r}")
    g = sc.gains_array({**origin.gains, **{k: to_float(v, f"gains.{k}") for k, v in gains.items()}})
    if not np.all(np.isfinite(g)):
        raise InputError("gains", "every gain must be finite")
    table, grid = discrete.no_table()
    bp: tuple[NDArray[np.float64], ...] = ()
    table_inputs: tuple[str, ...] = ()
    table_outputs: tuple[str, ...] = ()
    if rulebase is not None:
        rb = load_rulebase(rulebase, "params.rulebase")
        table, grid, bp = discrete.ecu_table(rb, points)
        table_inputs = tuple(v.name for v in rb.inputs)
        table_outputs = rb.output_names
    row = law_params(
        law.controller,
        sc.gain_names,
        g[None, :],
        sc.controller_params,
        sc.target_slip,
        ts,
        sc.plant_params.wheel_radius_m,
    )[0]
    return ExportedController(
        law=law,
        scenario=sc,
        gains=dict(zip(sc.gain_names, g.tolist(), strict=True)),
        params=row,
        table=table,
        grid=grid,
        breakpoints=bp,
        table_inputs=table_inputs,
        table_outputs=table_outputs,
        rulebase=rulebase,
        source=origin.label,
        ts_origin=ts_origin,
    )


def _sample_time(
    export_values: Mapping[str, object],
    source_values: Mapping[str, object],
    ctrl: Mapping[str, Any],
    dt: float,
    has_source: bool,
) -> tuple[float, str]:
    """The sample time (module docstring), in whole steps of dt, and where it came from."""
    if "ecu_ts_s" in export_values or "ecu_ts_s" in source_values:
        given = export_values.get("ecu_ts_s", source_values.get("ecu_ts_s"))
        ts = to_float(given, "params.ecu_ts_s")
        if not ts > 0:
            raise InputError("params.ecu_ts_s", f"must be positive, got {ts:g}")
        origin = "--param ecu_ts_s" if "ecu_ts_s" in export_values else "the source's ecu_ts_s"
    elif has_source and "ts_s" in ctrl:
        ts, origin = float(ctrl["ts_s"]), "the source's controller ts_s"
    else:
        ts, origin = DEFAULT_ECU_TS_S, "the realistic ECU's default"
    return max(1, round(ts / dt)) * dt, origin
