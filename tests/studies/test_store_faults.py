"""Store faults: a lock held by another process, a full disk, damaged contents, a read-only
store, a store deleted mid-run, a study whose every run failed, and which runs make the study."""

from __future__ import annotations

import shutil
import sqlite3
import subprocess
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path

import pytest
from studies_helpers import tiny_config, write_plan

import chassistune.studies.store as store_module
from chassistune.errors import InputError
from chassistune.reports.tables import load_study
from chassistune.studies.executors import Executor, SerialExecutor
from chassistune.studies.records import RunResult
from chassistune.studies.runner import pending_runs, run_study
from chassistune.studies.spec import RunSpec, StudyPlan
from chassistune.studies.store import open_study

HOLD = """
import sqlite3, sys, time
conn = sqlite3.connect(sys.argv[1], isolation_level=None)
conn.execute("BEGIN IMMEDIATE")
print("held", flush=True)
time.sleep(float(sys.argv[2]))
conn.execute("ROLLBACK")
"""


def _hold_lock(store: Path, seconds: float) -> subprocess.Popen[str]:
    """Another process holding the store's write lock for `seconds`."""
    proc = subprocess.Popen(
        [sys.executable, "-c", HOLD, str(store), str(seconds)], stdout=subprocess.PIPE, text=True
    )
    assert proc.stdout is not None and proc.stdout.readline() == "held\n"
    return proc


class _Between(Executor):
    """Serial runs; `act` is called once, after the first run finished and before the driver
    records it (a fault arriving in the middle of a study)."""

    def __init__(self, act) -> None:
        self._act = act

    def results(self, specs: Sequence[RunSpec]) -> Iterator[RunResult]:
        for i, result in enumerate(SerialExecutor().results(specs)):
            if i == 0:
                self._act()
            yield result


def _rows(folder: Path) -> int:
    conn = sqlite3.connect(folder / "study.sqlite")
    try:
        return conn.execute("SELECT count(*) FROM runs").fetchone()[0]
    finally:
        conn.close()


