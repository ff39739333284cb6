"""Each tuned law on its plant's held-out cases (docs/league.md, "Scores"): the stop distance over
the case's adhesion bound, UN R13-H adhesion utilisation (single wheel), the slip ITAE, valve
switching per second (the realistic ECU's valves), and the peak yaw rate in the first second."""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from chassistune.errors import InputError
from chassistune.league.cases import PLANTS, Case, LeaguePlant
from chassistune.league.plan import (
    Setting,
    league_laws,
    run_params,
    runs_realistic,
    scenario_name,
)
from chassistune.scenarios.registry import get_plant
from chassistune.studies.store import RunRecord, open_study

SCORES = {
    "distance_ratio": "stop distance over the adhesion bound [-]",
    "r13h_epsilon": "UN R13-H adhesion utilisation [-] (single wheel)",
    "slip_itae": "slip ITAE [s^2] about the target the law is given (the road's peak without one)",
    "locked_time_s": "time a wheel was locked [s] (vehicle: the four wheels' times added)",
    "valve_switches_per_s": "valve switches per second [1/s] (realistic ECU)",
    "yaw_rate_peak_1s_rad_s": "peak yaw rate in the first second [rad/s] (vehicle)",
}
"""The score columns, with what they are and their units."""

COLUMNS = ["plant", "law", "seed", "case", "road", "status", *SCORES]


@dataclass(frozen=True)
class Tuned:
    """A law's gains to score: a tuning run's best (seed: its index) or the law as it is (seed
    -1, no gains)."""

    plant: str
    law: str
    seed: int
    gains: Mapping[str, float]
    run_time_s: float = 0.0
    """The tuning run's wall time (0 for a law as it is)."""


def case_params(lp: LeaguePlant, case: Case, law: str, setting: Setting) -> dict[str, object]:
    """The parameters of a case's runs: the law's on the plant (`plan.run_params`), the case's,
    and its scaled ones (the preset's value times the factor)."""
    params: dict[str, object] = {**run_params(lp, law, setting), **dict(case.params)}
    if case.scale:
        base = get_plant(lp.plant).scenario(lp.preset, case.road, law, params).params()
        for name, factor in case.scale:
            params[name] = float(base[name]) * factor
    return params


def tuned_laws(study_dir: str | Path, setting: Setting) -> Iterator[Tuned]:
    """The completed runs' best gains, then the laws without gains, per plant."""
    with open_study(study_dir) as store:
        records: list[RunRecord] = [r for r in store.records() if r.completed]
    for name in setting.plants:
        lp = PLANTS[name]
        tuned, untuned = league_laws(lp, setting)
        for law in tuned:
            group = scenario_name(lp.plant, law)
            for r in sorted((r for r in records if r.spec.group == group), key=_seed):
                yield Tuned(lp.plant, law, r.spec.seed, r.best_gains, r.wall_time_s or 0.0)
        for law in untuned:
            yield Tuned(lp.plant, law, -1, {})


def _seed(r: RunRecord) -> int:
    return r.spec.seed


@functools.cache
def _adhesion(preset: str, road: str, params: tuple[tuple[str, Any], ...]) -> Any:
    """k_M of a case (one search per case, shared by its laws); None where no pressure cap
    keeps the wheel rolling."""
    from chassistune.scenarios.r13h import adhesion_coefficient

    try:
        return adhesion_coefficient(preset, road, dict(params))
    except InputError:
        return None


def _r13h(lp: LeaguePlant, case: Case, t: Tuned, params: dict[str, object]) -> float:
    from chassistune.scenarios.r13h import r13h_epsilon

    if lp.plant != "abs-wheel":
        return math.nan
    plant = {k: v for k, v in params.items() if k != "road_knowledge"}  # k_M is the road's
    adhesion = _adhesion(lp.preset, case.road, tuple(sorted(plant.items())))
    if adhesion is None:
        return math.nan
    return r13h_epsilon(t.law, lp.preset, case.road, t.gains, params, adhesion).epsilon


def score(t: Tuned, case: Case, setting: Setting) -> dict[str, object]:
    """One law's scores on one case of its league plant."""
    return score_on(PLANTS[t.plant], t, case, setting)


def score_on(lp: LeaguePlant, t: Tuned, case: Case, setting: Setting) -> dict[str, object]:
    """One law's scores on one case of the plant `lp` (a league plant or another study's)."""
    params = case_params(lp, case, t.law, setting)
    sc = get_plant(lp.plant).scenario(lp.preset, case.road, t.law, params)
    gains = np.array([[float(t.gains[n]) for n in sc.gain_names]]).reshape(1, -1)
    m = sc.metrics(gains)
    stopped = bool(m["stopped"][0])
    time_s = float(m["stop_time_s"][0])
    switches = m.get("valve_switches")
    realistic = runs_realistic(lp)
    return {
        "plant": t.plant,
        "law": t.law,
        "seed": t.seed,
        "case": case.name,
        "road": case.road,
        "status": str(m["status"][0]),
        "distance_ratio": float(m["distance_ratio"][0]) if stopped else math.nan,
        "r13h_epsilon": _r13h(lp, case, t, params),
        "slip_itae": float(m["slip_itae"][0]),
        "locked_time_s": float(m["locked_time_s"][0]),
        "valve_switches_per_s": (
            float(switches[0]) / time_s
            if realistic and switches is not None and stopped
            else math.nan
        ),
        "yaw_rate_peak_1s_rad_s": float(m.get("yaw_rate_peak_1s_rad_s", [math.nan])[0]),
    }


def score_league(study_dir: str | Path, setting: Setting) -> pd.DataFrame:
    """Every tuned law on every held-out case of its plant, a row each (`COLUMNS`)."""
    rows = [
        score(t, case, setting)
        for t in tuned_laws(study_dir, setting)
        for case in PLANTS[t.plant].held_out
    ]
    return pd.DataFrame(rows, columns=COLUMNS)
