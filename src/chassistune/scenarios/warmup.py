"""Compile every kernel variant a scenario can reach, once, ahead of its first use (numba caches
the machine code on disk, keyed on the sources): the scenario part of `chassistune warmup`.

The cases come from the registries: every plant x preset x road x controller, the single wheel
in each ECU mode (`ECU_MODES`). The first case of each controller in a group runs every
objective on a small random population and a trace; every other case, whose kernel differs in
values only, runs its default objective on the controller's default gains, one row, for a
short horizon (`exercise`, `Case.cut_short`: a run to the stop is seconds of simulated time,
which no compiler needs). Building one scenario of each (plant, controller, ECU mode) first,
in this process, compiles what scenarios share (the fuzzy surfaces) and names the compiled
entry point each kind of case goes through (`entry_point`); the cases are then grouped by entry
point and the groups, with `extra` (kernels no case reaches) run after the group whose kernels
it shares (`EXTRA_WITH`), spread over worker processes, the largest estimated compilation
first. No kernel is compiled in two groups, so no two processes write one function's cache
index at once (numba's index is rewritten whole: two writers would lose an entry).
"""

from __future__ import annotations

import gc
import itertools
import multiprocessing
import os
import time
import warnings
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from dataclasses import dataclass, fields, replace

import numpy as np

from chassistune._compile_notice import CompileLog, estimate_cpu_s, recording
from chassistune._interrupt import as_worker
from chassistune._rng import make_rng
from chassistune.errors import InputError
from chassistune.scenarios.abs_wheel import AbsWheelScenario
from chassistune.scenarios.abs_wheel_ecu import ECU_MODES
from chassistune.scenarios.base import Scenario
from chassistune.scenarios.registry import get_plant, plant_names

POPULATION = 4
"""Rows of each case's population (the batch path of a tuning, in one chunk)."""

HORIZON_PARAM = "t_max_s"
SHORT_HORIZON_S = 0.05
"""The horizon of a case that runs for its compilation only (`Case.cut_short`): a stop takes
seconds of simulated time, at up to 10^5 steps a second on the finest presets."""

Compiled = list[tuple[str, float]]
"""(function, CPU seconds) of each compilation (`_compile_notice.CompileLog.done`)."""


@dataclass(frozen=True)
class Case:
    """One plant, preset, road and controller, with the parameters that pick a kernel."""

    plant: str
    preset: str
    road: str
    controller: str
    params: tuple[tuple[str, str], ...] = ()

    def scenario(self) -> Scenario:
        plant = get_plant(self.plant)
        return plant.scenario(self.preset, self.road, self.controller, dict(self.params), 0)

    def cut_short(self) -> Case:
        """The case with its horizon `SHORT_HORIZON_S` where the plant has a horizon parameter
        (`HORIZON_PARAM`): the same kernel, on values that end a run soon."""
        groups = get_plant(self.plant).parameter_sets().values()
        names = {f.name for group in groups for f in fields(group)}
        if HORIZON_PARAM not in names:
            return self
        horizon = ((HORIZON_PARAM, repr(SHORT_HORIZON_S)),)
        return replace(self, params=self.params + horizon)


def cases() -> list[Case]:
    """Every combination the registries offer (`abs-wheel` in each ECU mode)."""
    out = []
    for name in plant_names():
        plant = get_plant(name)
        modes = [(("ecu", m),) for m in ECU_MODES] if name == "abs-wheel" else [()]
        for preset, road, spec, params in itertools.product(
            plant.presets(), plant.roads(), plant.controllers(), modes
        ):
            out.append(Case(name, preset, road, spec.name, params))
    return out


def entry_point(sc: Scenario) -> str:
    """The compiled entry point `sc`'s runs go through (`module.function`, as
    `_compile_notice.kernel_name` names it)."""
    if isinstance(sc, AbsWheelScenario):
        return "abs_wheel_ecu_kernel" if sc.ecu is not None else "abs_wheel_kernel"
    return f"{sc.plant.replace('-', '_')}_kernel"


def exercise(sc: Scenario, every_objective: bool, seed: int = 0) -> None:
    """With `every_objective`: each objective (one may have a kernel of its own: the quarter
    car's exact one) on a random population in the controller's box, and a trace; else the
    default objective on the default gains."""
    if not every_objective:
        sc.cost(sc.gains_array(None)[None, :], sc.default_objective)
        return
    box = np.array(sc.controller.bounds(), dtype=float).reshape(-1, 2)
    rows = make_rng(seed).random((POPULATION, box.shape[0]))
    population = box[:, 0] + rows * (box[:, 1] - box[:, 0])
    for objective in sc.objectives:
        sc.cost(population, objective)
    sc.trace(sc.gains_array(None))


