"""Running studies: the store, resume, failures, and identical numbers on every executor."""

from __future__ import annotations

import sqlite3
import subprocess
import sys

import pandas as pd
import pytest
import raising_plant
from studies_helpers import RAISING, tiny_config, write_plan

from chassistune.errors import InputError
from chassistune.reports.tables import runs_table
from chassistune.scenarios import registry
from chassistune.studies.executors import ProcessExecutor, SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.store import Store, open_study

VARYING = ["wall_time_s", "versions"]


@pytest.fixture
def raising():
    raising_plant.register()
    yield
    registry.unregister(raising_plant.NAME)


def _table(folder):
    with open_study(folder) as store:
        return runs_table(list(store.records())).drop(columns=VARYING)


def test_serial_study_records_every_run_once_and_a_rerun_skips_them(tmp_path):
    _, plan = write_plan(tmp_path, tiny_config(seeds=2))
    out = tmp_path / "out"
    calls = []
    first = run_study(plan, out, SerialExecutor(), progress=lambda *a: calls.append(a))
    assert (first.total, first.skipped, first.completed, first.failed) == (4, 0, 4, 0)
    assert calls[0] == (0, 0, 4) and calls[-1] == (4, 0, 4)
    with open_study(out) as store:
        records = list(store.records())
    assert sorted(r.spec.key for r in records) == sorted(s.key for s in plan.runs)
    r = records[0]
    assert r.status == "completed" and r.error is None
    assert r.nfev == r.history_nfev[-1] and len(r.history) == r.nit == 3
    assert set(r.best_gains) == {"kp", "ki", "kd"}
    assert set(r.metrics) == {"iso-b"} and "body_acc_rms" in r.metrics["iso-b"]
    assert r.test_costs == {"iso-b": r.best_cost}
    assert {"chassistune", "numpy", "numba"} <= set(r.versions)
    again = run_study(plan, out, SerialExecutor())
    assert (again.skipped, again.completed, again.failed) == (4, 0, 0)
    # adding seeds runs only the new ones; the old runs are untouched
    _, more = write_plan(tmp_path, tiny_config(seeds=3), "more.toml")
    grown = run_study(more, out, SerialExecutor())
    assert (grown.skipped, grown.completed) == (4, 2)
    table = _table(out)
    assert len(table) == 6
    fresh = tmp_path / "fresh"
    run_study(more, fresh, SerialExecutor())
    assert table.equals(_table(fresh))


def test_store_is_wal_and_has_one_row_per_run(tmp_path):
    _, plan = write_plan(tmp_path, tiny_config(seeds=1))
    run_study(plan, tmp_path / "out", SerialExecutor())
    conn = sqlite3.connect(tmp_path / "out" / "study.sqlite")
    assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    keys = [k for (k,) in conn.execute("SELECT key FROM runs")]
    assert len(keys) == len(set(keys)) == 2
    conn.close()


def test_a_raising_objective_is_recorded_failed_and_the_study_goes_on(tmp_path, raising):
    _, plan = write_plan(tmp_path, tiny_config(seeds=2, extra=RAISING))
    out = tmp_path / "out"
    outcome = run_study(plan, out, SerialExecutor())
    assert (outcome.completed, outcome.failed) == (4, 4)
    with open_study(out) as store:
        records = list(store.records())
    failed = [r for r in records if r.status == "failed"]
    assert {r.spec.scenario for r in failed} == {"boom/iso-b"}
    assert all(
        raising_plant.MESSAGE in (r.error or "") and "RuntimeError" in (r.error or "")
        for r in failed
    )
    assert all(r.best_cost is None and r.best_gains == {} for r in failed)
    # failed runs are finished: skipped on a rerun unless asked to retry them
    assert run_study(plan, out, SerialExecutor()).skipped == 8
    retried = run_study(plan, out, SerialExecutor(), retry_failed=True)
    assert (retried.skipped, retried.failed) == (4, 4)


def test_a_folder_made_from_another_config_is_refused(tmp_path, cli):
    config, plan = write_plan(tmp_path, tiny_config(seeds=1))
    out = tmp_path / "out"
    run_study(plan, out, SerialExecutor())
    changed = config.read_text().replace("iterations = 3", "iterations = 4")
    config.write_text(changed)
    before = _table(out)
    r = cli("study", "run", str(config), "--out", str(out))
    assert r.code == 2 and "different config" in r.err and len(r.err.strip().splitlines()) == 1
    config.write_text(changed.replace('name = "tiny"', 'name = "other"'))
    r = cli("study", "run", str(config), "--out", str(out))
    assert r.code == 2 and "holds the study 'tiny'" in r.err
    assert _table(out).equals(before)


