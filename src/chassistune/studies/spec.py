"""Study configs (TOML, validated by pydantic) and their expansion into run specs (design.md 2, 9).

A config is data: nothing in it is evaluated. `load_config` parses and validates the file,
`plan_study` resolves every name against the registries (building each distinct problem once,
kept for the runs of this process) and expands the grid scenarios x roads x optimizers x seeds
into `RunSpec`s. Both raise `InputError` naming the field (`scenarios[0].roads`,
`optimizers[1].hyperparameters`, ...), so a bad config is refused before anything is written.

Seeds: each run's randomness comes from `SeedSequence(study.seed, spawn_key=(seed_index,))`, the
same for every scenario and optimizer at that index (common random numbers) and unchanged when
seeds, scenarios or optimizers are added.
"""

from __future__ import annotations

import hashlib
import json
import math
import tomllib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
    ValidationError,
    field_validator,
    model_validator,
)

from chassistune._io import read_input
from chassistune._rng import child_seed, int_seed, make_rng
from chassistune.errors import InputError
from chassistune.memory import PLANNED_RUN_BYTES, check_fits, tune_bytes
from chassistune.tuning.robust.aggregate import parse_aggregate

MAX_CONFIG_BYTES = 1 << 20
"""Largest study config read (a config is a page of TOML)."""

MAX_SEEDS = 100_000
"""Largest seed count (and seed index) a config may ask for."""

Finite = Annotated[float, Field(strict=True, allow_inf_nan=False)]
Name = Annotated[str, Field(strict=True, min_length=1, max_length=200)]
Count = Annotated[int, Field(strict=True, ge=1)]
Value = StrictFloat | StrictInt | StrictStr
HyperValue = StrictBool | StrictFloat | StrictInt | StrictStr


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class StudySection(_Model):
    """`[study]`: name, seeds (a count n = indices 0..n-1, or a list of indices), root seed."""

    name: Name
    seeds: tuple[int, ...]
    seed: Annotated[int, Field(strict=True, ge=0, lt=2**63)] = 0
    description: Annotated[str, Field(strict=True, max_length=2000)] = ""

    @field_validator("seeds", mode="before")
    @classmethod
    def _seed_indices(cls, v: Any) -> tuple[int, ...]:
        if isinstance(v, int) and not isinstance(v, bool):
            if not 1 <= v <= MAX_SEEDS:
                raise ValueError(f"a seed count must be in 1..{MAX_SEEDS}, got {v}")
            return tuple(range(v))
        if isinstance(v, list):
            if not v:
                raise ValueError("the list of seed indices is empty")
            for s in v:
                if isinstance(s, bool) or not isinstance(s, int) or not 0 <= s < MAX_SEEDS:
                    raise ValueError(
                        f"seed indices must be integers in 0..{MAX_SEEDS - 1}, got {s!r}"
                    )
            if len(set(v)) != len(v):
                raise ValueError("a seed index is listed twice")
            return tuple(v)
        raise ValueError(f"expected a seed count or a list of seed indices, got {v!r}")


class BudgetConfig(_Model):
    """`[budget]`: population and iterations and/or evaluations (defaults as `tune`)."""

    pop_size: Count = 30
    iterations: Count | None = None
    evaluations: Count | None = None

    @model_validator(mode="before")
    @classmethod
    def _some_budget(cls, data: Any) -> Any:
        if isinstance(data, dict) and "iterations" not in data and "evaluations" not in data:
            return {**data, "iterations": 100}
        return data


MISSING = "missing required field: "
"""Prefix of a validator's error that names a missing field (reported at that field's path)."""


