"""Where runs execute: in the driver (serial), in a local process pool, or on Dask.

Every executor takes run specs and yields the workers' `RunResult`s as runs finish (in any
order); only the driver writes them to the store. A run's numbers depend only on its spec, so all
executors give identical results. Worker processes simulate with one thread each
(CHASSISTUNE_THREADS=1): the parallelism is across runs; a kernel's results do not depend on its
thread count.
"""

from __future__ import annotations

import ast
import concurrent.futures as cf
import multiprocessing
import os
import sys
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from chassistune._interrupt import as_worker
from chassistune.errors import InputError
from chassistune.sim.batch import default_workers
from chassistune.studies.records import RunResult
from chassistune.studies.spec import RunSpec
from chassistune.studies.worker import execute_run, failed_result

EXECUTORS = ("serial", "process", "dask")


class Executor(ABC):
    """Runs specs; `results(specs)` yields one `RunResult` per spec as runs finish."""

    name: str = ""

    @abstractmethod
    def results(self, specs: Sequence[RunSpec]) -> Iterator[RunResult]:
        """Yield one result per spec, in completion order."""

    def close(self) -> None:  # noqa: B027 - nothing to release by default
        """Release workers and clusters."""

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class SerialExecutor(Executor):
    """Runs in the driver's process, one after the other."""

    name = "serial"

    def results(self, specs: Sequence[RunSpec]) -> Iterator[RunResult]:
        for spec in specs:
            yield execute_run(spec)


def _init_worker(parent: int, extra: Callable[[], None] | None) -> None:
    """Worker set-up: one kernel thread, then `_interrupt.as_worker` (Ctrl-C left to the driver,
    SIGTERM silent, exit with the driver)."""
    os.environ["CHASSISTUNE_THREADS"] = "1"
    as_worker(parent)
    if extra is not None:
        extra()


def _under_main_guard(tree: ast.Module, line: int) -> bool:
    """Whether `line` of a module lies inside an `if __name__ == "__main__":` block."""
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.If)
            and "__main__" in ast.unparse(node.test)
            and "__name__" in ast.unparse(node.test)
        ):
            end = node.end_lineno or node.lineno
            if node.lineno <= line <= end:
                return True
    return False


def check_main_guard() -> None:
    """Refuse to start spawned workers from the unguarded top level of a script: each worker
    re-imports the script (spawn), which would start workers again; Python then kills every
    worker during its bootstrapping. One line instead of a study of dead workers."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if main is None or path is None or not str(path).endswith(".py"):
        return  # interactive, -c, or a console script: nothing re-imported
    frame = sys._getframe(1)
    while frame is not None and frame.f_globals is not vars(main):
        frame = frame.f_back  # type: ignore[assignment]
    if frame is None or frame.f_code.co_name != "<module>":
        return  # called from a function of the script: fine under spawn
    try:
        tree = ast.parse(Path(path).read_text(encoding="utf-8"))
    except (OSError, SyntaxError, ValueError):
        return
    if not _under_main_guard(tree, frame.f_lineno):
        raise InputError(
            "executor",
            f"worker processes re-import {os.path.basename(path)!r} "
            '(spawn): put the study code under `if __name__ == "__main__":` '
            "(docs/studies.md)",
        )


class ProcessExecutor(Executor):
    """A pool of `workers` spawned processes; a few runs in flight per worker.

    A worker process that dies (killed, out of memory, a crash in compiled code) breaks the pool:
    the runs that were in flight are then redone one at a time in a new pool, so that the run
    that kills its worker is found and recorded failed while the others complete.
    `initializer` (a module-level function) runs once in each worker, e.g. to register a plant.
    """

    name = "process"

    def __init__(
        self, workers: int | None = None, initializer: Callable[[], None] | None = None
    ) -> None:
        check_main_guard()
        self.workers = workers or default_workers()
        self._initializer = initializer
        self._pool: cf.ProcessPoolExecutor | None = None
        self._unfinished = False

    def _new_pool(self) -> cf.ProcessPoolExecutor:
        if self._pool is not None:
            self._pool.shutdown(wait=False, cancel_futures=True)
        self._pool = cf.ProcessPoolExecutor(
            self.workers,
            mp_context=multiprocessing.get_context("spawn"),
            initializer=_init_worker,
            initargs=(os.getpid(), self._initializer),
        )
        return self._pool

    def _alone(self, spec: RunSpec) -> RunResult:
        """Run one suspect with nothing else in flight; its worker dying convicts it."""
        pool = self._pool or self._new_pool()
        try:
            return pool.submit(execute_run, spec).result()
        except cf.process.BrokenProcessPool:
            self._new_pool()
            return failed_result(spec, "the worker process died while running it")

    def results(self, specs: Sequence[RunSpec]) -> Iterator[RunResult]:
        """The runs' results as they finish. The pool's workers serve every call (a reproduction's
        studies one after another: each worker imports and loads its kernels once); a call left
        before its end (runs of it may still be in flight) leaves the next one a new pool."""
        if self._pool is None or self._unfinished:
            self._new_pool()
        self._unfinished = True
        pending, suspects = deque(specs), deque[RunSpec]()
        running: dict[cf.Future[RunResult], RunSpec] = {}
        window = 2 * self.workers
        while pending or suspects or running:
            if suspects and not running:
                yield self._alone(suspects.popleft())
                continue
            while pending and not suspects and len(running) < window:
                spec = pending.popleft()
                running[self._pool.submit(execute_run, spec)] = spec  # type: ignore[union-attr]
            done, _ = cf.wait(running, return_when=cf.FIRST_COMPLETED)
            finished: list[RunResult] = []
            for fut in done:
                spec = running.pop(fut)
                try:
                    finished.append(fut.result())
                except cf.process.BrokenProcessPool:
                    suspects.append(spec)
            if suspects and running:  # the pool is broken: every run in flight is lost
                suspects.extend(running.values())
                running.clear()
            if suspects and not running:
                self._new_pool()
            yield from finished
        self._unfinished = False

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None


def _dask_missing() -> InputError:
    return InputError(
        "executor",
        'dask is not installed: pip install "chassistune[dask]" '
        '(or pip install "dask[distributed]")',
    )


def check_dask() -> None:
    """InputError saying how to install Dask when it is missing."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise _dask_missing() from None


