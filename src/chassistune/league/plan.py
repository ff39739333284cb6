"""The league as a study (design.md 9): one scenario per (plant, law with gains), every law of
the registry that runs on the plant in its mode, tuned on the plant's training roads together
with one optimizer and one evaluation budget; laws without gains are scored as they are."""

from __future__ import annotations

from dataclasses import dataclass

from chassistune.controllers import laws
from chassistune.errors import InputError
from chassistune.league.cases import KNOWLEDGE, OBJECTIVE, PLANTS, LeaguePlant
from chassistune.studies.spec import StudyPlan, parse_config, plan_study

STUDY_NAME = "league"


@dataclass(frozen=True)
class Budget:
    """Seeds per law, population and evaluations of every tuning run."""

    seeds: int
    pop_size: int
    evaluations: int


FULL = Budget(seeds=10, pop_size=20, evaluations=2000)
QUICK = Budget(seeds=2, pop_size=6, evaluations=18)


@dataclass(frozen=True)
class Setting:
    """A league: its plants (names of `cases.PLANTS`), optimizer, budget and root seed."""

    plants: tuple[str, ...]
    optimizer: str = "cma-es"
    budget: Budget = FULL
    seed: int = 0
    road_knowledge: str = "fixed"
    """What the laws that regulate a target slip are told of the road (`KNOWLEDGE`)."""


def runs_realistic(lp: LeaguePlant) -> bool:
    """Whether the plant's league runs the realistic ECU."""
    return dict(lp.params).get("ecu") == "realistic"


def knowledge(law: str, setting: Setting) -> str:
    """The road knowledge of a law's runs: `none` for a law that regulates no target slip,
    else the league's."""
    return setting.road_knowledge if laws.get(law).needs_target else "none"


def run_params(lp: LeaguePlant, law: str, setting: Setting) -> dict[str, object]:
    """The parameters of every run of a law on the plant: the plant's and its road knowledge."""
    return {**dict(lp.params), "road_knowledge": knowledge(law, setting)}


def league_laws(lp: LeaguePlant, setting: Setting) -> tuple[list[str], list[str]]:
    """(tuned, untuned): the registry's laws on the plant in its mode, with gains (a fixed target
    is one) and without."""
    tuned: list[str] = []
    untuned: list[str] = []
    for spec in laws.for_plant(lp.plant):
        if runs_realistic(lp) and laws.get(spec.name).ecu is None:
            continue
        fixed = knowledge(spec.name, setting) == "fixed"
        (tuned if spec.gains or fixed else untuned).append(spec.name)
    return tuned, untuned


def scenario_name(plant: str, law: str) -> str:
    """The study scenario (group) of a law on a plant."""
    return f"{plant}:{law}"


def config(setting: Setting) -> dict[str, object]:
    """The study config of `setting` (a `studies.spec` TOML table, as data)."""
    scenarios = []
    for name in setting.plants:
        lp = PLANTS[name]
        for law in league_laws(lp, setting)[0]:
            scenarios.append(
                {
                    "name": scenario_name(lp.plant, law),
                    "plant": lp.plant,
                    "preset": lp.preset,
                    "controller": law,
                    "objective": OBJECTIVE,
                    "tune_roads": list(lp.training),
                    "params": run_params(lp, law, setting),
                }
            )
    b = setting.budget
    return {
        "study": {
            "name": STUDY_NAME,
            "seeds": b.seeds,
            "seed": setting.seed,
            "description": "every ABS law of the registry tuned alike, scored on held-out cases",
        },
        "scenarios": scenarios,
        "optimizers": [{"name": setting.optimizer}],
        "budget": {"pop_size": b.pop_size, "evaluations": b.evaluations},
    }


def plan(setting: Setting) -> StudyPlan:
    """The league's study plan (InputError naming the option for a bad setting)."""
    for name in setting.plants:
        if name not in PLANTS:
            raise InputError("plants", f"the league runs {', '.join(PLANTS)}, not {name!r}")
    if setting.road_knowledge not in KNOWLEDGE:
        raise InputError(
            "road_knowledge", f"must be {' or '.join(KNOWLEDGE)}, got {setting.road_knowledge!r}"
        )
    try:
        return plan_study(parse_config(config(setting)))
    except InputError as exc:
        field = "optimizer" if exc.field.startswith("optimizers") else exc.field
        raise InputError(field, exc.problem) from None
