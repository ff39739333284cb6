"""The tuning problem of a run spec, built once per distinct problem in a process.

Planning a study builds each distinct problem (that is its validation) and keeps it here; runs in
the same process (the serial executor) take it from here, and a worker process builds it from
the spec on first use and keeps it for the next runs of the same problem (other optimizers at
the same seed index). The key holds every field that goes into `build_problem`, the scenario
seed included: two runs share a problem only when building it twice would give the same thing.

A scenario with an `[uncertainty]` table is a robust problem whose training set is
drawn from the run's seed sequence: every optimizer at a seed index sees the same K scenarios,
in any process (the scenario seed in the key is derived from that sequence).
"""

from __future__ import annotations

import json
import threading
from collections import OrderedDict
from collections.abc import Mapping
from typing import Any

import numpy as np

from chassistune.errors import InputError
from chassistune.tuning.problem import TuningProblem, build_problem

MAX_PROBLEMS = 64
PROBLEM_FIELDS = (
    "plant",
    "preset",
    "controller",
    "objective",
    "roads",
    "aggregate",
    "params",
    "bounds",
    "uncertainty",
)

_CACHE: OrderedDict[str, TuningProblem] = OrderedDict()
_LOCK = threading.Lock()


def problem_key(fields: Mapping[str, Any], seed: int) -> str:
    """The identity of a problem: the `PROBLEM_FIELDS` of a run spec and the scenario seed."""
    data: dict[str, Any] = {f: fields.get(f) for f in PROBLEM_FIELDS}
    data["roads"] = list(data["roads"])
    data["bounds"] = {k: list(v) for k, v in data["bounds"].items()}
    return json.dumps([data, seed], sort_keys=True)


def remember(key: str, problem: TuningProblem) -> None:
    """Keep `problem` under `key` (the least recently used one goes beyond MAX_PROBLEMS)."""
    with _LOCK:
        _CACHE[key] = problem
        _CACHE.move_to_end(key)
        while len(_CACHE) > MAX_PROBLEMS:
            _CACHE.popitem(last=False)


def build(
    fields: Mapping[str, Any], seed: int, sequence: np.random.SeedSequence | None = None
) -> TuningProblem:
    """The nominal problem of the spec fields, or with an `uncertainty` table the robust one
    (training set from `sequence`, default the scenario seed); errors name the domain field
    (`uncertainty.vary.mass_kg`)."""
    problem = build_problem(
        fields["plant"],
        fields["controller"],
        fields["preset"],
        list(fields["roads"]),
        fields["objective"],
        fields["aggregate"],
        fields["params"],
        fields["bounds"],
        seed,
    )
    table = fields.get("uncertainty")
    if table is None:
        return problem
    from chassistune.tuning.robust.problem import known_for, robust_problem
    from chassistune.tuning.robust.spec import parse_table

    try:
        spec = parse_table(table, known_for(problem))
        return robust_problem(
            problem, spec, fields["params"], seed if sequence is None else sequence
        )
    except InputError as exc:
        raise InputError(f"uncertainty.{exc.field}", exc.problem) from None


def problem_for(
    fields: Mapping[str, Any], seed: int, sequence: np.random.SeedSequence | None = None
) -> TuningProblem:
    """The problem of these spec fields and scenario seed: kept, or built and kept."""
    key = problem_key(fields, seed)
    with _LOCK:
        found = _CACHE.get(key)
        if found is not None:
            _CACHE.move_to_end(key)
            return found
    problem = build(fields, seed, sequence)
    remember(key, problem)
    return problem
