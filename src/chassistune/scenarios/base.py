"""What every plant offers the tuning, study, report and CLI layers.

A *plant* (registered by name in `chassistune.scenarios.registry`) knows its presets and roads and
builds a *scenario*: plant + preset + road + controller + parameter overrides, fully resolved and
validated. A scenario evaluates a whole population of gain vectors at once (`metrics`, `cost`)
and traces one candidate for plots (`trace`). What the upper layers need to know about a plant
without building anything (version, default preset, key metrics, plot function) is its `PlantSpec`.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

import numpy as np

from chassistune._registry import resolve
from chassistune.controllers.specs import ControllerSpec
from chassistune.errors import InputError
from chassistune.plants.presets import PresetInfo
from chassistune.scenarios.report_view import PlantView
from chassistune.units import with_pressure

PENALTY = 1e9
"""Cost of a run that cannot be scored (diverged, NaN, unstable, hopeless, not stopped)."""


def json_scalar(x: Any) -> Any:
    """A JSON-friendly metric value: numpy -> Python, NaN -> None."""
    if isinstance(x, np.bool_ | bool):
        return bool(x)
    if isinstance(x, np.str_ | str):
        return str(x)
    x = float(x)
    return None if math.isnan(x) else x


def pick_preset(plant: str, name: str | None, default: str, known: Mapping[str, Any]) -> str:
    """The preset name to use (default when None), or InputError listing the known ones."""
    name = name or default
    if name not in known:
        raise InputError(
            "preset", f"unknown preset {name!r} for {plant} (known: {', '.join(known)})"
        )
    return name


@dataclass(frozen=True)
class PlantSpec:
    """A plant's identity and what reports need of it.

    `key_metrics` are its lower-is-better metrics summarized in reports (each a metric name of
    its scenarios); `plot` names the function drawing a trace, lazily as "module:attr"
    (signature `plot(scenario, trace, path)`), so that no computation module imports matplotlib.
    `presets` ("module:attr" of the presets by name, each with its `info`) and `roads`
    ("module:attr" of a function: road name -> description) point into light modules, so that
    listing them imports no kernel; empty, the plant's builder answers (`Plant.presets`).
    The other fields say what the upper layers do with it (each default: nothing).
    """

    name: str
    version: int
    description: str
    default_preset: str
    key_metrics: tuple[str, ...]
    plot: str
    metric_notes: tuple[tuple[str, str], ...] = ()
    """(metric, note): what a metric's number is beyond its unit, shown after the unit wherever
    the metric is labelled (`metric_unit`)."""
    presets: str = ""
    roads: str = ""
    view: PlantView = field(default_factory=PlantView)
    """How the reports present it (baseline, response overlays, generalization metrics)."""
    refinable: bool = False
    """Its figures converge as the integration step is refined, so a tuned winner is re-run at
    a finer step to check them (`scenarios.refine`)."""
    exportable: bool = False
    """Its controllers' discrete forms export to C against it (`export.source`)."""
    export_refusal: str = ""
    """Why it cannot be exported although it names controllers with a discrete form."""
    varied: tuple[str, ...] = ()
    """The attributes of its scenarios holding the plant, road and actuator parameter
    dataclasses whose float fields robust tuning may vary (`tuning.robust.plant_params`)."""
    varied_scales: tuple[str, ...] = ()
    """Positive scale factors robust tuning may vary besides those fields."""

    def metric_unit(self, name: str, unit: str) -> str:
        """`unit` with the metric's note (`metric_notes`): `s, summed over the four wheels`."""
        note = dict(self.metric_notes).get(name, "")
        return f"{unit}, {note}" if note else unit

    def preset_table(self) -> Mapping[str, Any]:
        """The presets by name as the plant defines them (each with its `info`), imported now."""
        presets: Mapping[str, Any] = resolve(self.presets)  # type: ignore[assignment]
        return presets

    def preset_infos(self) -> dict[str, PresetInfo]:
        """The presets by name, read from the `presets` module (imported now)."""
        return {name: preset.info for name, preset in self.preset_table().items()}

    def road_descriptions(self) -> dict[str, str]:
        """Road name -> one-line description, from the `roads` function (imported now)."""
        roads: Any = resolve(self.roads)
        return dict(roads())


@dataclass
class Trace:
    """Time series of one closed-loop run (`signals[name]` arrays of equal length) and metrics."""

    signals: dict[str, np.ndarray]
    metrics: dict[str, Any]
    units: dict[str, str] = field(default_factory=dict)
    shown_as: dict[str, np.ndarray] = field(default_factory=dict)
    """Signals as figures, reports and the CSV show them, where that differs from the recorded
    `signals` (the 7-DOF vehicle's slip of a locked wheel: 1)."""

    @property
    def shown(self) -> dict[str, np.ndarray]:
        """`signals` with the `shown_as` ones in their place."""
        return {**self.signals, **self.shown_as}