ALLOWED_FAILURES = 0
"""On a cluster we start, the scheduler gives up on a run at its worker's first death (Dask's
default 3 retries a run four times, and convicts the innocent runs queued on the same worker
along with it); the driver then redoes each such run alone (`DaskExecutor.results`)."""
SCHEDULER_TIMEOUT_S = 3
"""How long an unreachable `--scheduler` is waited for."""


class DaskExecutor(Executor):
    """dask.distributed: the scheduler at `address`, else a LocalCluster on loopback.

    A run whose worker died (Dask's KilledWorker) is redone alone once every other run has
    finished, so that a run that kills its worker is told apart from those that shared the
    worker: the latter complete, the former is recorded failed ("the worker process died while
    running it"). On the LocalCluster started here the scheduler's `allowed-failures` is
    ALLOWED_FAILURES (a run is tried twice in all); an external scheduler keeps its own setting
    (Dask's default 3: up to four tries before the driver's one alone). A run that raises is
    recorded failed by its worker and never retried (failures are deterministic). No dashboard
    is started.
    """

    name = "dask"

    def __init__(
        self, address: str | None = None, workers: int | None = None, processes: bool = True
    ) -> None:
        check_dask()
        from distributed import Client, LocalCluster

        self._cluster: Any = None
        if address is None:
            if processes:
                check_main_guard()
            # worker processes listen on loopback only; threads talk in-process (inproc://)
            where: dict[str, Any] = (
                {"host": "127.0.0.1", "env": {"CHASSISTUNE_THREADS": "1"}} if processes else {}
            )
            self._cluster = LocalCluster(
                n_workers=workers or default_workers(),
                threads_per_worker=1,
                processes=processes,
                dashboard_address=None,
                scheduler_kwargs={
                    "dashboard": False,
                    "dashboard_address": "127.0.0.1:0",
                    "allowed_failures": ALLOWED_FAILURES,
                },
                **where,
            )
            self._client = Client(self._cluster)
        else:
            try:
                self._client = Client(address, timeout=f"{SCHEDULER_TIMEOUT_S}s")
            except (OSError, ValueError, TypeError) as exc:
                raise InputError(
                    "scheduler",
                    f"cannot reach a Dask scheduler at {address!r} "
                    f"within {SCHEDULER_TIMEOUT_S} s ({type(exc).__name__}: "
                    f"{exc})",
                ) from None

    def results(self, specs: Sequence[RunSpec]) -> Iterator[RunResult]:
        from distributed import as_completed

        suspects = []
        futures = {
            self._client.submit(execute_run, s, key=f"run-{s.spec_hash}", pure=False): s
            for s in specs
        }
        for fut in as_completed(futures):
            result = _collect(fut, futures[fut])
            if result is None:
                suspects.append(futures[fut])
            else:
                yield result
        for spec in suspects:  # alone now: a worker dying convicts this run
            fut = self._client.submit(execute_run, spec, key=f"alone-{spec.spec_hash}", pure=False)
            yield _collect(fut, spec) or failed_result(
                spec, "the worker process died while running it"
            )

    def close(self) -> None:
        self._client.close()
        if self._cluster is not None:
            self._cluster.close()


def _collect(fut: Any, spec: RunSpec) -> RunResult | None:
    """A Dask future's run result (released); None when its worker died (KilledWorker)."""
    from distributed.scheduler import KilledWorker

    try:
        result: RunResult = fut.result()
    except KilledWorker:
        return None
    except Exception as exc:  # any other scheduler error fails this run only
        result = failed_result(spec, f"dask: {type(exc).__name__}: {exc}")
    finally:
        fut.release()
    return result


def make_executor(name: str, workers: int | None = None, scheduler: str | None = None) -> Executor:
    """An executor by name (`serial`, `process`, `dask`)."""
    if name not in EXECUTORS:
        raise InputError("executor", f"unknown executor {name!r} (known: {', '.join(EXECUTORS)})")
    if scheduler is not None and name != "dask":
        raise InputError("scheduler", "a scheduler address needs the dask executor")
    if workers is not None and workers < 1:
        raise InputError("workers", f"must be a positive whole number, got {workers}")
    if name == "serial":
        if workers is not None:
            raise InputError(
                "workers",
                "the serial executor runs in the driver alone; use the "
                "process or dask executor for workers",
            )
        return SerialExecutor()
    if name == "process":
        return ProcessExecutor(workers)
    return DaskExecutor(scheduler, workers)
