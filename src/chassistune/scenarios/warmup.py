"""Compile every kernel variant a scenario can reach, once, ahead of its first use (numba caches
the machine code on disk, keyed on the sources): the scenario part of `chassistune warmup`.

The cases come from the registries: every plant x preset x road x controller, the single wheel
in each ECU mode (`ECU_MODES`); each runs its default objective on a small population, the
first of each controller every objective and a trace (`exercise`). Building every case's
scenario first, in this process, compiles what scenarios share (the fuzzy surfaces); the runs
are then grouped by the compiled entry point they go through (`entry_point`) and the groups
spread over worker processes, the largest estimated compilation first. No kernel is compiled in
two groups, so no two processes write one function's cache index at once (numba's index is
rewritten whole: two writers would lose an entry).
"""

from __future__ import annotations

import itertools
import multiprocessing
import os
import time
import warnings
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass

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
    """The default objective on a random population in the controller's box; with
    `every_objective`, each objective (one may have a kernel of its own: the quarter car's exact
    one) and a trace too."""
    box = np.array(sc.controller.bounds(), dtype=float).reshape(-1, 2)
    rows = make_rng(seed).random((POPULATION, box.shape[0]))
    population = box[:, 0] + rows * (box[:, 1] - box[:, 0])
    for objective in sc.objectives if every_objective else (sc.default_objective,):
        sc.cost(population, objective)
    if every_objective:
        sc.trace(sc.gains_array(None))


def run(group: list[Case]) -> Compiled:
    """Exercise every case of `group` in this process, with every objective and a trace for
    the first case of each controller (the others differ in values only): what was compiled."""
    log = CompileLog()
    seen: set[str] = set()
    with recording(log), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # implausible values of the combinations: not the user's
        for case in group:
            exercise(case.scenario(), case.controller not in seen)
            seen.add(case.controller)
    return log.done


@dataclass(frozen=True)
class Warmup:
    """What `warm_up` did."""

    cases: int
    groups: dict[str, int]
    """Cases per entry point."""
    compiled: Compiled
    wall_s: float


def warm_up(
    processes: int = 2,
    before: Callable[[], None] | None = None,
    progress: Callable[[str, Compiled], None] | None = None,
) -> Warmup:
    """Compile the kernels of every case, in `processes` worker processes (1: here); `before`
    runs here first, after the scenarios are built (kernels no case reaches, such as the C
    export's replay); `progress(entry point, compiled)` as each group finishes."""
    t0 = time.perf_counter()
    log = CompileLog()
    groups: dict[str, list[Case]] = {}
    with recording(log), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for case in cases():
            try:
                sc = case.scenario()
            except InputError:  # a preset and road that do not go together
                continue
            groups.setdefault(entry_point(sc), []).append(case)
        if before is not None:
            before()
    compiled = list(log.done)
    order = sorted(groups, key=lambda k: -estimate_cpu_s(k))
    if processes <= 1:
        for key in order:
            done = run(groups[key])
            compiled += done
            if progress is not None:
                progress(key, done)
    else:
        spawn = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(
            processes, mp_context=spawn, initializer=as_worker, initargs=(os.getpid(),)
        ) as pool:
            futures = {pool.submit(run, groups[key]): key for key in order}
            for future in as_completed(futures):
                done = future.result()
                compiled += done
                if progress is not None:
                    progress(futures[future], done)
    sizes = {key: len(groups[key]) for key in order}
    return Warmup(sum(sizes.values()), sizes, compiled, time.perf_counter() - t0)
