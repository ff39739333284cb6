"""One driver per study folder: an OS advisory lock on DIR/.study.lock (`fcntl.flock`).

The kernel releases the lock when the driver's process ends in any way (SIGKILL included), so a
rerun after a crash proceeds; the descriptor is close-on-exec and workers are spawned, so no
worker holds it. The file keeps the holder's PID for the refusal message.
"""

from __future__ import annotations

import fcntl
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from chassistune.errors import InputError

LOCK_NAME = ".study.lock"


def _in_use(out_dir: str | Path, pid: bytes) -> InputError:
    return InputError(
        "out",
        f"{str(out_dir)!r} is in use by another study run (process "
        f"{pid.decode('ascii', 'replace').strip() or 'unknown'}); wait for it to "
        "finish or stop it",
    )


def refuse_if_locked(out_dir: str | Path) -> None:
    """InputError naming the driver that holds DIR's lock now (checked before reading DIR)."""
    pid = holder(out_dir)
    if pid is not None:
        raise _in_use(out_dir, pid.encode("ascii"))


@contextmanager
def study_lock(out_dir: str | Path) -> Iterator[None]:
    """Hold DIR's lock for the block, or raise InputError naming the process that holds it."""
    os.makedirs(out_dir, exist_ok=True)
    path = Path(out_dir) / LOCK_NAME
    fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise _in_use(out_dir, os.pread(fd, 32, 0)) from None
        try:
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode("ascii"), 0)
        except OSError as exc:
            raise InputError("out", f"cannot write {str(path)!r}: {exc.strerror}") from None
        yield
    finally:
        os.close(fd)  # closing the descriptor releases the lock


def holder(out_dir: str | Path) -> str | None:
    """The PID of the driver holding DIR's lock now, else None (never creates the file)."""
    path = Path(out_dir) / LOCK_NAME
    try:
        fd = os.open(path, os.O_RDONLY | os.O_CLOEXEC)
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return os.pread(fd, 32, 0).decode("ascii", "replace").strip() or "unknown"
    finally:
        os.close(fd)
    return None
