"""The study store: one SQLite file, DIR/study.sqlite, written only by the driver.

WAL journal; each finished run is one transaction (`record`), so a study killed at any moment
keeps every run it finished and loses only the ones in flight. A run is in the store only once it
finished: `completed` or `failed` (with its error text); unfinished runs leave no row. Arrays and
mappings are stored as JSON text (floats round-trip exactly); nothing is pickled.
"""

from __future__ import annotations

import json
import os
import sqlite3
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from chassistune._io import atomic_path, dumps
from chassistune.errors import InputError
from chassistune.studies.records import RunResult, RunStatus
from chassistune.studies.spec import RunSpec

STORE_NAME = "study.sqlite"
SCHEMA_VERSION = "1"

_STATUSES = ", ".join(f"'{s.value}'" for s in RunStatus)
_SCHEMA = f"""
CREATE TABLE IF NOT EXISTS meta (
    key TEXT PRIMARY KEY,
    value TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS runs (
    key TEXT PRIMARY KEY,
    scenario TEXT NOT NULL,
    optimizer TEXT NOT NULL,
    seed INTEGER NOT NULL,
    spec_hash TEXT NOT NULL,
    spec TEXT NOT NULL,
    status TEXT NOT NULL CHECK (status IN ({_STATUSES})),
    error TEXT,
    best_cost REAL,
    nfev INTEGER,
    nit INTEGER,
    wall_time_s REAL,
    best_gains TEXT,
    metrics TEXT,
    test_costs TEXT,
    history TEXT,
    history_nfev TEXT,
    robust TEXT,
    diagnostics TEXT,
    step_check TEXT,
    versions TEXT NOT NULL,
    finished_at TEXT NOT NULL
);
"""

_JSON_COLUMNS = (
    "best_gains",
    "metrics",
    "test_costs",
    "history",
    "history_nfev",
    "robust",
    "diagnostics",
    "step_check",
)


@dataclass(frozen=True)
class RunRecord:
    """A finished run as read back from the store."""

    spec: RunSpec
    status: RunStatus
    error: str | None
    best_cost: float | None
    nfev: int | None
    nit: int | None
    wall_time_s: float | None
    best_gains: dict[str, float]
    metrics: dict[str, dict[str, Any]]
    test_costs: dict[str, float]
    history: list[float]
    history_nfev: list[int]
    versions: dict[str, str]
    diagnostics: dict[str, Any]
    robust: dict[str, Any] | None = None
    """Robust runs (an `[uncertainty]` table): the training summary and the validation."""
    step_check: dict[str, Any] | None = None
    """The winner at a quarter of the step, by road (`scenarios.refine`; issue 11)."""

    @property
    def completed(self) -> bool:
        return self.status is RunStatus.COMPLETED


def _init_schema(conn: sqlite3.Connection) -> None:
    conn.executescript(_SCHEMA)
    for column in ("robust", "diagnostics", "step_check"):  # stores before issues 17, 14, 11
        if column not in _columns(conn):
            conn.execute(f"ALTER TABLE runs ADD COLUMN {column} TEXT")
    conn.execute("INSERT OR IGNORE INTO meta VALUES ('schema_version', ?)", (SCHEMA_VERSION,))


def store_path(study_dir: str | Path) -> Path:
    return Path(study_dir) / STORE_NAME


def _connect(path: Path, read_only: bool) -> sqlite3.Connection:
    """A connection to an existing store (`read_only`: no statement may write) or a new one.

    A reader opens the file read-write (never creating it) with `query_only` on: a `mode=ro`
    connection to a WAL database creates -wal and -shm files that it cannot remove, whereas the
    last connection that can write checkpoints and removes them on close. A file or folder that
    is not writable falls back to `mode=ro`.
    """
    if read_only:
        uri = path.resolve().as_uri()
        mode = "rw" if os.access(path, os.W_OK) and os.access(path.parent, os.W_OK) else "ro"
        conn = sqlite3.connect(f"{uri}?mode={mode}", uri=True)
        conn.execute("PRAGMA query_only=ON")
    else:
        conn = sqlite3.connect(path)
        conn.execute("PRAGMA journal_mode=WAL")
        conn.execute("PRAGMA synchronous=NORMAL")  # WAL + NORMAL: commits survive a killed process
    conn.execute("PRAGMA busy_timeout=10000")
    return conn


