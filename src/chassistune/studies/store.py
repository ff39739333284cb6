"""The study store: one SQLite file, DIR/study.sqlite, written only by the driver.

WAL journal; each finished run is one transaction (`record`), so a study killed at any moment
keeps every run it finished and loses only the ones in flight. A run is in the store only once it
finished: `completed` or `failed` (with its error text); unfinished runs leave no row. Arrays and
mappings are stored as JSON text (floats round-trip exactly); nothing is pickled.

The runs that belong to the study are those of the config the store holds (meta `config`): its
scenarios x optimizers x seeds. Rows of an earlier config (a scenario since renamed) stay in the
file but are not part of the study: `scan` and `records` leave them out, so status, export and
report count the same runs. A row that does not decode (text that is not UTF-8, a JSON column
that does not parse, a spec that does not validate) is damage, named by its run.
"""

from __future__ import annotations

import json
import os
import sqlite3
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from chassistune._io import atomic_path, dumps
from chassistune.errors import InputError
from chassistune.studies.records import RunResult, RunStatus
from chassistune.studies.spec import RunSpec
from chassistune.studies.store_faults import is_busy, lock_holders, primary_code, store_error

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

_REQUIRED_COLUMNS = frozenset(
    {"key", "scenario", "optimizer", "seed", "spec_hash", "spec", "status", "error", "best_cost"}
    | {"nfev", "nit", "wall_time_s", "best_gains", "metrics", "test_costs", "history"}
    | {"history_nfev", "versions", "finished_at"}
)
"""The columns of every store since schema version 1 (later ones are added by `_init_schema`)."""

_DAMAGE_CODES = frozenset({sqlite3.SQLITE_CORRUPT, sqlite3.SQLITE_NOTADB, sqlite3.SQLITE_ERROR})
"""Codes of a file that is not (or no longer) a study store; the others are the disk's."""

LOCK_WAIT_S = 120.0
"""How long a write waits for another process to release the store's lock before it stops."""
_LOCK_POLL_MS = 1000
"""SQLite's own wait per attempt (busy_timeout) while `LOCK_WAIT_S` runs."""

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
    """The winner at a quarter of the step, by road (`scenarios.refine`)."""

    @property
    def completed(self) -> bool:
        return self.status is RunStatus.COMPLETED


@dataclass(frozen=True)
class Damage:
    """A stored run that cannot be read back: its key (as far as it decodes) and why."""

    key: str
    problem: str


@dataclass(frozen=True)
class Scan:
    """The runs of a store that belong to its study, read back; the damaged ones; and how many
    rows belong to an earlier config."""

    records: list[RunRecord]
    damaged: list[Damage]
    others: int


class StoreBusy(InputError):
    """Another process held the store's lock for longer than `LOCK_WAIT_S`."""


def _init_schema(conn: sqlite3.Connection) -> None:
    conn.executescript(_SCHEMA)
    for column in ("robust", "diagnostics", "step_check"):  # added after schema 1
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
        conn.execute("PRAGMA busy_timeout=10000")
    else:
        conn = sqlite3.connect(path)
        conn.execute(f"PRAGMA busy_timeout={_LOCK_POLL_MS}")
        conn.execute("PRAGMA journal_mode=WAL")
        conn.execute("PRAGMA synchronous=NORMAL")  # WAL + NORMAL: commits survive a killed process
    return conn


Notice = Callable[[str], None]
"""Where a store says that it waits (one line each)."""


