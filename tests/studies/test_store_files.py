"""Reading a study (resume check, report, export) leaves no SQLite side files in its folder."""

from __future__ import annotations

import sqlite3

from studies_helpers import tiny_config, write_plan

from chassistune.reports.build import build_report
from chassistune.reports.tables import runs_table, write_table
from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import pending_runs, run_study
from chassistune.studies.store import Store, open_study

SIDE_FILES = ("study.sqlite-wal", "study.sqlite-shm", "study.sqlite-journal")


def _side_files(folder):
    return sorted(p.name for p in folder.iterdir() if p.name in SIDE_FILES)


def test_report_and_export_leave_only_the_store(tmp_path):
    _, plan = write_plan(tmp_path, tiny_config(seeds=1))
    out = tmp_path / "out"
    run_study(plan, out, SerialExecutor())
    assert _side_files(out) == []
    assert pending_runs(plan, out) == []
    with open_study(out) as store:
        write_table(runs_table(list(store.records())), str(tmp_path / "runs.csv"))
    build_report(out)
    assert _side_files(out) == []
    conn = sqlite3.connect(out / "study.sqlite")  # still a WAL store, untouched by the readers
    assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    conn.close()


def test_a_reader_cannot_write_and_a_reader_beside_the_writer_leaves_nothing(tmp_path):
    _, plan = write_plan(tmp_path, tiny_config(seeds=1))
    out = tmp_path / "out"
    run_study(plan, out, SerialExecutor())
    writer = Store.create(out)
    with open_study(out) as reader:
        assert len(list(reader.records())) == 2
        try:
            reader.set_meta({"x": "y"})
            raise AssertionError("a reader wrote to the store")
        except sqlite3.OperationalError as exc:
            assert "readonly" in str(exc) or "query_only" in str(exc) or "read" in str(exc)
    writer.close()
    assert _side_files(out) == []


def test_a_new_store_appears_with_its_meta(tmp_path, monkeypatch):
    """A reader never sees a store without the study's meta (it raced `study status` once)."""
    import chassistune.studies.store as store_module

    seen: list[dict[str, str]] = []
    real_connect = store_module._connect

    def connect_and_read(path, read_only):  # the first moment the store exists under its name
        reader = sqlite3.connect(path)
        seen.append(dict(reader.execute("SELECT key, value FROM meta").fetchall()))
        reader.close()
        return real_connect(path, read_only)

    monkeypatch.setattr(store_module, "_connect", connect_and_read)
    Store.create(tmp_path / "st", {"config": "{}", "study": "s"}).close()
    assert seen and seen[0]["config"] == "{}" and seen[0]["study"] == "s"
