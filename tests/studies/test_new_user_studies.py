"""What a new user hit in studies: unequal evaluation counts shown and warned about, the docs'
script under spawn, export formats, one driver per folder, Dask retries, dashboard and options."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
import raising_plant
from studies_helpers import RAISING, tiny_config, write_plan

from chassistune.errors import InputError
from chassistune.reports.tables import (
    budget_warnings,
    load_study,
    rank_sum_table,
    summary_table,
)
from chassistune.scenarios import registry
from chassistune.studies.executors import SerialExecutor, make_executor
from chassistune.studies.runner import run_study
from chassistune.studies.store import open_study

ABC_VS_PSO = tiny_config(seeds=2).replace('name = "de"', 'name = "abc"')


def test_unequal_evaluations_are_shown_and_warned(cli, tmp_path):
    """An `iterations` budget: ABC spends about twice PSO's evaluations."""
    config, _ = write_plan(tmp_path, ABC_VS_PSO)
    r = cli("study", "run", str(config), "--out", str(tmp_path / "st"))
    assert r.code == 0, r.err
    assert "warning: qc/iso-b: the optimizers spent unequal evaluations" in r.err
    with open_study(tmp_path / "st") as store:
        data = load_study(store)
    (line,) = budget_warnings(data)
    assert "pso" in line and "abc" in line
    summary = summary_table(data)
    nfev = summary[summary.quantity == "nfev"].set_index("optimizer")["median"]
    assert nfev["abc"] > 1.05 * nfev["pso"]
    ranks = rank_sum_table(data, "pso")
    assert {"nfev_reference", "nfev"} <= set(ranks.columns)
    r = cli("study", "report", str(tmp_path / "st"))
    assert r.code == 0 and "unequal evaluations" in r.err
    html = (tmp_path / "st" / "report.html").read_text(encoding="utf-8")
    assert "evaluations (nfev)" in html and "unequal evaluations" in html


def test_equal_budgets_give_no_warning(tmp_path):
    _, plan = write_plan(
        tmp_path, tiny_config(seeds=2).replace("iterations = 3", "evaluations = 24")
    )
    run_study(plan, tmp_path / "st", SerialExecutor())
    with open_study(tmp_path / "st") as store:
        assert budget_warnings(load_study(store)) == []


SCRIPT = """
import sys
from chassistune.studies.spec import load_plan
from chassistune.studies.executors import make_executor
from chassistune.studies.runner import run_study
{body}
"""
BODY = """
plan = load_plan(sys.argv[1])
with make_executor("process", workers=2) as ex:
    outcome = run_study(plan, sys.argv[2], ex)
print("completed", outcome.completed, "failed", outcome.failed)
"""