class Store:
    """Read and write access to DIR/study.sqlite."""

    def __init__(
        self, conn: sqlite3.Connection, path: Path, field: str, notice: Notice | None = None
    ) -> None:
        self._conn = conn
        self.path = path
        self._field = field
        self._notice = notice
        self._identity = _identity(path)

    @classmethod
    def create(
        cls, study_dir: str | Path, meta: dict[str, str] | None = None, notice: Notice | None = None
    ) -> Store:
        """Open DIR/study.sqlite for writing, creating the folder and the schema if needed.

        `meta` is written in the same step: a new store is built aside with its schema and meta
        and renamed, so neither a kill nor a concurrent reader ever sees a store without them.
        A lock held by another process is waited for (`LOCK_WAIT_S`, said on `notice`); SQLite's
        errors (a full disk, a read-only file) are `InputError`s naming the store.
        """
        os.makedirs(study_dir, exist_ok=True)
        path = store_path(study_dir)
        items = list((meta or {}).items())

        def init(conn: sqlite3.Connection) -> None:
            _init_schema(conn)
            conn.executemany("INSERT OR REPLACE INTO meta VALUES (?, ?)", items)

        try:
            if not path.exists():
                with atomic_path(path) as tmp:
                    fresh = sqlite3.connect(tmp)
                    try:
                        with fresh:
                            init(fresh)
                    finally:
                        fresh.close()
            conn = _connect(path, read_only=False)
        except sqlite3.Error as exc:
            raise store_error(path, exc, "out", "nothing was written") from None
        store = cls(conn, path, "out", notice)
        try:
            store._write(init, "nothing was written")
        except BaseException:
            store.close()
            raise
        return store

    @classmethod
    def open(cls, study_dir: str | Path, field: str = "DIR") -> Store:
        """Open an existing study read-only (InputError naming `field` when there is none, or
        when the file is not a study store of this schema)."""
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
            missing = _REQUIRED_COLUMNS - _columns(conn)
        except sqlite3.DatabaseError as exc:
            if primary_code(exc) in _DAMAGE_CODES:
                raise InputError(
                    field, f"{str(path)!r} is not a readable study store ({exc})"
                ) from None
            raise store_error(path, exc, field, "nothing was changed") from None
        if version is None or version[0] != SCHEMA_VERSION:
            conn.close()
            raise InputError(field, f"{str(path)!r} has an unknown store schema")
        if missing:
            conn.close()
            what = "no runs table" if missing == _REQUIRED_COLUMNS else "runs without"
            detail = "" if missing == _REQUIRED_COLUMNS else " " + ", ".join(sorted(missing))
            raise InputError(field, f"{str(path)!r} is a damaged study store ({what}{detail})")
        return cls(conn, path, field)

    def close(self) -> None:
        self._conn.close()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _write(self, write: Callable[[sqlite3.Connection], object], consequence: str) -> None:
        """Run `write` as one transaction; while another process holds the lock, retry for up to
        `LOCK_WAIT_S` (saying once whom it waits for), then raise StoreBusy."""
        deadline: float | None = None
        while True:
            try:
                with self._conn:
                    write(self._conn)
                return
            except sqlite3.Error as exc:
                if not is_busy(exc):
                    raise store_error(self.path, exc, self._field, consequence) from None
            holders = ", ".join(lock_holders(self.path)) or "unknown"
            if deadline is None:
                deadline = time.monotonic() + LOCK_WAIT_S
                if self._notice is not None:
                    self._notice(
                        f"{str(self.path)!r} is locked by another process (processes with it "
                        f"open: {holders}); waiting up to {LOCK_WAIT_S:.0f} s"
                    )
            elif time.monotonic() >= deadline:
                raise StoreBusy(
                    self._field,
                    f"{str(self.path)!r} stayed locked by another process for "
                    f"{LOCK_WAIT_S:.0f} s (processes with it open: {holders})",
                )

    def check_present(self) -> None:
        """InputError when DIR/study.sqlite is no longer the file this store wrote (deleted or
        replaced): what it held is gone with it."""
        now = _identity(self.path)
        if now == self._identity:
            return
        (held,) = self._conn.execute("SELECT count(*) FROM runs").fetchone()
        how = "deleted" if now is None else "replaced by another file"
        raise InputError(
            self._field,
            f"{str(self.path)!r} was {how} while the study ran: the {held} runs recorded in it "
            "are lost with it; run the same command to redo them",
        )

    # -- meta ------------------------------------------------------------------------------------

    def set_meta(self, values: dict[str, str]) -> None:
        with self._conn:
            self._conn.executemany("INSERT OR REPLACE INTO meta VALUES (?, ?)", values.items())

    def meta(self) -> dict[str, str]:
        try:
            return dict(self._conn.execute("SELECT key, value FROM meta").fetchall())
        except sqlite3.DatabaseError as exc:
            raise InputError(self._field, f"{str(self.path)!r} is damaged (meta: {exc})") from None

    # -- runs ------------------------------------------------------------------------------------

    def finished(self) -> dict[str, tuple[str, RunStatus]]:
        """key -> (spec_hash, status) of every finished run (of any config: the resume check)."""
        try:
            rows = self._conn.execute("SELECT key, spec_hash, status FROM runs").fetchall()
            return {k: (h, RunStatus(s)) for k, h, s in rows}
        except (sqlite3.DatabaseError, ValueError) as exc:
            raise InputError(self._field, f"{str(self.path)!r} is damaged (runs: {exc})") from None

    def record(self, spec: RunSpec, result: RunResult) -> None:
        """Write one finished run (a worker's result) as one transaction (InputError when the
        store was deleted or replaced meanwhile, or cannot take it; StoreBusy when its lock is
        held too long)."""
        if result.key != spec.key or result.spec_hash != spec.spec_hash:
            raise RuntimeError(f"result {result.key} does not belong to run {spec.key}")
        self.check_present()
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
        self._write(
            lambda conn: conn.execute(
                f"INSERT OR REPLACE INTO runs ({cols}) VALUES ({marks})", row
            ),
            f"run {spec.key!r} is not stored; the runs stored before are kept",
        )

    def scan(self, integrity: bool = False) -> Scan:
        """Read back the study's runs, ordered by scenario, optimizer and seed, setting aside
        the rows that do not decode; `integrity` first runs SQLite's quick_check (a damaged
        page is damage of the whole store: InputError)."""
        member = _membership(self.meta())
        records: list[RunRecord] = []
        damaged: list[Damage] = []
        others = 0
        self._conn.text_factory = bytes
        try:
            if integrity:
                problems = [r[0] for r in self._conn.execute("PRAGMA quick_check")]
                if problems != [b"ok"]:
                    text = problems[0].decode("utf-8", "replace")
                    raise InputError(self._field, f"{str(self.path)!r} is damaged ({text})")
            for row in self._conn.execute(_select(_columns(self._conn))):
                try:
                    record = _record(row)
                except _Undecodable as exc:
                    key = row[0].decode("utf-8", "replace") if isinstance(row[0], bytes) else row[0]
                    damaged.append(Damage(str(key), str(exc)))
                    continue
                if member(record.spec):
                    records.append(record)
                else:
                    others += 1
        except sqlite3.DatabaseError as exc:
            raise InputError(self._field, f"{str(self.path)!r} is damaged ({exc})") from None
        finally:
            self._conn.text_factory = str
        return Scan(records, damaged, others)

    def records(self) -> Iterator[RunRecord]:
        """The study's runs, ordered by scenario, optimizer and seed (InputError naming the
        first damaged run)."""
        scan = self.scan()
        if scan.damaged:
            raise damaged_error(self.path, scan.damaged, self._field)
        yield from scan.records


