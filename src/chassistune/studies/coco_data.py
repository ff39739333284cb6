"""COCO's data folder, written from the study store of `studies.bbob` (Hansen et al. 2021,
COCO).

For each optimizer in the store, the runs are replayed in the driver through cocoex's `bbob`
observer: evaluation k of a run evaluates the point of the last improvement at or before k, so
the observer sees exactly the run's best-so-far cost at every evaluation and the point of every
improvement (what `cocopp`'s ECDFs and tables read); the "measured fitness" of an evaluation that
did not improve is logged as the best-so-far cost. Each improvement's cost is checked against the
stored one, bit for bit. The folder is built in a temporary place and moved in whole:
DIR/coco/<optimizer>/ appears complete or not at all.
"""

from __future__ import annotations

import shutil
import tempfile
from collections import defaultdict
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from chassistune.studies.bbob import SUITE, parse_problem_id
from chassistune.studies.store import RunRecord, open_study

COCO_FOLDER = "coco"


def _replay(problem: Any, record: RunRecord) -> None:
    """Feed the run's best-so-far sequence to `problem` (an observed cocoex problem)."""
    nfev, costs = record.history_nfev, record.history
    points = record.metrics["improvements"]["x"]
    total = int(record.nfev or 0)
    if not nfev or nfev[0] != 1:
        raise RuntimeError(f"{record.spec.key}: the trace must start at evaluation 1")
    ends = [*nfev[1:], total + 1]
    for k, end, cost, x in zip(nfev, ends, costs, points, strict=True):
        point = np.asarray(x, dtype=float)
        value = float(problem(point))
        if value != cost:
            raise RuntimeError(
                f"{record.spec.key}: cocoex gives {value!r} at evaluation {k}, the store {cost!r}"
            )
        for _ in range(end - k - 1):
            problem(point)


def _write_one(optimizer: str, records: list[RunRecord], stage: Path) -> Path:
    import cocoex

    cocoex.log_level("warning")  # no "results will be output to" line on stdout
    keys = sorted(parse_problem_id(r.spec.scenario) for r in records)
    by_problem = {parse_problem_id(r.spec.scenario): r for r in records}
    instances = ",".join(str(i) for i in sorted({k[2] for k in keys}))
    functions = ",".join(str(f) for f in sorted({k[0] for k in keys}))
    dims = ",".join(str(d) for d in sorted({k[1] for k in keys}))
    suite = cocoex.Suite(
        SUITE, f"instances: {instances}", f"function_indices: {functions} dimensions: {dims}"
    )
    observer = cocoex.Observer(
        SUITE,
        f"outer_folder: {stage} result_folder: {optimizer} algorithm_name: {optimizer} "
        f"algorithm_info: chassistune_{optimizer}_pop{records[0].spec.pop_size}",
    )
    for key in keys:
        problem = suite.get_problem_by_function_dimension_instance(*key)
        problem.observe_with(observer)
        _replay(problem, by_problem[key])
        problem.free()
    return Path(observer.result_folder)


def move_in(built: Path, target: Path) -> None:
    """Replace `target` by the folder `built` (copied beside it first, then renamed)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    beside = target.with_name(f".{target.name}.tmp")
    shutil.rmtree(beside, ignore_errors=True)
    shutil.copytree(built, beside)
    old = target.with_name(f".{target.name}.old")
    if target.exists():
        shutil.rmtree(old, ignore_errors=True)
        target.rename(old)
    beside.rename(target)
    shutil.rmtree(old, ignore_errors=True)


def write_coco_data(study_dir: str | Path, optimizers: Iterable[str] | None = None) -> list[Path]:
    """DIR/coco/<optimizer>/ for each optimizer of the store (or those named); their paths."""
    runs: dict[str, list[RunRecord]] = defaultdict(list)
    with open_study(study_dir, "out") as store:
        for record in store.records():
            if record.completed:
                runs[record.spec.optimizer].append(record)
    names = list(optimizers) if optimizers is not None else sorted(runs)
    out = []
    for name in names:
        target = Path(study_dir) / COCO_FOLDER / name
        with tempfile.TemporaryDirectory(prefix="chassistune-coco-") as tmp:
            built = _write_one(name, runs[name], Path(tmp))
            move_in(built, target)
        out.append(target)
    return out