@contextmanager
def collection_paused() -> Iterator[None]:
    """Python's cyclic garbage collector off inside (back as it was after): numba's compiler
    makes many short-lived objects, and collecting them while it runs costs a fifth of a kernel's
    compile time; the cycles it leaves (hundreds of MB at most) are collected at the end."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()
        gc.collect()


def run(group: list[Case], extra: Callable[[], None] | None = None) -> Compiled:
    """Exercise every case of `group` in this process, with every objective and a trace for
    the first case of each controller (the others differ in values only), then `extra`: what
    was compiled. A case whose preset and road do not go together is skipped. Python's garbage
    collector is paused meanwhile (`collection_paused`)."""
    log = CompileLog()
    seen: set[str] = set()
    with collection_paused(), recording(log), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # implausible values of the combinations: not the user's
        for case in group:
            first = case.controller not in seen
            try:
                sc = (case if first else case.cut_short()).scenario()
            except InputError:
                continue
            exercise(sc, first)
            seen.add(case.controller)
        if extra is not None:
            extra()
    return log.done


def _kind(case: Case) -> tuple[str, str, tuple[tuple[str, str], ...]]:
    """What picks a case's entry point: its plant, controller and parameters (the ECU mode)."""
    return case.plant, case.controller, case.params


def group_by_entry_point(all_cases: list[Case]) -> dict[str, list[Case]]:
    """The cases by the entry point they go through, from one built scenario per `_kind` (which
    compiles here what the scenarios share)."""
    entry: dict[tuple[str, str, tuple[tuple[str, str], ...]], str] = {}
    groups: dict[str, list[Case]] = {}
    for case in all_cases:
        kind = _kind(case)
        if kind not in entry:
            try:
                entry[kind] = entry_point(case.scenario())
            except InputError:  # a preset and road that do not go together
                continue
        groups.setdefault(entry[kind], []).append(case)
    return groups


@dataclass(frozen=True)
class Warmup:
    """What `warm_up` did."""

    cases: int
    groups: dict[str, int]
    """Cases per entry point."""
    compiled: Compiled
    wall_s: float


EXTRA = "extra"
"""The group name of `warm_up`'s `extra` kernels where no case goes through `EXTRA_WITH`."""
EXTRA_WITH = "abs_wheel_ecu_kernel"
"""The entry point whose group runs `extra` after its cases: the realistic ECU kernel, whose
law dispatch (`controllers.laws.dispatch.ecu_step`) the C export's replay calls too."""


Job = tuple[list[Case], Callable[[], None] | None]
"""The cases of a group and its `extra` (`run`'s arguments)."""


def _plan(
    extra: Callable[[], None] | None,
) -> tuple[dict[str, list[Case]], dict[str, Job], Compiled]:
    """(the cases by entry point, the jobs by group, the largest estimated compilation first,
    what grouping compiled here)."""
    log = CompileLog()
    with collection_paused(), recording(log), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        groups = group_by_entry_point(cases())
    jobs: dict[str, Job] = {key: (cases_, None) for key, cases_ in groups.items()}
    if extra is not None and EXTRA_WITH in jobs:
        jobs[EXTRA_WITH] = (jobs[EXTRA_WITH][0], extra)
    elif extra is not None:
        jobs[EXTRA] = ([], extra)
    order = sorted(jobs, key=lambda k: -estimate_cpu_s(k))
    return groups, {key: jobs[key] for key in order}, list(log.done)


def warm_up(
    processes: int = 2,
    extra: Callable[[], None] | None = None,
    progress: Callable[[str, Compiled], None] | None = None,
) -> Warmup:
    """Compile the kernels of every case, in `processes` worker processes (1: here); `extra`
    compiles kernels no case reaches (such as the C export's replay; a module-level function,
    since it runs in a worker), after the cases of `EXTRA_WITH`, with which it shares a kernel;
    `progress(entry point, compiled)` as each group finishes."""
    t0 = time.perf_counter()
    if processes <= 1:
        groups, jobs, compiled = _plan(extra)
        for key in jobs:
            done = run(*jobs[key])
            compiled += done
            if progress is not None:
                progress(key, done)
    else:
        spawn = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(
            processes, mp_context=spawn, initializer=as_worker, initargs=(os.getpid(),)
        ) as pool:
            for _ in range(processes):  # the workers start and import while the cases are grouped
                pool.submit(run, [])
            groups, jobs, compiled = _plan(extra)
            futures = {pool.submit(run, *jobs[key]): key for key in jobs}
            for future in as_completed(futures):
                done = future.result()
                compiled += done
                if progress is not None:
                    progress(futures[future], done)
    sizes = {key: len(jobs[key][0]) for key in jobs if key in groups}
    return Warmup(sum(sizes.values()), sizes, compiled, time.perf_counter() - t0)