class Store:
    """Read and write access to DIR/study.sqlite."""

    def __init__(self, conn: sqlite3.Connection, path: Path) -> None:
        self._conn = conn
        self.path = path

    @classmethod
    def create(cls, study_dir: str | Path, meta: dict[str, str] | None = None) -> Store:
        """Open DIR/study.sqlite for writing, creating the folder and the schema if needed.

        `meta` is written in the same step: a new store is built aside with its schema and meta
        and renamed, so neither a kill nor a concurrent reader ever sees a store without them.
        """
        os.makedirs(study_dir, exist_ok=True)
        path = store_path(study_dir)
        items = list((meta or {}).items())
        if not path.exists():
            with atomic_path(path) as tmp:
                fresh = sqlite3.connect(tmp)
                with fresh:
                    _init_schema(fresh)
                    fresh.executemany("INSERT OR REPLACE INTO meta VALUES (?, ?)", items)
                fresh.close()
        conn = _connect(path, read_only=False)
        with conn:
            _init_schema(conn)
            conn.executemany("INSERT OR REPLACE INTO meta VALUES (?, ?)", items)
        return cls(conn, path)

    @classmethod
    def open(cls, study_dir: str | Path, field: str = "DIR") -> Store:
        """Open an existing study read-only (InputError naming `field` when there is none)."""
        path = store_path(study_dir)
        if not Path(study_dir).is_dir():
            raise InputError(field, f"no study folder {str(study_dir)!r}")
        if not path.is_file():
            raise InputError(
                field, f"{str(study_dir)!r} holds no {STORE_NAME} (not a study folder)"
            )
        try:
            conn = _connect(path, read_only=True)
            version = conn.execute("SELECT value FROM meta WHERE key = 'schema_version'").fetchone()
        except sqlite3.DatabaseError as exc:
            raise InputError(
                field, f"{str(path)!r} is not a readable study store ({exc})"
            ) from None
        if version is None or version[0] != SCHEMA_VERSION:
            conn.close()
            raise InputError(field, f"{str(path)!r} has an unknown store schema")
        return cls(conn, path)

    def close(self) -> None:
        self._conn.close()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- meta ------------------------------------------------------------------------------------

    def set_meta(self, values: dict[str, str]) -> None:
        with self._conn:
            self._conn.executemany("INSERT OR REPLACE INTO meta VALUES (?, ?)", values.items())

    def meta(self) -> dict[str, str]:
        return dict(self._conn.execute("SELECT key, value FROM meta").fetchall())

    # -- runs ------------------------------------------------------------------------------------

    def finished(self) -> dict[str, tuple[str, RunStatus]]:
        """key -> (spec_hash, status) of every finished run."""
        rows = self._conn.execute("SELECT key, spec_hash, status FROM runs").fetchall()
        return {k: (h, RunStatus(s)) for k, h, s in rows}

    def record(self, spec: RunSpec, result: RunResult) -> None:
        """Write one finished run (a worker's result) as one transaction."""
        if result.key != spec.key or result.spec_hash != spec.spec_hash:
            raise RuntimeError(f"result {result.key} does not belong to run {spec.key}")
        row: dict[str, Any] = {
            "key": spec.key,
            "scenario": spec.scenario,
            "optimizer": spec.optimizer,
            "seed": spec.seed,
            "spec_hash": spec.spec_hash,
            "spec": spec.model_dump_json(),  # field and gain order kept
            "status": result.status.value,
            "error": result.error,
            "best_cost": result.best_cost,
            "nfev": result.nfev,
            "nit": result.nit,
            "wall_time_s": result.wall_time_s,
            "versions": dumps(result.versions, sort_keys=True),
            "finished_at": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        }
        for col in _JSON_COLUMNS:
            value = getattr(result, col)
            row[col] = None if value is None else dumps(value)
        cols = ", ".join(row)
        marks = ", ".join(f":{c}" for c in row)
        with self._conn:
            self._conn.execute(f"INSERT OR REPLACE INTO runs ({cols}) VALUES ({marks})", row)

    def records(self) -> Iterator[RunRecord]:
        """Every finished run, ordered by scenario, optimizer and seed."""
        have = _columns(self._conn)
        robust = "robust" if "robust" in have else "NULL"
        diagnostics = "diagnostics" if "diagnostics" in have else "NULL"
        step_check = "step_check" if "step_check" in have else "NULL"
        cur = self._conn.execute(
            "SELECT spec, status, error, best_cost, nfev, nit, wall_time_s, best_gains, metrics, "
            f"test_costs, history, history_nfev, versions, {robust}, {diagnostics}, {step_check} "
            "FROM runs ORDER BY scenario, optimizer, seed"
        )
        for (
            spec,
            status,
            error,
            cost,
            nfev,
            nit,
            wall,
            gains,
            metrics,
            tests,
            hist,
            hist_n,
            vers,
            rob,
            diag,
            steps,
        ) in cur:
            yield RunRecord(
                spec=RunSpec.model_validate_json(spec),
                status=RunStatus(status),
                error=error,
                best_cost=cost,
                nfev=nfev,
                nit=nit,
                wall_time_s=wall,
                best_gains=_loads(gains, {}),
                metrics=_loads(metrics, {}),
                test_costs=_loads(tests, {}),
                history=_loads(hist, []),
                history_nfev=_loads(hist_n, []),
                versions=_loads(vers, {}),
                diagnostics=_loads(diag, {}),
                robust=_loads(rob, None),
                step_check=_loads(steps, None),
            )


def _columns(conn: sqlite3.Connection) -> set[str]:
    return {row[1] for row in conn.execute("PRAGMA table_info(runs)")}


def _loads(text: str | None, empty: Any) -> Any:
    return empty if text is None else json.loads(text)


@contextmanager
def open_study(study_dir: str | Path, field: str = "DIR") -> Iterator[Store]:
    """`Store.open` as a context manager."""
    store = Store.open(study_dir, field)
    try:
        yield store
    finally:
        store.close()
