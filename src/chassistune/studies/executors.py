"""Where runs execute: in the driver (serial), in a local process pool, or on Dask.

Every executor takes run specs and yields the workers' `RunResult`s as runs finish (in any
order); only the driver writes them to the store. A run's numbers depend only on its spec, so all
executors give identical results. Worker processes simulate with one thread each
(CHASSISTUNE_THREADS=1): the parallelism is across runs; a kernel's results do not depend on its
thread count.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
import threading
import time
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from typing import Any

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


def _exit_with_parent(parent: int, period_s: float = 0.5) -> None:
    """End this worker once its driver is gone (a SIGKILLed driver cannot shut its pool)."""
    while os.getppid() == parent:
        time.sleep(period_s)
    os._exit(1)


def _init_worker(parent: int, extra: Callable[[], None] | None) -> None:
    os.environ["CHASSISTUNE_THREADS"] = "1"
    threading.Thread(target=_exit_with_parent, args=(parent,), daemon=True).start()
    if extra is not None:
        extra()


class ProcessExecutor(Executor):
    """A pool of `workers` spawned processes; a few runs in flight per worker.

    A worker process that dies (killed, out of memory, a crash in compiled code) breaks the pool:
    the runs that were in flight are then redone one at a time in a new pool, so that the run
    that kills its worker is found and recorded failed while the others complete.
    `initializer` (a module-level function) runs once in each worker, e.g. to register a plant.
    """

    name = "process"

    def __init__(self, workers: int | None = None,
                 initializer: Callable[[], None] | None = None) -> None:
        self.workers = workers or default_workers()
        self._initializer = initializer
        self._pool: cf.ProcessPoolExecutor | None = None

    def _new_pool(self) -> cf.ProcessPoolExecutor:
        if self._pool is not None:
            self._pool.shutdown(wait=False, cancel_futures=True)
        self._pool = cf.ProcessPoolExecutor(
            self.workers, mp_context=multiprocessing.get_context("spawn"),
            initializer=_init_worker, initargs=(os.getpid(), self._initializer))
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
        self._new_pool()
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

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None


def _dask_missing() -> InputError:
    return InputError("--executor", 'dask is not installed: pip install "chassistune[dask]" '
                      '(or pip install "dask[distributed]")')


def check_dask() -> None:
    """InputError saying how to install Dask when it is missing."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise _dask_missing() from None


class DaskExecutor(Executor):
    """dask.distributed: the scheduler at `address`, else a LocalCluster on loopback.

    A lost worker's runs are retried elsewhere by Dask (`retries`); a run that still cannot
    finish is recorded failed with the reason.
    """

    name = "dask"

    def __init__(self, address: str | None = None, workers: int | None = None,
                 processes: bool = True, retries: int = 1) -> None:
        check_dask()
        from distributed import Client, LocalCluster

        self._cluster: Any = None
        self.retries = retries
        if address is None:
            # worker processes listen on loopback only; threads talk in-process (inproc://)
            where: dict[str, Any] = ({"host": "127.0.0.1", "env": {"CHASSISTUNE_THREADS": "1"}}
                                     if processes else {})
            self._cluster = LocalCluster(n_workers=workers or default_workers(),
                                         threads_per_worker=1, processes=processes,
                                         dashboard_address=None, **where)
            self._client = Client(self._cluster)
        else:
            try:
                self._client = Client(address, timeout="20s")
            except (OSError, ValueError, TypeError) as exc:
                raise InputError("--scheduler", f"cannot reach a Dask scheduler at {address!r} "
                                 f"({type(exc).__name__}: {exc})") from None

    def results(self, specs: Sequence[RunSpec]) -> Iterator[RunResult]:
        from distributed import as_completed

        futures = {self._client.submit(execute_run, s, key=f"run-{s.spec_hash}", pure=False,
                                       retries=self.retries): s for s in specs}
        for fut in as_completed(futures):
            spec = futures[fut]
            try:
                result: RunResult = fut.result()
            except Exception as exc:  # the worker running it was lost too often
                result = failed_result(spec, f"dask: {type(exc).__name__}: {exc}")
            fut.release()
            yield result

    def close(self) -> None:
        self._client.close()
        if self._cluster is not None:
            self._cluster.close()


def make_executor(name: str, workers: int | None = None, scheduler: str | None = None) -> Executor:
    """An executor by name (`serial`, `process`, `dask`)."""
    if name not in EXECUTORS:
        raise InputError("--executor", f"unknown executor {name!r} (known: {', '.join(EXECUTORS)})")
    if scheduler is not None and name != "dask":
        raise InputError("--scheduler", "a scheduler address needs --executor dask")
    if workers is not None and workers < 1:
        raise InputError("--workers", f"must be a positive whole number, got {workers}")
    if name == "serial":
        return SerialExecutor()
    if name == "process":
        return ProcessExecutor(workers)
    return DaskExecutor(scheduler, workers)