class ScenarioConfig(_Model):
    """`[[scenarios]]`: what is tuned, on which roads, scored how; or, with `functions`, the
    benchmark functions an optimizer comparison minimizes (no plant, controller or roads)."""

    name: Name | None = None
    plant: Name | None = None
    preset: Name | None = None
    controller: Name | None = None
    functions: list[Name] | None = None
    budget: BudgetConfig | None = None
    objective: Name | None = None
    roads: list[Name] | None = None
    tune_roads: list[Name] | None = None
    aggregate: Name = "mean"
    test_roads: list[Name] | None = None
    params: dict[str, Value] = Field(default_factory=dict)
    bounds: dict[str, tuple[Finite, Finite]] = Field(default_factory=dict)
    uncertainty: dict[str, Any] | None = None
    """Robust tuning: the `[uncertainty]` table (`tuning.robust.spec.parse_table`)."""

    @field_validator("roads", "tune_roads", "test_roads")
    @classmethod
    def _distinct(cls, v: list[str] | None) -> list[str] | None:
        if v is not None:
            if not v:
                raise ValueError("the list is empty")
            if len(set(v)) != len(v):
                raise ValueError("a road is listed twice")
        return v

    @field_validator("tune_roads")
    @classmethod
    def _several(cls, v: list[str] | None) -> list[str] | None:
        if v is not None and len(v) < 2:
            raise ValueError(
                "one controller for several roads needs at least two roads (use `roads` for one)"
            )
        return v

    @field_validator("bounds", mode="before")
    @classmethod
    def _pairs(cls, v: Any) -> Any:
        if isinstance(v, dict):
            for gain, pair in v.items():
                if not isinstance(pair, list) or len(pair) != 2:
                    raise ValueError(f"{gain}: expected [lo, hi], got {pair!r}")
        return v

    @field_validator("bounds")
    @classmethod
    def _ordered(cls, v: dict[str, tuple[float, float]]) -> dict[str, tuple[float, float]]:
        for gain, (lo, hi) in v.items():
            if not lo < hi:
                raise ValueError(f"{gain}: need lo < hi, got [{lo:g}, {hi:g}]")
        return v

    @model_validator(mode="after")
    def _kind(self) -> ScenarioConfig:
        if self.functions is not None:
            plant_keys = (
                "plant",
                "preset",
                "controller",
                "objective",
                "roads",
                "tune_roads",
                "test_roads",
                "uncertainty",
            )
            extra = [k for k in plant_keys if getattr(self, k) is not None]
            extra += [k for k in ("params", "bounds") if getattr(self, k)]
            if extra:
                raise ValueError(
                    f"a `functions` scenario takes no plant settings, got {', '.join(extra)}"
                )
            if not self.functions or len(set(self.functions)) != len(self.functions):
                raise ValueError("`functions` must list distinct benchmark functions")
        else:
            for key in ("plant", "controller"):
                if getattr(self, key) is None:
                    raise ValueError(f"{MISSING}{key}")
        return self


class OptimizerConfig(_Model):
    """`[[optimizers]]`: a registered optimizer, an optional label and hyperparameters."""

    name: Name
    label: Name | None = None
    hyperparameters: dict[str, HyperValue] = Field(default_factory=dict)


class QuickConfig(_Model):
    """`[quick]`: the reduced run of `reproduce --quick`: seed count and budget overrides that
    replace those of `[budget]` and of every scenario's `budget`."""

    seeds: Count
    pop_size: Count | None = None
    iterations: Count | None = None
    evaluations: Count | None = None


class StudyConfig(_Model):
    """A whole study config file."""

    study: StudySection
    scenarios: Annotated[list[ScenarioConfig], Field(min_length=1)]
    optimizers: Annotated[list[OptimizerConfig], Field(min_length=1)]
    budget: BudgetConfig = Field(default_factory=BudgetConfig)
    quick: QuickConfig | None = None


def _quick_budget(b: BudgetConfig, q: QuickConfig) -> BudgetConfig:
    if q.iterations is None and q.evaluations is None:
        iters, evals = b.iterations, b.evaluations
    else:
        iters, evals = q.iterations, q.evaluations
    return BudgetConfig(pop_size=q.pop_size or b.pop_size, iterations=iters, evaluations=evals)


