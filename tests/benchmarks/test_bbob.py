"""`chassistune bbob`: runs recorded in the store, COCO's data folder written from it, read back
by cocopp, and the numbers equal to cocoex's own evaluation."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

from chassistune.cli.bbob import parse_instances
from chassistune.errors import InputError
from chassistune.studies.bbob import (
    BBOBPlan,
    get_problem,
    parse_problem_id,
)
from chassistune.studies.store import open_study
from chassistune.studies.worker import execute_run

ARGS = [
    "bbob",
    "--optimizer",
    "cma-es",
    "--optimizer",
    "random-search",
    "--dim",
    "2",
    "--dim",
    "3",
    "--function",
    "1",
    "--function",
    "15",
    "--budget",
    "40",
    "--pop",
    "6",
    "--instances",
    "1,2",
    "--no-postprocess",
]


@pytest.fixture(scope="module")
def tiny(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from chassistune.cli.main import main

    out = tmp_path_factory.mktemp("bbob") / "run"
    with pytest.raises(SystemExit) as exc:
        main([*ARGS, "--out", str(out)])
    assert exc.value.code == 0
    return out


def _records(out: Path) -> list:
    with open_study(out) as store:
        return list(store.records())


def test_every_run_is_in_the_store_with_its_exact_budget(tiny: Path) -> None:
    records = _records(tiny)
    assert len(records) == 2 * 2 * 2 * 2  # optimizers x functions x dims x instances
    for r in records:
        _, d, i = parse_problem_id(r.spec.scenario)
        assert r.completed and r.nfev == 40 * d and r.spec.seed == i
        assert r.history_nfev[0] == 1 and r.history_nfev[-1] <= r.nfev
        assert np.all(np.diff(r.history) < 0) and r.history[-1] == r.best_cost


def test_stored_costs_are_cocoex_evaluations_of_the_stored_points(tiny: Path) -> None:
    runs = [r for r in _records(tiny) if r.spec.scenario == "bbob_f015_i02_d03"]
    assert {r.spec.optimizer for r in runs} == {"cma-es", "random-search"}
    for r in runs:
        problem = get_problem(15, 3, 2)
        points = np.asarray(r.metrics["improvements"]["x"])
        assert points.shape == (len(r.history), 3)
        again = [float(problem(x)) for x in points]
        problem.free()
        assert again == r.history  # bit for bit


def _dat_rows(path: Path) -> list[tuple[float, list[tuple[int, float]]]]:
    """Per instance: Fopt and the (evaluation, measured fitness) rows of a COCO .dat file."""
    blocks: list[tuple[float, list[tuple[int, float]]]] = []
    for line in path.read_text().splitlines():
        if line.startswith("%"):
            blocks.append((float(line.split("Fopt (")[1].split(")")[0]), []))
        elif line.strip():
            cols = line.split()
            blocks[-1][1].append((int(cols[0]), float(cols[3])))
    return blocks


def test_coco_folder_holds_the_stored_improvements_and_cocopp_reads_it(tiny: Path) -> None:
    with warnings.catch_warnings(record=True):  # cocopp's import fetches its online archive list
        from cocopp.pproc import DataSetList

    runs = {(r.spec.optimizer, r.spec.scenario): r for r in _records(tiny)}
    for name in ("cma-es", "random-search"):
        folder = tiny / "coco" / name
        dat = folder / "data_f1" / "bbobexp_f1_DIM3.dat"
        for instance, (_fopt, rows) in zip((1, 2), _dat_rows(dat), strict=True):
            r = runs[(name, f"bbob_f001_i{instance:02d}_d03")]
            stored = dict(zip(r.history_nfev, r.history, strict=True))
            assert rows[-1][0] == r.nfev  # the last evaluation is logged
            for k, value in rows[:-1]:  # the target hits are improvements of the store
                assert value == pytest.approx(stored[k], rel=1e-9)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sets = DataSetList(str(folder))
        assert sorted((s.funcId, s.dim) for s in sets) == [(1, 2), (1, 3), (15, 2), (15, 3)]
        for s in sets:
            assert list(s.instancenumbers) == [1, 2]
            assert list(s.maxevals) == [40 * s.dim] * 2
            best = [
                runs[(name, f"bbob_f{s.funcId:03d}_i{i:02d}_d{s.dim:02d}")].best_cost
                for i in (1, 2)
            ]
            dat = folder / f"data_f{s.funcId}" / f"bbobexp_f{s.funcId}_DIM{s.dim}.dat"
            fopt = [block[0] for block in _dat_rows(dat)]
            assert s.finalfunvals == pytest.approx(np.subtract(best, fopt), rel=1e-6, abs=1e-12)


def test_rerun_skips_stored_runs_and_other_settings_are_refused(tiny: Path, cli) -> None:
    mtime = (tiny / "study.sqlite").stat().st_mtime_ns
    again = cli(*ARGS, "--out", str(tiny))
    assert again.code == 0 and "0 runs done now, 16 were stored already" in again.out
    other = cli(*[a if a != "40" else "50" for a in ARGS], "--out", str(tiny))
    assert other.code == 2 and other.err.count("\n") == 1 and "--out" in other.err
    with sqlite3.connect(tiny / "study.sqlite") as conn:
        assert conn.execute("SELECT COUNT(*) FROM runs").fetchone()[0] == 16
    assert (tiny / "study.sqlite").stat().st_mtime_ns >= mtime


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["--optimizer", "nope"], "--optimizer"),
        (["--optimizer", "de", "--instances", "3-1"], "--instances"),
        (["--optimizer", "de", "--instances", "a"], "--instances"),
        (["--optimizer", "de", "--dim", "7"], "--dim"),
        (["--optimizer", "de", "--function", "25"], "--function"),
        (["--optimizer", "de", "--pop", "2"], "--pop"),
        (["--optimizer", "de", "--budget", "1", "--dim", "2"], "--budget"),
    ],
)
def test_bad_input_is_one_line_exit_2_and_writes_nothing(
    args: list[str], field: str, cli, tmp_path: Path
) -> None:
    out = tmp_path / "never"
    res = cli("bbob", *args, "--out", str(out))
    assert res.code == 2 and res.err.count("\n") == 1 and field in res.err, res.err
    assert "Traceback" not in res.err and not out.exists()


def test_parse_instances() -> None:
    assert parse_instances("1-3,71") == (1, 2, 3, 71)
    with pytest.raises(InputError, match="twice"):
        parse_instances("1,1")


@pytest.mark.slow
def test_cocopp_postprocessing_writes_its_ecdf_pages(tiny: Path, cli) -> None:
    res = cli(*[a for a in ARGS if a != "--no-postprocess"], "--out", str(tiny))
    assert res.code == 0, res.err
    index = tiny / "ppdata" / "index.html"
    assert index.is_file()
    assert list((tiny / "ppdata").rglob("pprldmany*"))  # the ECDF figures


@pytest.mark.slow
def test_offline_postprocessing_says_nothing_of_cocopps_online_archive(tiny: Path) -> None:
    """Importing cocopp fetches the list of its online archive of reference results, and warns
    where that fails: offline (an unreachable proxy here) the command prints no such line, since
    no reference result is compared. A fresh process: an imported cocopp does not fetch again."""
    env = {**os.environ, "https_proxy": "http://127.0.0.1:9", "http_proxy": "http://127.0.0.1:9"}
    code = (
        "import sys; from pathlib import Path; from chassistune.plots.coco_ecdf import "
        "postprocess; coco = Path(sys.argv[1]) / 'coco'; "
        "postprocess(sorted(coco.iterdir()), Path(sys.argv[2]))"
    )
    pp = tiny.parent / "pp-offline"
    done = subprocess.run(
        [sys.executable, "-c", code, str(tiny), str(pp)], env=env, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    assert (pp / "index.html").is_file()
    assert "failed to connect" not in done.stderr and "Warning" not in done.stderr


@pytest.mark.parametrize("executor", ["process", "dask"])
def test_every_executor_stores_the_serial_traces(executor: str, tiny: Path, cli) -> None:
    """The same plan on two worker processes (a process pool, a Dask LocalCluster) stores, run for
    run, the serial run's trace, points and final cost (the tiny fixture ran serially)."""
    if executor == "dask":
        pytest.importorskip("distributed")
    out = tiny.parent / executor
    res = cli(*ARGS, "--executor", executor, "--workers", "2", "--out", str(out))
    assert res.code == 0, res.err
    serial = {r.spec.key: r for r in _records(tiny)}
    process = {r.spec.key: r for r in _records(out)}
    assert sorted(process) == sorted(serial) and len(serial) == 16
    for key, run in serial.items():
        other = process[key]
        assert other.spec == run.spec
        assert other.history == run.history and other.history_nfev == run.history_nfev
        assert other.metrics == run.metrics and other.best_cost == run.best_cost


