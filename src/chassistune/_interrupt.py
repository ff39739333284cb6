"""The one Ctrl-C policy of the command line: stop within a moment, exit 130, one line.

Installed by `cli.main` (and by the package's `__init__` when the process is the `chassistune`
console script, so that Ctrl-C during the first imports is covered too); stdlib only.

Python runs a signal handler only in the main thread between bytecodes, so a compiled kernel in
the main thread, an import in C, or a swallowed KeyboardInterrupt (inside a ctypes callback of
the compiler) would delay or lose Ctrl-C. Instead the C-level handler writes the signal number to
a pipe (`signal.set_wakeup_fd`), which it does at once whatever the main thread is doing; a
watcher thread reading that pipe runs the commands' `on_interrupt` hooks (a tune writes its best
so far, a study says what is stored), prints one line and ends the process with `os._exit(130)`.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from collections.abc import Callable

EXIT_INTERRUPTED = 130

_hooks: list[Callable[[], str | None]] = []
_installed = False


def on_interrupt(hook: Callable[[], str | None]) -> Callable[[], None]:
    """Run `hook` when Ctrl-C stops the command (its text, if any, ends the one line); the
    returned function unregisters it."""
    _hooks.append(hook)
    return lambda: _hooks.remove(hook) if hook in _hooks else None


def _finish() -> None:
    words = ["interrupted"]
    for hook in list(_hooks):
        try:
            said = hook()
        except Exception as exc:  # the exit must happen whatever a hook does
            said = f"({type(exc).__name__} while saving: {exc})"
        if said:
            words.append(said)
    try:
        sys.stderr.write("chassistune: " + "; ".join(words) + "\n")
        sys.stderr.flush()
        sys.stdout.flush()
    finally:
        os._exit(EXIT_INTERRUPTED)


def _watch(fd: int) -> None:
    while True:
        try:
            data = os.read(fd, 64)
        except InterruptedError:  # pragma: no cover - retried by os.read since PEP 475
            continue
        if not data:  # pragma: no cover - the write end never closes
            return
        if signal.SIGINT in data or signal.SIGTERM in data:
            _finish()


def _ignore(signum: int, frame: object) -> None:
    """Python-level handler: nothing (the watcher thread acts on the wakeup byte)."""


def install() -> None:
    """Route SIGINT and SIGTERM to the watcher (main thread only; once per process)."""
    global _installed
    if _installed or threading.current_thread() is not threading.main_thread():
        return
    read_fd, write_fd = os.pipe()
    os.set_blocking(write_fd, False)
    signal.set_wakeup_fd(write_fd, warn_on_full_buffer=False)
    signal.signal(signal.SIGINT, _ignore)
    signal.signal(signal.SIGTERM, _ignore)
    threading.Thread(target=_watch, args=(read_fd,), name="ctrl-c", daemon=True).start()
    _installed = True


def _exit_with_parent(parent: int, period_s: float = 0.5) -> None:
    """End this worker once its driver is gone (a SIGKILLed driver cannot shut its pool)."""
    while os.getppid() == parent:
        time.sleep(period_s)
    os._exit(1)


def as_worker(parent: int) -> None:
    """In a pool's worker process of driver `parent`: Ctrl-C is left to the driver (which ends
    the command at once) and the worker ends within a moment of the driver. A spawned worker
    re-imports the driver's main module under the driver's argv, so it may have taken the
    command line's policy (`install`): it ends on SIGTERM as any process does, saying nothing."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.set_wakeup_fd(-1)
    threading.Thread(target=_exit_with_parent, args=(parent,), daemon=True).start()