def damaged_error(path: Path, damaged: list[Damage], field: str) -> InputError:
    """One line naming the first damaged run of a store (and how many there are)."""
    first = damaged[0]
    more = f" and {len(damaged) - 1} more" if len(damaged) > 1 else ""
    return InputError(
        field,
        f"{str(path)!r} holds a damaged run {first.key!r} ({first.problem}){more}; "
        "`chassistune study status` lists them; rerun into a new --out folder",
    )


def _identity(path: Path) -> tuple[int, int] | None:
    try:
        st = os.stat(path)
    except FileNotFoundError:
        return None
    return st.st_dev, st.st_ino


def _columns(conn: sqlite3.Connection) -> set[str]:
    rows = conn.execute("PRAGMA table_info(runs)").fetchall()
    return {r[1].decode() if isinstance(r[1], bytes) else r[1] for r in rows}


_READ = (
    "key",
    "spec",
    "status",
    "error",
    "best_cost",
    "nfev",
    "nit",
    "wall_time_s",
    "versions",
)


def _select(have: set[str]) -> str:
    cols = [*_READ, *(c if c in have else "NULL" for c in _JSON_COLUMNS)]
    return f"SELECT {', '.join(cols)} FROM runs ORDER BY scenario, optimizer, seed"


class _Undecodable(ValueError):
    """A stored row that does not read back (the message names the column)."""


