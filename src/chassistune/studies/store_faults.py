"""What went wrong with a study store, in one line: SQLite's errors named by the store's path.

SQLite reports a full disk, an I/O error, a read-only file, a damaged file or a lock held by
another process through `sqlite3` exceptions whose (primary) result codes tell them apart
(https://www.sqlite.org/rescode.html). `store_error` turns each into an `InputError` naming the
store; `lock_holders` names the processes that have the store open (Linux `/proc`), so that a
wait for a lock says whom it waits for.
"""

from __future__ import annotations

import os
import sqlite3
from pathlib import Path

from chassistune.errors import InputError

BUSY_CODES = frozenset({sqlite3.SQLITE_BUSY, sqlite3.SQLITE_LOCKED})
"""Another connection holds a lock the statement needs (retried until a timeout)."""

_PROBLEMS = {
    sqlite3.SQLITE_FULL: "the disk is full",
    sqlite3.SQLITE_IOERR: "a disk I/O error",
    sqlite3.SQLITE_READONLY: "it is read-only",
    sqlite3.SQLITE_CANTOPEN: "it cannot be opened",
    sqlite3.SQLITE_CORRUPT: "it is damaged",
    sqlite3.SQLITE_NOTADB: "it is not an SQLite file",
    sqlite3.SQLITE_PERM: "permission denied",
}


def primary_code(exc: sqlite3.Error) -> int | None:
    """SQLite's primary result code of `exc` (extended codes keep it in the low byte)."""
    code = getattr(exc, "sqlite_errorcode", None)
    return None if code is None else code & 0xFF


def is_busy(exc: sqlite3.Error) -> bool:
    return primary_code(exc) in BUSY_CODES


def store_error(path: str | Path, exc: sqlite3.Error, field: str, consequence: str) -> InputError:
    """`exc` as one line naming the store at `path`; `consequence` says what became of the work
    (e.g. "the runs stored before are kept"). SQLite reports a full disk as an I/O error when
    it cannot create its side files: a file system without free space is named as full."""
    code = primary_code(exc)
    problem = _PROBLEMS.get(code, "SQLite failed") if code is not None else "SQLite failed"
    if code in _DISK_CODES and _no_space_left(Path(path)):
        problem = _PROBLEMS[sqlite3.SQLITE_FULL]
    return InputError(field, f"cannot use {str(path)!r}: {problem} ({exc}); {consequence}")


_DISK_CODES = frozenset({sqlite3.SQLITE_FULL, sqlite3.SQLITE_IOERR, sqlite3.SQLITE_CANTOPEN})


def _no_space_left(path: Path) -> bool:
    try:
        return os.statvfs(path.parent).f_bavail == 0
    except OSError:
        return False


def lock_holders(path: str | Path) -> list[str]:
    """'PID (command)' of every other process with the store (or its -wal/-shm) open; empty
    where /proc is not readable."""
    target = Path(path).resolve()
    names = {str(target), f"{target}-wal", f"{target}-shm", f"{target}-journal"}
    found = []
    for pid in _pids():
        if pid == os.getpid():
            continue
        try:
            links = {os.readlink(f"/proc/{pid}/fd/{fd}") for fd in os.listdir(f"/proc/{pid}/fd")}
        except OSError:
            continue
        if links & names:
            found.append(f"{pid} ({_command(pid)})")
    return found


def _pids() -> list[int]:
    try:
        return [int(p) for p in os.listdir("/proc") if p.isdigit()]
    except OSError:
        return []


def _command(pid: int) -> str:
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as fh:
            words = fh.read().split(b"\0")
    except OSError:
        return "unknown"
    text = " ".join(" ".join(w.decode("utf-8", "replace").split()) for w in words if w)
    return text[:80] or "unknown"
