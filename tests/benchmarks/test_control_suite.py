"""The control problems as a benchmark: the shipped config runs through the study machinery at
a reduced budget, and the ECDF, references and final costs are what the store says."""

from __future__ import annotations

import re
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from chassistune.studies.control_suite import (
    PRECISIONS,
    ecdfs,
    final_costs,
    markdown,
    references,
    references_toml,
    shipped_references,
    targets,
)
from chassistune.studies.executors import make_executor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import StudyConfig, load_config, plan_study, quick_config
from chassistune.studies.store import open_study

CONFIG = resources.files("chassistune") / "data" / "studies" / "control-suite.toml"


def _config() -> StudyConfig:
    return quick_config(load_config(str(CONFIG)))


def _reduced() -> StudyConfig:
    """Two cheap problems of the suite, a paper's optimizer and the two references."""
    full = _config()
    wheel = full.scenarios[0].model_copy(update={"roads": ["wet-asphalt"]})
    keep = {"derlsp-ao", "cma-es", "random-search"}
    return full.model_copy(
        update={
            "scenarios": [wheel, full.scenarios[1]],
            "optimizers": [o for o in full.optimizers if o.name in keep],
        }
    )


def _run(config: StudyConfig, out: Path) -> list:
    with make_executor("serial") as ex:
        outcome = run_study(plan_study(config), out, ex)
    assert outcome.failed == 0
    with open_study(out) as store:
        return list(store.records())


def test_the_suite_holds_every_optimizer_and_the_four_papers_problems() -> None:
    from chassistune.optimizers.registry import names

    config = load_config(str(CONFIG))
    assert sorted(o.name for o in config.optimizers) == sorted(names())
    assert {s.plant for s in config.scenarios} == {"abs-wheel", "quarter-car", "abs-vehicle"}
    assert config.budget.evaluations is not None and config.budget.iterations is None


@pytest.fixture(scope="module")
def reduced(tmp_path_factory: pytest.TempPathFactory) -> list:
    return _run(_reduced(), tmp_path_factory.mktemp("control") / "suite")


def test_runs_at_equal_evaluations(reduced: list) -> None:
    assert len(reduced) == 2 * 3 * 2  # problems x optimizers x seeds
    assert all(r.completed and r.nfev == 36 for r in reduced)


def test_references_and_final_costs(reduced: list) -> None:
    refs = references(reduced, {})
    for problem, ref in refs.items():
        assert ref == min(r.best_cost for r in reduced if r.spec.scenario == problem)
    problem = reduced[0].spec.scenario
    assert references(reduced, {problem: 1.0, "x": 2.0}) == {**refs, problem: 1.0}
    for (_, _), (q1, q2, q3) in final_costs(reduced, refs).items():
        assert 1.0 <= q1 <= q2 <= q3
    assert np.all(np.diff(targets(2.0)) < 0) and targets(2.0)[-1] == 2.0 * (1 + PRECISIONS[-1])


def test_shipped_references_are_dated_and_below_a_short_run(reduced: list) -> None:
    """The long reference run's costs are the default references, and a 36-evaluation run
    does not reach them."""
    shipped = shipped_references()
    assert shipped.command.startswith("chassistune study run") and shipped.budget
    assert re.fullmatch(r"\d{4}-\d{2}-\d{2}", shipped.date)
    refs = references(reduced)
    assert refs == {p: shipped.values[p] for p in refs}
    assert all(r.best_cost > refs[r.spec.scenario] for r in reduced)
    text = references_toml(reduced, 'chassistune study run "a b"', "2026-01-02", "36")
    again = tomllib.loads(text)
    assert again["command"] == 'chassistune study run "a b"'
    assert again["reference"] == references(reduced, {})


def test_ecdf_is_the_stored_hits_over_the_evaluations(reduced: list) -> None:
    refs = references(reduced, {})
    curves = {e.optimizer: e for e in ecdfs(reduced, refs)}
    assert set(curves) == {"derlsp-ao", "cma-es", "random-search"}
    for name, e in curves.items():
        assert np.all(np.diff(e.fraction) >= 0) and 0 <= e.fraction[0] <= e.fraction[-1] <= 1
        runs = [r for r in reduced if r.spec.optimizer == name]
        final = np.mean([r.best_cost <= t for r in runs for t in targets(refs[r.spec.scenario])])
        assert e.fraction[-1] == pytest.approx(final)  # every target reached by the end counts
        assert 0 <= e.area <= 1
    assert max(e.fraction[-1] for e in curves.values()) > 0  # someone set each reference
    assert "| problem | f_ref |" in markdown(reduced, refs)


@pytest.mark.slow
def test_the_whole_quick_suite_runs(tmp_path: Path) -> None:
    records = _run(_config(), tmp_path / "suite")
    assert len(records) == len(plan_study(_config()).runs)
    assert all(r.completed for r in records)
    assert len(ecdfs(records, references(records))) == 14