def test_the_docs_script_runs_under_spawn_and_an_unguarded_one_is_refused(tmp_path):
    """The guarded snippet completes; without the guard, one line before any worker."""
    config, _ = write_plan(tmp_path, tiny_config(seeds=1))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    guarded = tmp_path / "guarded.py"
    guarded.write_text(
        SCRIPT.format(body='if __name__ == "__main__":\n' + textwrap.indent(BODY, "    "))
    )
    done = subprocess.run(
        [sys.executable, str(guarded), str(config), str(tmp_path / "a")],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert "completed 2 failed 0" in done.stdout
    bare = tmp_path / "bare.py"
    bare.write_text(SCRIPT.format(body=BODY))
    done = subprocess.run(
        [sys.executable, str(bare), str(config), str(tmp_path / "b")],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert done.returncode != 0
    assert 'put the study code under `if __name__ == "__main__":`' in done.stderr
    assert "worker process died" not in done.stderr + done.stdout
    assert not (tmp_path / "b" / "study.sqlite").exists()


def test_the_docs_snippet_itself_is_guarded():
    docs = Path(__file__).resolve().parents[2] / "docs" / "studies.md"
    text = docs.read_text(encoding="utf-8")
    snippet = text.split("```python", 1)[1].split("```", 1)[0]
    assert 'if __name__ == "__main__":' in snippet
    assert all(
        line.startswith(("    ", "from ", "if ")) or not line.strip()
        for line in snippet.splitlines()
    ), snippet


@pytest.fixture
def study_dir(tmp_path: Path) -> Path:
    _, plan = write_plan(tmp_path, tiny_config(seeds=1))
    run_study(plan, tmp_path / "st", SerialExecutor())
    return tmp_path / "st"


def test_export_takes_its_format_from_the_suffix(cli, study_dir, tmp_path):
    """No CSV in a .parquet name; `-` is stdout."""
    r = cli(
        "study",
        "export",
        str(study_dir),
        "--format",
        "csv",
        "--output",
        str(tmp_path / "x.parquet"),
    )
    assert r.code == 2 and "--format" in r.err and not (tmp_path / "x.parquet").exists()
    r = cli("study", "export", str(study_dir), "--output", str(tmp_path / "y.csv"))
    assert r.code == 0 and (tmp_path / "y.csv").read_text().startswith("scenario,")
    r = cli("study", "export", str(study_dir), "--output", "-")
    assert r.code == 0 and r.out.startswith("scenario,") and not Path("-").exists()
    assert len(r.out.strip().splitlines()) == 3  # header + 2 runs
    r = cli("study", "export", str(study_dir), "--output", str(tmp_path / "z.txt"))
    assert r.code == 2 and "cannot tell the format" in r.err


def test_study_status_counts_done_failed_and_missing(cli, tmp_path, monkeypatch):
    raising_plant.register()
    try:
        _, plan = write_plan(tmp_path, tiny_config(seeds=2, extra=RAISING))
        run_study(plan, tmp_path / "st", SerialExecutor())
        (tmp_path / "more.toml").write_text(tiny_config(seeds=3, extra=RAISING))
        r = cli("study", "status", str(tmp_path / "st"))
        assert r.code == 0, r.err
        assert "8 runs, 4 completed, 4 failed, 0 missing" in r.out
    finally:
        registry.unregister(raising_plant.NAME)
    r = cli("study", "status", str(tmp_path / "nothing"))
    assert r.code == 2 and r.err.startswith("chassistune: error: DIR")


LONG = tiny_config(seeds=40).replace("iterations = 3", "iterations = 60")


def _driver(config: Path, out: Path) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "chassistune.cli", "study", "run", str(config), "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def _wait_for_lock(out: Path, proc: subprocess.Popen[str]) -> None:
    from chassistune.studies.lock import holder

    for _ in range(600):
        if holder(out) == str(proc.pid):
            return
        time.sleep(0.05)
    pytest.fail("the first driver never took the lock")


def test_a_second_driver_is_refused_and_a_rerun_after_sigkill_proceeds(cli, tmp_path):
    """One driver per folder; the kernel frees the lock of a SIGKILLed driver."""
    config, _ = write_plan(tmp_path, LONG)
    out = tmp_path / "st"
    first = _driver(config, out)
    try:
        _wait_for_lock(out, first)
        r = cli("study", "run", str(config), "--out", str(out))
        assert r.code == 2 and r.err.count("\n") == 1
        assert f"in use by another study run (process {first.pid})" in r.err
        for _ in range(200):  # the first driver has the lock; its store may not be written yet
            r = cli("study", "status", str(out))
            if r.code == 0:
                break
            time.sleep(0.05)
        assert f"running now (process {first.pid})" in r.out
    finally:
        first.send_signal(signal.SIGKILL)
        first.wait()
    assert first.returncode == -signal.SIGKILL
    rerun = _driver(config, out)
    _wait_for_lock(out, rerun)  # it proceeds: the dead driver's lock is gone
    rerun.send_signal(signal.SIGINT)
    _, err = rerun.communicate(timeout=10)
    assert rerun.returncode == 130, err


def test_workers_with_the_serial_executor_are_refused():
    """`--workers` with `--executor serial` is refused rather than ignored."""
    with pytest.raises(InputError, match=r"^workers: the serial executor"):
        make_executor("serial", workers=3)


def test_dask_fails_fast_on_an_unreachable_scheduler():
    pytest.importorskip("distributed")
    from chassistune.studies.executors import DaskExecutor

    with pytest.raises(InputError, match="within 3 s") as exc:
        DaskExecutor("tcp://127.0.0.1:9")  # discard port: nothing listens
    assert exc.value.field == "scheduler"


def _register_plugin() -> object:
    """A Dask worker plugin: the test plant in every worker, restarted ones included."""
    from distributed import WorkerPlugin

    class Register(WorkerPlugin):  # type: ignore[misc]
        def setup(self, worker: object) -> None:
            raising_plant.register()

    return Register()


def _assert_no_dashboard(services: dict[str, int]) -> None:
    """Dask's HTTP server (health checks) may run, on a random port, but serves no dashboard."""
    import urllib.error
    import urllib.request

    port = services.get("dashboard")
    if port is None:
        return
    assert port != 8787
    with pytest.raises(urllib.error.HTTPError) as exc:
        urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=5)
    assert exc.value.code == 404


DIES = """
[[scenarios]]
name = "crash"
plant = "raising-quarter-car"
controller = "skyhook"
objective = "dies"
"""


@pytest.mark.slow
def test_a_run_that_kills_its_dask_worker_is_tried_twice_then_failed(tmp_path, monkeypatch):
    """Tried once by the scheduler (allowed-failures 0 on our LocalCluster; Dask's
    default 3 tried it four times) and once alone; the runs that shared its worker complete;
    no dashboard."""
    pytest.importorskip("distributed")
    from chassistune.studies.executors import ALLOWED_FAILURES, DaskExecutor

    deaths = tmp_path / "deaths"
    deaths.mkdir()
    monkeypatch.setenv("CHASSISTUNE_TEST_DEATHS", str(deaths))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(sys.path))
    raising_plant.register()
    try:
        text = tiny_config(seeds=1).replace('name = "de"', 'name = "pso"\nlabel = "pso2"')
        _, plan = write_plan(tmp_path, text + DIES)
        with DaskExecutor(workers=2) as ex:
            _assert_no_dashboard(ex._client.scheduler_info()["services"])
            ex._client.register_plugin(_register_plugin(), name="raising")
            outcome = run_study(plan, tmp_path / "st", ex)
    finally:
        registry.unregister(raising_plant.NAME)
    assert outcome.completed == 2 and outcome.failed == 2  # qc x 2 done; crash x 2 failed
    assert len(list(deaths.iterdir())) == 2 * (ALLOWED_FAILURES + 2)
    with open_study(tmp_path / "st") as store:
        errors = [r.error for r in store.records() if not r.completed]
    assert errors == ["the worker process died while running it"] * 2