class Scenario(ABC):
    """A resolved plant + preset + road + controller; gains are (n, k) rows (gain_names)."""

    plant: str
    preset: str
    road: str
    controller: ControllerSpec
    objectives: tuple[str, ...]
    default_objective: str
    seed: int
    status_reasons: Mapping[str, str] = {}
    """Why a run with metric `status` did not reach its goal, by status (text output)."""

    def __init__(
        self, plant: str, preset: str, road: str, controller: ControllerSpec, seed: int
    ) -> None:
        self.plant = plant
        self.preset = preset
        self.road = road
        self.controller = controller
        self.seed = seed

    @property
    def gain_names(self) -> tuple[str, ...]:
        return self.controller.gain_names

    @property
    def pressure_unit(self) -> str:
        """The unit of the brake pressures ('' for a plant without brakes; braking plants
        answer their preset's `PresetInfo.pressure_unit`)."""
        return ""

    def units(self, declared: Mapping[str, str]) -> dict[str, str]:
        """Trace units as a kernel layout declares them, the pressure's in this preset's unit."""
        return {name: with_pressure(unit, self.pressure_unit) for name, unit in declared.items()}

    def pick_objective(self, objective: str | None) -> str:
        """The objective to use (the default when None), or InputError listing the known ones."""
        objective = objective or self.default_objective
        if objective not in self.objectives:
            raise InputError(
                "objective",
                f"unknown objective {objective!r} for {self.plant} "
                f"(known: {', '.join(self.objectives)})",
            )
        return objective

    @abstractmethod
    def params(self) -> dict[str, Any]:
        """Every plant, road, solver and controller value used, by name, in SI (JSON echo)."""

    @abstractmethod
    def metrics(self, gains: np.ndarray) -> dict[str, np.ndarray]:
        """Metrics of each candidate row: name -> array of shape (n,)."""

    @abstractmethod
    def cost(self, gains: np.ndarray, objective: str | None = None) -> np.ndarray:
        """Objective of each row, shape (n,), finite, at most PENALTY, never NaN."""

    @abstractmethod
    def trace(self, gains: np.ndarray) -> Trace:
        """Time series of one candidate (gains of shape (k,))."""

    def gains_array(self, gains: Mapping[str, float] | None) -> np.ndarray:
        """Registry defaults overridden by `gains`, as a (k,) array in gain_names order."""
        values = self.controller.default_gains()
        for name, value in (gains or {}).items():
            if name not in values:
                if not self.gain_names:
                    raise InputError("gains", f"{self.controller.name} has no gains, got {name!r}")
                raise InputError(
                    "gains",
                    f"unknown gain {name!r} for {self.controller.name} "
                    f"(known: {', '.join(self.gain_names)})",
                )
            values[name] = float(value)
        return np.array([values[n] for n in self.gain_names], dtype=np.float64)


S = TypeVar("S", bound=Scenario)


class Plant(ABC, Generic[S]):
    """A registered plant: its spec, presets, roads and how to build a scenario (of type S)."""

    spec: PlantSpec

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def description(self) -> str:
        return self.spec.description

    @property
    def default_preset(self) -> str:
        return self.spec.default_preset

    def presets(self) -> dict[str, PresetInfo]:
        """Presets by name (those of the spec; a plant whose spec names none overrides this)."""
        return self.spec.preset_infos()

    def roads(self) -> dict[str, str]:
        """Road name -> one-line description (the spec's; else overridden)."""
        return self.spec.road_descriptions()

    @abstractmethod
    def controllers(self) -> list[ControllerSpec]:
        """The controllers a scenario of this plant accepts, in catalogue order."""

    def parameter_sets(self, preset: str | None = None) -> dict[str, Any]:
        """The parameter dataclasses of a scenario by group (plant, road, scoring, ...), at the
        preset's values (default preset when None): what `list params` describes from their
        field metadata (unit, valid and plausible range). Plants override it."""
        return {}

    def scenario(
        self,
        preset: str | None = None,
        road: str | None = None,
        controller: str = "none",
        params: Mapping[str, object] | None = None,
        seed: int = 0,
    ) -> S:
        """Resolve and validate; unknown names or bad values raise InputError.

        The preset (default when None) and road (the preset's first when None) are resolved
        here from the spec's presets; `build` does the rest."""
        presets = self.spec.preset_table()
        name = pick_preset(self.name, preset, self.default_preset, presets)
        pre = presets[name]
        return self.build(
            name, pre, road or pre.info.roads[0], controller, dict(params or {}), seed
        )

    def build(
        self,
        preset: str,
        pre: Any,
        road: str,
        controller: str,
        values: dict[str, object],
        seed: int,
    ) -> S:
        """The scenario of preset `preset` (its object `pre` from the spec's presets) on `road`
        with `controller` and parameter overrides `values`. Plants whose spec declares no
        presets override `scenario` instead."""
        raise NotImplementedError(f"plant {self.name!r} defines neither build nor scenario")