@pytest.fixture(scope="module")
def done(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished tiny study (2 runs) to copy: seeds 1, optimizers pso and de."""
    folder = tmp_path_factory.mktemp("done")
    _, plan = write_plan(folder, tiny_config(seeds=1))
    run_study(plan, folder / "st", SerialExecutor())
    return folder / "st"


def _copy(done: Path, tmp_path: Path) -> tuple[Path, Path, StudyPlan]:
    """A copy of the finished study, and the config and plan of its two-seed continuation."""
    out = tmp_path / "st"
    shutil.copytree(done, out)
    config, plan = write_plan(tmp_path, tiny_config(seeds=2), "more.toml")
    return out, config, plan


# -- a lock held by another process ----------------------------------------------------------------


def test_a_lock_held_for_a_while_is_waited_for_and_its_holder_named(done, tmp_path, monkeypatch):
    monkeypatch.setattr(store_module, "LOCK_WAIT_S", 60.0, raising=False)
    out, _, plan = _copy(done, tmp_path)
    holders: list[subprocess.Popen[str]] = []
    said: list[str] = []
    ex = _Between(lambda: holders.append(_hold_lock(out / "study.sqlite", 3)))
    outcome = run_study(plan, out, ex, notice=said.append)
    holders[0].wait()
    assert outcome.completed == 2 and _rows(out) == 4
    assert len(said) == 1 and f"{holders[0].pid} (" in said[0] and "up to 60 s" in said[0]
    assert "\n" not in said[0]  # the holder's command line (HOLD has several) on one line


def test_a_lock_held_past_the_wait_keeps_the_finished_run(cli, done, tmp_path, monkeypatch):
    monkeypatch.setattr(store_module, "LOCK_WAIT_S", 2.0, raising=False)
    out, _, plan = _copy(done, tmp_path)
    holders: list[subprocess.Popen[str]] = []
    ex = _Between(lambda: holders.append(_hold_lock(out / "study.sqlite", 120)))
    try:
        with pytest.raises(InputError) as exc:
            run_study(plan, out, ex)
    finally:
        holders[0].kill()
        holders[0].wait()
    assert exc.value.field == "out"
    assert f"processes with it open: {holders[0].pid} (" in exc.value.problem
    assert "kept in" in exc.value.problem and _rows(out) == 2
    from chassistune.studies import unrecorded

    (kept,) = unrecorded.kept(out)
    status = cli("study", "status", str(out))
    assert f"  1 finished run waits in {out / 'unrecorded'} (the store was locked)" in status.out
    outcome = run_study(plan, out, SerialExecutor())  # the lock is free again
    assert (outcome.skipped, outcome.completed) == (3, 1)  # the kept run is stored, not redone
    assert _rows(out) == 4 and unrecorded.kept(out) == []
    with open_study(out) as store:
        stored = {r.spec.key: r.best_gains for r in store.records()}
    assert stored[kept[1].key] == kept[2].best_gains


# -- a full disk -----------------------------------------------------------------------------------


@pytest.fixture
def small_fs(tmp_path: Path) -> Iterator[Path]:
    """A tmpfs of 640 KiB (root and a kernel that lets this process mount, else skipped)."""
    mount = tmp_path / "small"
    mount.mkdir()
    made = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=640k", "tmpfs", str(mount)], capture_output=True
    )
    if made.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {made.stderr.decode().strip()}")
    try:
        yield mount
    finally:
        subprocess.run(["umount", "-l", str(mount)], check=True)


def _fill(folder: Path) -> Path:
    """Fill the file system of `folder` to the last byte."""
    filler = folder / "filler"
    with open(filler, "wb", buffering=0) as fh:
        try:
            while True:
                fh.write(b"\0" * 4096)
        except OSError:
            pass
    return filler


def test_a_disk_that_fills_mid_study_stops_it_in_one_line_keeping_what_is_stored(
    cli, done, small_fs
):
    out, config, plan = _copy(done, small_fs)
    with pytest.raises(InputError) as exc:
        run_study(plan, out, _Between(lambda: _fill(small_fs)))
    assert exc.value.field == "out" and "the disk is full" in exc.value.problem
    assert repr(str(out / "study.sqlite")) in exc.value.problem
    r = cli("study", "run", str(config), "--out", str(out))  # still full: refused at the start
    assert r.code == 2 and len(r.err.splitlines()) == 1, r.err
    assert r.err.startswith(f"chassistune: error: --out: cannot use {str(out / 'study.sqlite')!r}")
    assert "the disk is full" in r.err
    (small_fs / "filler").unlink()
    with open_study(out) as store:
        scan = store.scan(integrity=True)
    assert len(scan.records) == 2 and scan.damaged == []  # the stored runs read back whole
    assert sorted(p.name for p in out.iterdir()) == [".study.lock", "study.sqlite"]


def test_a_full_disk_before_a_new_study_is_named_by_the_file_it_stops_at(cli, small_fs, tmp_path):
    config, _ = write_plan(tmp_path, tiny_config(seeds=1))
    _fill(small_fs)
    r = cli("study", "run", str(config), "--out", str(small_fs / "new"))
    assert r.code == 2, r.err
    assert r.err == (
        f"chassistune: error: --out: cannot write {str(small_fs / 'new' / '.study.lock')!r}: "
        "No space left on device\n"
    )
    assert not (small_fs / "new" / "study.sqlite").exists()


def test_a_store_that_cannot_grow_fails_the_run_naming_it(done, tmp_path, monkeypatch):
    """Fault injection where no file system can be mounted: SQLite's page limit is its full
    disk (SQLITE_FULL)."""
    out, _, plan = _copy(done, tmp_path)
    real = store_module._connect

    def capped(path: Path, read_only: bool) -> sqlite3.Connection:
        conn = real(path, read_only)
        if not read_only:
            pages = conn.execute("PRAGMA page_count").fetchone()[0]
            conn.execute(f"PRAGMA max_page_count={pages}")
        return conn

    monkeypatch.setattr(store_module, "_connect", capped)
    with pytest.raises(InputError) as exc:
        run_study(plan, out, SerialExecutor())
    assert exc.value.field == "out" and "the disk is full" in exc.value.problem
    assert "the runs stored before are kept" in exc.value.problem
    assert repr(str(out / "study.sqlite")) in exc.value.problem
    monkeypatch.undo()
    assert len(pending_runs(plan, out)) == 2  # the two stored runs intact; the rest to do


# -- damaged contents ------------------------------------------------------------------------------

DAMAGE = {
    "json": "UPDATE runs SET metrics = '{\"iso-b\": {' WHERE optimizer = 'pso'",
    "utf8": "UPDATE runs SET best_gains = CAST(X'7B226B70223A20FF7D' AS TEXT) "
    "WHERE optimizer = 'pso'",
}


@pytest.mark.parametrize("kind", sorted(DAMAGE))
def test_a_damaged_run_is_named_by_every_command_before_any_work(cli, done, tmp_path, kind):
    out, config, _ = _copy(done, tmp_path)
    conn = sqlite3.connect(out / "study.sqlite")
    with conn:
        conn.execute(DAMAGE[kind])
        (key,) = conn.execute("SELECT key FROM runs WHERE optimizer = 'pso'").fetchone()
    conn.close()
    column = "metrics" if kind == "json" else "best_gains"
    r = cli("study", "status", str(out))
    assert r.code == 0, r.err
    assert f"damaged: run {key!r} does not read back ({column} is not" in r.out
    assert "2 runs, 1 completed, 0 failed, 1 missing" in r.out and "finishes it" not in r.out
    for args in (
        ("study", "export", str(out), "--output", str(tmp_path / "runs.csv")),
        ("study", "report", str(out)),
        ("study", "run", str(config), "--out", str(out)),
        ("export", f"{out}#{key}", "--format", "c", "--out", str(tmp_path / "c")),
    ):
        r = cli(*args)
        assert r.code == 2, (args, r.err)
        assert len(r.err.strip().splitlines()) == 1 and f"damaged run {key!r}" in r.err, args
    assert _rows(out) == 2  # `study run` did no run
    assert not (tmp_path / "runs.csv").exists() and not (out / "report.html").exists()


def test_reproduce_refuses_a_damaged_study_store_before_any_work(cli, done, tmp_path):
    from chassistune.papers.reproduce import plan_reproduction

    out = tmp_path / "rep"
    folder = plan_reproduction("derlsp-ao-abs", quick=True)[0].folder(out)
    shutil.copytree(done, folder)
    conn = sqlite3.connect(folder / "study.sqlite")
    with conn:
        conn.execute(DAMAGE["json"])
    conn.close()
    r = cli("reproduce", "derlsp-ao-abs", "--quick", "--out", str(out))
    assert r.code == 2, r.err
    assert len(r.err.splitlines()) == 1 and "holds a damaged run 'qc/iso-b|pso|0'" in r.err
    assert sorted(p.name for p in out.rglob("*")) == sorted(
        ["studies", folder.name, ".study.lock", "study.sqlite"]
    )


def _drop_runs(store: Path) -> None:
    conn = sqlite3.connect(store)
    conn.execute("DROP TABLE runs")
    conn.close()


def _smash_runs_page(store: Path) -> None:
    conn = sqlite3.connect(store)
    (root,) = conn.execute("SELECT rootpage FROM sqlite_master WHERE name = 'runs'").fetchone()
    size = conn.execute("PRAGMA page_size").fetchone()[0]
    conn.close()
    data = bytearray(store.read_bytes())
    data[(root - 1) * size : (root - 1) * size + 8] = b"\xff" * 8  # its b-tree page header
    store.write_bytes(bytes(data))


@pytest.mark.parametrize(
    ("damage", "said"),
    [
        (_drop_runs, "is a damaged study store (no runs table)"),
        (_smash_runs_page, "study.sqlite' is damaged ("),
    ],
    ids=["runs-table-dropped", "runs-page-smashed"],
)
def test_a_store_damaged_below_its_rows_is_refused_in_one_line(cli, done, tmp_path, damage, said):
    out, config, _ = _copy(done, tmp_path)
    damage(out / "study.sqlite")
    for args in (
        ("study", "status", str(out)),
        ("study", "export", str(out), "--output", "-"),
        ("study", "report", str(out)),
        ("study", "run", str(config), "--out", str(out)),
    ):
        r = cli(*args)
        assert r.code == 2, (args, r.err)
        assert len(r.err.splitlines()) == 1 and said in r.err, args


# -- a read-only store -----------------------------------------------------------------------------


def test_a_read_only_store_is_refused_before_any_work(cli, done, tmp_path):
    out, config, _ = _copy(done, tmp_path)
    store = out / "study.sqlite"
    if subprocess.run(["chattr", "+i", str(store)], capture_output=True).returncode != 0:
        pytest.skip("chattr +i is not available here")
    try:
        r = cli("study", "run", str(config), "--out", str(out))
    finally:
        subprocess.run(["chattr", "-i", str(store)], check=True)
    assert r.code == 2, r.err
    assert r.err == (
        f"chassistune: error: --out: {str(store)!r} is read-only: a study run adds its runs to "
        "it; make it writable or use a new --out folder\n"
    )
    assert _rows(out) == 2


# -- the store deleted or replaced mid-run ---------------------------------------------------------


@pytest.mark.parametrize("how", ["deleted", "replaced by another file"])
def test_a_store_deleted_or_replaced_mid_run_stops_the_study_saying_what_is_lost(
    done, tmp_path, how
):
    out, _, plan = _copy(done, tmp_path)
    other = tmp_path / "other.sqlite"
    sqlite3.connect(other).close()

    def fault() -> None:
        (out / "study.sqlite").unlink()
        if how != "deleted":
            other.rename(out / "study.sqlite")

    with pytest.raises(InputError) as exc:
        run_study(plan, out, _Between(fault))
    assert exc.value.problem == (
        f"{str(out / 'study.sqlite')!r} was {how} while the study ran: the 2 runs recorded in "
        "it are lost with it; run the same command to redo them"
    )


# -- which runs make the study ---------------------------------------------------------------------


def test_status_export_and_report_count_the_same_runs_after_a_rename(cli, done, tmp_path):
    out, _, _ = _copy(done, tmp_path)
    renamed, _ = write_plan(
        tmp_path, tiny_config(seeds=1).replace('name = "qc"', 'name = "qc2"'), "renamed.toml"
    )
    assert cli("study", "run", str(renamed), "--out", str(out)).code == 0
    assert _rows(out) == 4
    status = cli("study", "status", str(out))
    assert "2 runs, 2 completed, 0 failed, 0 missing" in status.out
    assert "2 stored runs of an earlier config" in status.out
    export = cli("study", "export", str(out), "--output", "-")
    assert len(export.out.strip().splitlines()) == 1 + 2
    with open_study(out) as store:
        data = load_study(store)  # what the report reads
    assert {r.spec.scenario for r in data.records} == {"qc2/iso-b"} and len(data.records) == 2