def test_report_and_export_refuse_a_folder_without_a_study(cli, tmp_path):
    for args in (
        ["report", str(tmp_path)],
        ["export", str(tmp_path / "none"), "--format", "csv", "--output", str(tmp_path / "x.csv")],
    ):
        r = cli("study", *args)
        assert r.code == 2 and r.err.startswith("chassistune: error: DIR")
    with pytest.raises(InputError):
        Store.open(tmp_path)
    assert not (tmp_path / "study.sqlite").exists()


def test_serial_process_and_dask_give_identical_tables(tmp_path, raising):
    """One plan on the three executors, with a raising scenario recorded failed in each."""
    _, plan = write_plan(tmp_path, tiny_config(seeds=2, roads='["iso-b", "iso-c"]', extra=RAISING))
    run_study(plan, tmp_path / "serial", SerialExecutor())
    with ProcessExecutor(2, initializer=raising_plant.register) as ex:
        run_study(plan, tmp_path / "process", ex)
    serial = _table(tmp_path / "serial")
    assert (serial["status"] == "failed").sum() == 4 and len(serial) == 12
    assert serial.equals(_table(tmp_path / "process"))
    pytest.importorskip("distributed")
    from chassistune.studies.executors import DaskExecutor

    with DaskExecutor(workers=2, processes=False) as ex:
        run_study(plan, tmp_path / "dask", ex)
    assert serial.equals(_table(tmp_path / "dask"))


def test_the_cli_runs_a_study_with_the_process_executor(cli, tmp_path):
    config, _ = write_plan(tmp_path, tiny_config(seeds=1))
    out = tmp_path / "out"
    r = cli(
        "study", "run", str(config), "--out", str(out), "--executor", "process", "--workers", "2"
    )
    assert r.code == 0, r.err
    assert "2 completed and 0 failed" in r.out
    assert len(_table(out)) == 2


def test_python_m_chassistune_cli_runs_a_study_with_the_process_executor(tmp_path):
    """The module entry point re-imported by spawned workers does not start the command again."""
    config, _ = write_plan(tmp_path, tiny_config(seeds=1))
    out = tmp_path / "out"
    command = ["study", "run", str(config), "--out", str(out), "--executor", "process"]
    r = subprocess.run(
        [sys.executable, "-m", "chassistune.cli", *command, "--workers", "1"],
        capture_output=True,
        text=True,
        timeout=1200,
    )
    assert r.returncode == 0, r.stderr
    assert len(_table(out)) == 2


def test_a_run_that_kills_its_worker_process_is_found_and_recorded_failed(tmp_path, raising):
    dies = RAISING.replace('"raises"', '"dies"')
    _, plan = write_plan(tmp_path, tiny_config(seeds=2, extra=dies))
    with ProcessExecutor(2, initializer=raising_plant.register) as ex:
        outcome = run_study(plan, tmp_path / "out", ex)
    assert (outcome.completed, outcome.failed) == (4, 4)
    table = _table(tmp_path / "out")
    failed = table[table["status"] == "failed"]
    assert set(failed["scenario"]) == {"boom/iso-b"}
    assert failed["error"].str.contains("worker process died").all()
    serial = tmp_path / "serial"
    run_study(write_plan(tmp_path, tiny_config(seeds=2), "ok.toml")[1], serial, SerialExecutor())
    alone = _table(serial)
    ok = table[table["status"] == "completed"].reset_index(drop=True)[alone.columns]
    pd.testing.assert_frame_equal(
        ok.drop(columns=["error"]), alone.drop(columns=["error"]), check_dtype=False
    )  # failed rows made bool columns object


def test_one_process_executor_serves_studies_one_after_another_with_the_same_workers(tmp_path):
    """Workers start (import, load kernels) once per executor, not once per study; a call left
    before its end gets the next call a new pool. The numbers are the serial ones throughout."""
    _, plan = write_plan(tmp_path, tiny_config(seeds=2))
    run_study(plan, tmp_path / "serial", SerialExecutor())
    with ProcessExecutor(2) as ex:
        run_study(plan, tmp_path / "first", ex)
        workers = set(ex._pool._processes)
        run_study(plan, tmp_path / "second", ex)
        assert workers and workers <= set(ex._pool._processes)
        left = ex.results(plan.runs)
        next(left)
        left.close()
        run_study(plan, tmp_path / "third", ex)
        assert workers.isdisjoint(ex._pool._processes)
    serial = _table(tmp_path / "serial")
    for name in ("first", "second", "third"):
        assert serial.equals(_table(tmp_path / name))
