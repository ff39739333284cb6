"""studies.records and studies.problems: typed results, one status vocabulary, and each distinct
problem built once per process."""

from __future__ import annotations

from collections import OrderedDict

import pytest
from studies_helpers import tiny_config, write_plan

from chassistune.studies import problems, worker
from chassistune.studies.executors import SerialExecutor
from chassistune.studies.records import RunResult, RunStatus
from chassistune.studies.runner import run_study
from chassistune.studies.store import _SCHEMA, open_study
from chassistune.tuning import problem as tuning_problem


def test_the_store_schema_allows_exactly_the_enum_words() -> None:
    assert "CHECK (status IN ('completed', 'failed'))" in _SCHEMA
    assert [s.value for s in RunStatus] == ["completed", "failed"]


def test_each_distinct_problem_is_built_once_in_process(tmp_path, monkeypatch) -> None:
    built: list[int] = []
    real = tuning_problem.build_problem

    def counting(*args, **kwargs):  # type: ignore[no-untyped-def]
        built.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(problems, "_CACHE", OrderedDict())
    monkeypatch.setattr(tuning_problem, "build_problem", counting)  # planning's import
    monkeypatch.setattr(problems, "build_problem", counting)  # the workers'
    # 2 roads (cells) x 2 optimizers x 3 seeds = 12 runs, 2 x 3 distinct problems
    _, plan = write_plan(tmp_path, tiny_config(seeds=3, roads='["iso-b", "iso-c"]'))
    assert len(built) == 2  # planning: one per cell, kept for the first seed index
    outcome = run_study(plan, tmp_path / "out", SerialExecutor())
    assert outcome.completed == 12
    assert len(built) == 6  # the runs built only the other two seed indices' problems
    with open_study(tmp_path / "out") as store:
        records = list(store.records())
    assert {r.status for r in records} == {RunStatus.COMPLETED}


def test_worker_returns_a_frozen_typed_result(tmp_path) -> None:
    _, plan = write_plan(tmp_path, tiny_config(seeds=1))
    res = worker.execute_run(plan.runs[0])
    assert isinstance(res, RunResult) and res.completed and res.error is None
    assert res.key == plan.runs[0].key and res.nfev == res.history_nfev[-1]
    with pytest.raises(AttributeError):
        res.best_cost = 0.0  # type: ignore[misc]
    lost = worker.failed_result(plan.runs[0], "gone")
    assert lost.status is RunStatus.FAILED and not lost.completed and lost.best_cost is None