def quick_config(config: StudyConfig) -> StudyConfig:
    """The config's `[quick]` version: study `<name>-quick` with its seeds and budgets."""
    q = config.quick
    if q is None:
        raise InputError("quick", f"study {config.study.name!r} has no [quick] table")
    return config.model_copy(
        update={
            "study": config.study.model_copy(
                update={"name": f"{config.study.name}-quick", "seeds": tuple(range(q.seeds))}
            ),
            "budget": _quick_budget(config.budget, q),
            "scenarios": [
                sc.model_copy(update={"budget": _quick_budget(sc.budget, q)})
                if sc.budget is not None
                else sc
                for sc in config.scenarios
            ],
            "quick": None,
        }
    )


class RunSpec(_Model):
    """Everything a worker needs to do one run; its JSON is the run's identity in the store."""

    study: str
    group: str
    scenario: str
    plant: str
    preset: str
    controller: str
    objective: str
    roads: tuple[str, ...]
    aggregate: str
    test_roads: tuple[str, ...]
    params: dict[str, Value]
    bounds: dict[str, tuple[float, float]]
    optimizer: str
    optimizer_name: str
    hyperparameters: dict[str, HyperValue]
    pop_size: int
    max_iter: int | None
    max_evals: int | None
    root_seed: int
    seed: int
    uncertainty: dict[str, Any] | None = None

    @property
    def key(self) -> str:
        """Unique within a study: scenario, optimizer label and seed index."""
        return f"{self.scenario}|{self.optimizer}|{self.seed}"

    @property
    def road(self) -> str:
        """The export's `road`: the road, or the tuned roads joined by '+'."""
        return "+".join(self.roads)

    @property
    def spec_hash(self) -> str:
        nominal = {"uncertainty"} if self.uncertainty is None else set()  # hashes as before
        text = json.dumps(self.model_dump(mode="json", exclude=nominal), sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()

    def seed_sequence(self) -> np.random.SeedSequence:
        """Child `seed` of the study's root seed."""
        return child_seed(self.root_seed, self.seed)

    def optimizer_rng(self) -> np.random.Generator:
        """The optimizer's generator, from `seed_sequence()`."""
        return make_rng(self.seed_sequence())

    @property
    def scenario_seed(self) -> int:
        """The scenario's seed (the quarter car's road realization), from the same sequence."""
        return int_seed(self.seed_sequence())


@dataclass(frozen=True)
class StudyPlan:
    """A validated config and its runs, in grid order (scenario, road, optimizer, seed)."""

    config: StudyConfig
    runs: tuple[RunSpec, ...]

    @property
    def scenarios(self) -> list[str]:
        return list(dict.fromkeys(r.scenario for r in self.runs))

    @property
    def optimizers(self) -> list[str]:
        return list(dict.fromkeys(r.optimizer for r in self.runs))

    def config_json(self) -> str:
        return json.dumps(self.config.model_dump(mode="json"), sort_keys=True)


# -- loading -------------------------------------------------------------------------------------


def _where(loc: tuple[int | str, ...]) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "CONFIG"


def _first_error(exc: ValidationError) -> InputError:
    err = exc.errors()[0]
    kind = err["type"]
    if kind == "extra_forbidden":
        problem = "unknown key"
    elif kind == "missing":
        problem = "missing required field"
    else:
        problem = str(err["msg"]).removeprefix("Value error, ")
        if problem.startswith(MISSING):  # a field required by the scenario's kind
            return InputError(
                _where((*err["loc"], problem.removeprefix(MISSING))), "missing required field"
            )
        problem = problem[:1].lower() + problem[1:]
        value = err.get("input")
        if kind != "value_error" and isinstance(value, str | int | float | bool):
            problem += f", got {value!r}"
    return InputError(_where(tuple(err["loc"])), problem)


def parse_config(data: dict[str, Any]) -> StudyConfig:
    """Validate parsed TOML; the first problem raises InputError naming its field."""
    if not data:
        raise InputError(
            "CONFIG", "the config is empty (need [study], [[scenarios]] and [[optimizers]])"
        )
    try:
        return StudyConfig.model_validate(data)
    except ValidationError as exc:
        raise _first_error(exc) from None


def load_config(path: str | Path) -> StudyConfig:
    """Read and validate a TOML study config."""
    p = Path(path)
    if not p.exists():
        raise InputError("CONFIG", f"file not found: {str(p)!r}")
    if p.is_dir():
        raise InputError("CONFIG", f"{str(p)!r} is a folder, not a TOML file")
    text = read_input(p, "CONFIG", MAX_CONFIG_BYTES)
    if not text.strip():
        raise InputError("CONFIG", f"{str(p)!r} is empty")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("CONFIG", f"{str(p)!r} is not valid TOML: {exc}") from None
    return parse_config(data)


# -- planning ------------------------------------------------------------------------------------

_CONFIG_KEYS = {
    "road": "roads",
    "pop_size": "budget.pop_size",
    "max_iter": "budget.iterations",
    "max_evals": "budget.evaluations",
}
"""Domain field heads whose config key differs (budget keys live in the top-level table)."""


def config_path(field: str, table: str) -> str:
    """Where a domain field path lives in the config (the one mapping): `params.mass_kg` of
    `scenarios[0]` -> `scenarios[0].params.mass_kg`, `road` -> `scenarios[0].roads`,
    `pop_size` -> `budget.pop_size`."""
    head, dot, rest = field.partition(".")
    key = _CONFIG_KEYS.get(head, head)
    return key if key.startswith("budget.") else f"{table}.{key}{dot}{rest}"


@dataclass(frozen=True)
class _Cell:
    """One scenario of the comparison: a config scenario on one road or one set of roads."""

    group: str
    name: str
    roads: tuple[str, ...]


def _cells(sc: ScenarioConfig, plant: str, controller: str, default_road: str) -> Iterator[_Cell]:
    group = sc.name or f"{plant}-{controller}"
    roads = sc.roads if sc.roads is not None else ([] if sc.tune_roads else [default_road])
    for road in roads:
        yield _Cell(group, f"{group}/{road}", (road,))
    if sc.tune_roads:
        yield _Cell(group, f"{group}/{'+'.join(sc.tune_roads)}", tuple(sc.tune_roads))


def _resolve_functions(
    index: int, sc: ScenarioConfig, functions: list[str]
) -> list[dict[str, Any]]:
    """The run-spec fields of a benchmark-function scenario: one cell per function."""
    from chassistune.tuning.functions import FUNCTION_KIND, build_function_problem

    group = sc.name or "functions"
    out = []
    for k, name in enumerate(functions):
        try:
            problem = build_function_problem(name, 0)
        except InputError as exc:
            raise InputError(f"scenarios[{index}].functions[{k}]", exc.problem) from None
        out.append(
            {
                "group": group,
                "scenario": f"{group}/{problem.function.name}",
                "plant": FUNCTION_KIND,
                "preset": "",
                "controller": "",
                "objective": "value",
                "roads": (problem.function.name,),
                "aggregate": "mean",
                "test_roads": (),
                "params": {},
                "bounds": dict(zip(problem.gain_names, problem.bounds, strict=True)),
            }
        )
    return out


def _check_spans(names: tuple[str, ...], bounds: list[tuple[float, float]]) -> None:
    """Refuse a box whose width hi - lo overflows a float (the optimizers scale by it)."""
    for name, (lo, hi) in zip(names, bounds, strict=True):
        if not math.isfinite(hi - lo):
            raise InputError(
                f"bounds.{name}", f"the range hi - lo of [{lo:g}, {hi:g}] overflows a float"
            )


def _resolve_scenario(
    index: int, sc: ScenarioConfig, seed: int, sequence: np.random.SeedSequence
) -> list[dict[str, Any]]:
    """Build each cell's problem once (kept for the runs: `studies.problems`); the run-spec
    fields of each cell. `seed` is the scenario seed of the study's first seed index, `sequence`
    its seed sequence (a robust problem's training set)."""
    from chassistune.scenarios.registry import get_plant
    from chassistune.studies.problems import build, problem_key, remember

    if sc.functions is not None:
        return _resolve_functions(index, sc, sc.functions)
    plant_name, controller = str(sc.plant), str(sc.controller)  # both set (`_kind`)
    try:
        plant = get_plant(plant_name)
        preset = sc.preset or plant.default_preset
        default_road = plant.presets()[preset].roads[0] if preset in plant.presets() else ""
        cells = list(_cells(sc, plant_name, controller, default_road))
        every_road = list(dict.fromkeys(r for c in cells for r in c.roads))
        test_roads = tuple(sc.test_roads or every_road)
        out = []
        for cell in cells:
            fields: dict[str, Any] = {
                "plant": plant_name,
                "preset": preset,
                "controller": controller,
                "objective": sc.objective,
                "roads": cell.roads,
                "aggregate": sc.aggregate,
                "params": dict(sc.params),
                "bounds": dict(sc.bounds),
                "uncertainty": sc.uncertainty,
            }
            problem = build(fields, seed, sequence)
            _check_spans(problem.gain_names, problem.bounds)
            fields.update(
                {
                    "group": cell.group,
                    "scenario": cell.name,
                    "preset": problem.scenarios[0].preset,
                    "objective": problem.objective,
                    "aggregate": str(parse_aggregate(sc.aggregate)),
                    "test_roads": test_roads,
                    "bounds": dict(zip(problem.gain_names, problem.bounds, strict=True)),
                }
            )
            remember(problem_key(fields, seed), problem)
            out.append(fields)
    except InputError as exc:
        raise InputError(config_path(exc.field, f"scenarios[{index}]"), exc.problem) from None
    for road in test_roads:
        if road not in every_road:
            try:
                plant.scenario(preset, road, controller, sc.params, seed)
            except InputError as exc:
                raise InputError(f"scenarios[{index}].test_roads", exc.problem) from None
    return out


def _check_hyper_types(opt: OptimizerConfig, where: str) -> None:
    """Refuse a hyperparameter whose value is not of its default's type (a number for a number:
    `w = "x"`), naming it; unknown names are left to the registry's check."""
    from chassistune.optimizers.registry import get

    defaults = get(opt.name).defaults.as_dict()
    for key, value in opt.hyperparameters.items():
        if key not in defaults:
            continue
        default = defaults[key]
        if isinstance(default, bool) or not isinstance(default, int | float):
            ok, kind = isinstance(value, type(default)), type(default).__name__
        elif isinstance(default, float):
            ok, kind = isinstance(value, int | float) and not isinstance(value, bool), "number"
        else:
            ok, kind = isinstance(value, int) and not isinstance(value, bool), "whole number"
        if not ok:
            raise InputError(f"{where}.hyperparameters.{key}", f"expected a {kind}, got {value!r}")


def _resolve_optimizer(
    index: int, opt: OptimizerConfig, budget: BudgetConfig, bounds: list[tuple[float, float]]
) -> None:
    """Construct the optimizer once (no evaluation) so that every setting is checked."""
    from chassistune.optimizers.peers import PEERS
    from chassistune.optimizers.registry import get, make

    where = f"optimizers[{index}]"
    if opt.name in PEERS:
        if opt.hyperparameters:
            raise InputError(
                f"{where}.hyperparameters",
                f"the peer {opt.name} runs with the "
                "settings of optimizers.peers; give no hyperparameters",
            )
        return
    try:
        get(opt.name)
    except InputError as exc:
        raise InputError(f"{where}.name", exc.problem) from None
    _check_hyper_types(opt, where)
    hyper: dict[str, Any] = dict(opt.hyperparameters)
    try:
        make(
            opt.name,
            bounds,
            budget.pop_size,
            0,
            max_iter=budget.iterations,
            max_evals=budget.evaluations,
            **hyper,
        )
    except InputError as exc:
        if exc.field in _CONFIG_KEYS:
            field = config_path(exc.field, where)
        elif exc.field in opt.hyperparameters:
            field = config_path(f"hyperparameters.{exc.field}", where)
        else:
            field = config_path("hyperparameters", where)
        raise InputError(field, exc.problem) from None
    except (TypeError, ValueError) as exc:
        raise InputError(f"{where}.hyperparameters", str(exc)) from None


def _check_budget(budget: BudgetConfig, cells: list[dict[str, Any]], where: str) -> None:
    """Refuse an evaluation budget smaller than one population, as `tune` does (no iteration
    would run, and every run would fail), and a population whose run would not fit in memory."""
    from chassistune.optimizers.base import check_covers_population
    from chassistune.tuning.robust.spec import UncertaintySpec

    try:
        check_covers_population(budget.pop_size, budget.evaluations)
    except InputError as exc:
        raise InputError(f"{where}.evaluations", exc.problem) from None
    for cell in cells:
        table = cell.get("uncertainty") or {}
        training = int(table.get("scenarios", UncertaintySpec.scenarios)) if table else 1
        need = tune_bytes(budget.pop_size, len(cell["bounds"]), len(cell["roads"]) * training)
        check_fits(need, f"{where}.pop_size", f"a population of {budget.pop_size:,}")


def _check_grid(runs: int, cells: int, config: StudyConfig) -> None:
    """Refuse, before expanding it, a grid of runs whose plan would not fit in memory."""
    check_fits(
        runs * PLANNED_RUN_BYTES,
        "study.seeds",
        f"a grid of {runs:,} runs ({cells} scenario cells x {len(config.optimizers)} "
        f"optimizers x {len(config.study.seeds)} seeds)",
    )


def plan_study(config: StudyConfig) -> StudyPlan:
    """Resolve every name and expand the grid into run specs (InputError on the first problem)."""
    cells: list[dict[str, Any]] = []
    budgets: list[BudgetConfig] = []
    first = child_seed(config.study.seed, config.study.seeds[0])
    for i, sc in enumerate(config.scenarios):
        resolved = _resolve_scenario(i, sc, int_seed(first), first)
        budget = sc.budget or config.budget
        _check_budget(budget, resolved, f"scenarios[{i}].budget" if sc.budget else "budget")
        budgets += [budget] * len(resolved)
        if any(c["group"] == resolved[0]["group"] for c in cells):
            raise InputError(
                f"scenarios[{i}].name",
                f"another scenario is also named "
                f"{resolved[0]['group']!r}: give each scenario a distinct `name`",
            )
        cells.extend(resolved)
    _check_grid(len(cells) * len(config.optimizers) * len(config.study.seeds), len(cells), config)
    labels: list[str] = []
    for j, opt in enumerate(config.optimizers):
        label = opt.label or opt.name
        if label in labels:
            raise InputError(
                f"optimizers[{j}].label",
                f"{label!r} is used twice: give each optimizer entry a distinct `label`",
            )
        labels.append(label)
        for c, b in zip(cells, budgets, strict=True):
            _resolve_optimizer(j, opt, b, list(c["bounds"].values()))
    runs = tuple(
        RunSpec(
            study=config.study.name,
            optimizer=label,
            optimizer_name=opt.name.lower(),
            hyperparameters=dict(opt.hyperparameters),
            pop_size=b.pop_size,
            max_iter=b.iterations,
            max_evals=b.evaluations,
            root_seed=config.study.seed,
            seed=s,
            **c,
        )
        for c, b in zip(cells, budgets, strict=True)
        for opt, label in zip(config.optimizers, labels, strict=True)
        for s in config.study.seeds
    )
    return StudyPlan(config, runs)


def load_plan(path: str | Path) -> StudyPlan:
    """`load_config` then `plan_study`."""
    return plan_study(load_config(path))
