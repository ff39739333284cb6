"""The transfer study at a tiny budget: fuzzy-immune-abs's PID carried to the Ford Escort and
re-tuned there, end to end through the command; no stop beats its adhesion bound; the cells
marked `not available` are exactly those the plant refuses; an interrupted run resumes to the
same table. Behind `slow`: the whole study (every source, car and the vehicle), and the process
executor giving the serial table byte for byte."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from chassistune.cli.main import main
from chassistune.cli.transfer import SOURCE_KEYS
from chassistune.errors import InputError
from chassistune.papers.reproduce import shipped_config
from chassistune.plants.cars import CARS
from chassistune.scenarios.registry import get_plant
from chassistune.sim.abs_wheel_layout import STATUS_NAMES
from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import QuickConfig, RunSpec, plan_study, quick_config
from chassistune.transfer.cells import SOURCES, cells, missing
from chassistune.transfer.page import PAGE, SCORES_CSV, figure_name
from chassistune.transfer.plan import Setting, check_sources, plans
from chassistune.transfer.run import run_transfer
from chassistune.transfer.score import NOT_AVAILABLE

TINY_SOURCE = "fuzzy-immune-abs:pid"
ENDINGS = STATUS_NAMES
"""How a run ends (the vehicle's are the wheel's)."""
TINY = ("--source", TINY_SOURCE, "--car", "ford-escort", "--seeds", "1", "--pop", "4")
TINY_EVALS = ("--evals", "4")


def _reproduction(out: Path, studies: tuple[str, ...]) -> Path:
    """A reproduction's quick stores of `studies`, shrunk to 1 seed, population 4, 1 iteration
    (what `chassistune reproduce PAPER --quick` writes under DIR/studies/)."""
    (out / "studies").mkdir(parents=True)
    for name in studies:
        tiny = shipped_config(name).model_copy(
            update={"quick": QuickConfig(seeds=1, pop_size=4, iterations=1)}
        )
        plan = plan_study(quick_config(tiny))
        run_study(plan, out / "studies" / plan.config.study.name, SerialExecutor())
    return out


def _transfer(from_dir: Path, out: Path, *extra: str) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["transfer", "--from", str(from_dir), "--out", str(out), *extra])
    assert exc.value.code == 0


@pytest.fixture(scope="module")
def repro(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _reproduction(tmp_path_factory.mktemp("repro"), ("fuzzy-immune-abs",))


@pytest.fixture(scope="module")
def tiny(repro: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("transfer")
    _transfer(repro, out, *TINY, *TINY_EVALS)
    return out


def test_the_command_lists_every_source() -> None:
    assert tuple(s.key for s in SOURCES) == SOURCE_KEYS


def test_tiny_transfer_scores_every_cell(tiny: Path) -> None:
    scores = pd.read_csv(tiny / SCORES_CSV)
    (source,) = check_sources((TINY_SOURCE,))
    every = cells(source, ("ford-escort",))
    assert len(every) == 8  # the paper plant in two ECUs, the car in three tires and two ECUs
    for c in every:
        rows = scores[(scores.target == c.target) & (scores.tire == c.tire) & (scores.ecu == c.ecu)]
        if missing(c) is None:
            for gains in ("paper", "re-tuned"):
                assert sorted(rows[rows.gains == gains].road) == sorted(source.roads)
        else:
            assert len(rows) == 1
    page = (tiny / PAGE).read_text()
    refusals = [r for r in map(missing, every) if r is not None]
    assert all(f"not available: {r}" in page for r in refusals)
    assert ("not available" in page) == bool(refusals)
    assert (tiny / figure_name(source)).stat().st_size > 0


def _distances_respect_their_bounds(scores: pd.DataFrame) -> None:
    ran = scores[~scores.status.str.startswith(NOT_AVAILABLE)]
    stopped = ran[ran.status == "stopped"]
    # in the papers' ideal ECU nearly every run stops (all of them in the quick run); with the
    # realistic ECU fewer (the fuzzy immune PID's paper gains never on asphalt-0.8: measured 79 %
    # at this budget, 87-96 % in the quick run), and with the lag as well fewer still (41 % in the
    # quick run: the sampled loop's, tests/sim/test_abs_wheel_ecu_relaxation), not asserted
    ideal = ran[ran.ecu == "ideal"]
    unlagged = ran[(ran.ecu == "realistic") & ~ran.tire.str.contains("lag")]
    assert (ideal.status == "stopped").mean() > 0.9
    assert (unlagged.status == "stopped").mean() > 0.7
    assert (stopped.distance_ratio >= 1.0).all(), stopped[stopped.distance_ratio < 1.0]
    assert ran[ran.status != "stopped"].distance_ratio.isna().all()
    eps = ran[ran.plant == "abs-wheel"].r13h_epsilon.dropna()
    assert len(eps) > 0 and ((eps >= 0.0) & (eps <= 1.2)).all()
    assert (ran.locked_time_s >= 0.0).all()


def test_no_stop_beats_its_adhesion_bound(tiny: Path) -> None:
    _distances_respect_their_bounds(pd.read_csv(tiny / SCORES_CSV))


def _kernel_refuses(plant: str, preset: str, road: str, law: str, params: dict) -> str | None:  # type: ignore[type-arg]
    """Ask the plant: build the scenario and simulate one candidate (its default gains)."""
    try:
        sc = get_plant(plant).scenario(preset, road, law, params)
        m = sc.metrics(sc.gains_array(None).reshape(1, -1))
    except InputError as exc:
        return str(exc)
    assert str(m["status"][0]) in ENDINGS  # it ran to an end
    return None


def _not_available_are_the_refused(scores: pd.DataFrame, setting: Setting) -> None:
    for source in setting.sources:
        for c in setting.cells(source):
            refused = [
                _kernel_refuses(source.plant, c.target, road, source.controller, c.params())
                for road in source.roads
            ]
            rows = scores[
                (scores.source == source.key)
                & (scores.target == c.target)
                & (scores.tire == c.tire)
                & (scores.ecu == c.ecu)
            ]
            marked = rows.status.str.startswith(NOT_AVAILABLE)
            if any(refused):
                assert marked.all() and len(rows) == 1, c
                first = next(r for r in refused if r)
                assert rows.status.iloc[0].removeprefix(NOT_AVAILABLE) == first.split(" (known:")[0]
            else:
                assert not marked.any() and len(rows) > 0, c


def test_not_available_cells_are_those_the_kernel_refuses(tiny: Path) -> None:
    scores = pd.read_csv(tiny / SCORES_CSV)
    _not_available_are_the_refused(scores, Setting(check_sources((TINY_SOURCE,)), ("ford-escort",)))


class _Interrupted(SerialExecutor):
    """Serial runs, then a Ctrl-C after the first `keep`."""

    def __init__(self, keep: int) -> None:
        super().__init__()
        self.keep = keep

    def results(self, specs: list[RunSpec]) -> Iterator:  # type: ignore[override,type-arg]
        for i, result in enumerate(super().results(specs)):
            if i == self.keep:
                raise KeyboardInterrupt
            yield result


def test_an_interrupted_transfer_resumes_to_the_same_table(
    repro: Path, tiny: Path, tmp_path: Path
) -> None:
    setting = Setting(check_sources((TINY_SOURCE,)), ("ford-escort",), False, 1, 4, 4)
    with pytest.raises(KeyboardInterrupt):
        run_transfer(setting, repro, tmp_path, _Interrupted(keep=3))
    assert not (tmp_path / SCORES_CSV).exists()
    outcome = run_transfer(setting, repro, tmp_path, SerialExecutor())
    assert outcome.skipped == 3 and outcome.total == len(next(iter(plans(setting).values())).runs)
    assert (tmp_path / SCORES_CSV).read_bytes() == (tiny / SCORES_CSV).read_bytes()


def test_bad_input_names_the_field(
    repro: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["transfer", "--from", str(tmp_path / "none"), "--out", str(tmp_path / "o")])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("chassistune: error: --from:"), err
    with pytest.raises(SystemExit) as exc:  # the reproduction holds fuzzy-immune-abs only
        main(["transfer", "--from", str(repro), "--out", str(tmp_path / "o")])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "derlsp-ao-abs" in err[0] and "--from" in err[0], err
    assert not (tmp_path / "o").exists()
    with pytest.raises(SystemExit) as exc:  # DERLSP-AO needs a population of 4
        main(
            [
                "transfer",
                "--from",
                str(repro),
                "--out",
                str(tmp_path / "o"),
                *TINY[:2],
                "--pop",
                "2",
            ]
        )
    assert exc.value.code == 2
    # the TIR file's warning of its absent coefficients may come first: the one error line
    err = [e for e in capsys.readouterr().err.splitlines() if "warning: " not in e]
    assert len(err) == 1 and err[0].startswith("chassistune: error: --pop:"), err


@pytest.mark.slow
def test_the_whole_study_at_a_tiny_budget(tmp_path: Path) -> None:
    studies = tuple(dict.fromkeys(s.study for s in SOURCES))
    repro = _reproduction(tmp_path / "repro", studies)
    out = tmp_path / "transfer"
    _transfer(repro, out, "--seeds", "1", "--pop", "4", *TINY_EVALS)
    scores = pd.read_csv(out / SCORES_CSV)
    _distances_respect_their_bounds(scores)
    _not_available_are_the_refused(scores, Setting(SOURCES, CARS))
    vehicle = scores[(scores.plant == "abs-vehicle")]
    split = vehicle[vehicle.road == "split-mu"].yaw_rate_peak_1s_rad_s
    assert len(split) > 0 and np.isfinite(split).all()


@pytest.mark.slow
def test_the_process_executor_gives_the_same_table(repro: Path, tiny: Path, tmp_path: Path) -> None:
    _transfer(repro, tmp_path, *TINY, *TINY_EVALS, "--executor", "process", "--workers", "2")
    assert (tmp_path / SCORES_CSV).read_bytes() == (tiny / SCORES_CSV).read_bytes()