def _text(value: object, column: str) -> str | None:
    if value is None:
        return None
    if not isinstance(value, bytes):
        raise _Undecodable(f"{column} is not text but {type(value).__name__} {value!r}")
    try:
        return value.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise _Undecodable(f"{column} is not UTF-8 text: {exc}") from None


def _json(value: object, column: str, empty: Any) -> Any:
    text = _text(value, column)
    if text is None:
        return empty
    try:
        return json.loads(text)
    except ValueError as exc:
        raise _Undecodable(f"{column} is not JSON: {exc}") from None


def _record(row: tuple[Any, ...]) -> RunRecord:
    """One row of `_select` (text as bytes) as a RunRecord; _Undecodable names the column."""
    _key, spec, status, error, cost, nfev, nit, wall, vers = row[: len(_READ)]
    cols = dict(zip(_JSON_COLUMNS, row[len(_READ) :], strict=True))
    try:
        parsed = RunSpec.model_validate_json(_text(spec, "spec") or "")
    except ValidationError as exc:
        raise _Undecodable(f"spec does not validate: {exc.errors()[0]['msg']}") from None
    try:
        run_status = RunStatus(_text(status, "status") or "")
    except ValueError:
        raise _Undecodable(f"status {status!r} is not a run status") from None
    return RunRecord(
        spec=parsed,
        status=run_status,
        error=_text(error, "error"),
        best_cost=cost,
        nfev=nfev,
        nit=nit,
        wall_time_s=wall,
        best_gains=_json(cols["best_gains"], "best_gains", {}),
        metrics=_json(cols["metrics"], "metrics", {}),
        test_costs=_json(cols["test_costs"], "test_costs", {}),
        history=_json(cols["history"], "history", []),
        history_nfev=_json(cols["history_nfev"], "history_nfev", []),
        versions=_json(vers, "versions", {}),
        diagnostics=_json(cols["diagnostics"], "diagnostics", {}),
        robust=_json(cols["robust"], "robust", None),
        step_check=_json(cols["step_check"], "step_check", None),
    )


def _membership(meta: dict[str, str]) -> Callable[[RunSpec], bool]:
    """Whether a run belongs to the study of the config in `meta` (its scenarios x optimizers
    x seeds); every run does in a store that holds no config."""
    if "config" not in meta:
        return lambda spec: True
    try:
        seeds = set(json.loads(meta["config"])["study"]["seeds"])
    except (ValueError, KeyError, TypeError):
        return lambda spec: True
    scenarios = set(meta.get("scenarios", "").splitlines())
    optimizers = set(meta.get("optimizers", "").splitlines())
    return lambda spec: (
        spec.scenario in scenarios and spec.optimizer in optimizers and spec.seed in seeds
    )


@contextmanager
def open_study(study_dir: str | Path, field: str = "DIR") -> Iterator[Store]:
    """`Store.open` as a context manager."""
    store = Store.open(study_dir, field)
    try:
        yield store
    finally:
        store.close()