@pytest.mark.parametrize("executor", ["serial", "process"])
def test_killed_run_resumes_to_the_uninterrupted_numbers(
    executor: str, tmp_path: Path, cli
) -> None:
    """SIGKILL the command once a run is stored, rerun it: every run once, each with the numbers
    a run of its spec gives on its own (the process executor's workers end with their driver)."""
    out = tmp_path / "killed"
    args = [
        "bbob",
        "--optimizer",
        "cma-es",
        "--dim",
        "2",
        "--function",
        "3",
        "--budget",
        "1500",
        "--pop",
        "6",
        "--instances",
        "1-4",
        "--no-postprocess",
        "--executor",
        executor,
        "--out",
        str(out),
    ]
    code = "import sys; from chassistune.cli import main; main(sys.argv[1:])"
    proc = subprocess.Popen([sys.executable, "-c", code, *args], env=os.environ.copy())
    store = out / "study.sqlite"
    deadline = time.monotonic() + 120
    stored = 0
    while time.monotonic() < deadline and proc.poll() is None:
        if store.exists():
            with sqlite3.connect(f"{store.as_uri()}?mode=ro", uri=True, timeout=0.05) as conn:
                try:
                    stored = conn.execute("SELECT COUNT(*) FROM runs").fetchone()[0]
                except sqlite3.Error:
                    stored = 0
            if stored:
                break
        time.sleep(0.02)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert 1 <= stored < 4, stored
    res = cli(*args)
    assert res.code == 0 and "were stored already" in res.out, res.err
    records = {r.spec.key: r for r in _records(out)}
    plan = BBOBPlan("bbob", ("cma-es",), (3,), (2,), (1, 2, 3, 4), 1500, 6, 0)
    assert sorted(records) == sorted(s.key for s in plan.runs())
    for spec in plan.runs():
        alone = execute_run(spec)
        assert records[spec.key].history == alone.history
        assert records[spec.key].history_nfev == alone.history_nfev
