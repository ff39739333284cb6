"""The files of a tune (`tune --out`) and of the demo, written by a function that any command can
call (`tune`, `demo`, and `reproduce` next): results in, files out, nothing printed.

Here rather than in `tuning/`: the outputs include figures, and only reports, papers and the CLI
may draw (computation modules never import matplotlib).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from chassistune._io import file_set
from chassistune.tuning.problem import TuningProblem
from chassistune.tuning.run import TuneResult

DEMO_PRESET = "paper-derlsp-ao"
DEMO_METRICS = (
    "stop_time_s",
    "stop_distance_m",
    "bound_distance_m",
    "distance_ratio",
    "wheel_lock_time_s",
)


def write_tune_outputs(result: TuneResult, out_dir: str) -> list[str]:
    """best_gains.json, tune.json, history.csv, convergence.png and one response plot per road
    into `out_dir` (created if missing), as one set: all or none (`_io.file_set`); the paths
    written, in that order."""
    from chassistune.plots.convergence import plot_convergence
    from chassistune.plots.registry import plot_trace

    written = []
    with file_set(out_dir) as staged:
        path = os.path.join(out_dir, "best_gains.json")
        staged.write_json(path, result.best_gains)
        written.append(path)
        path = os.path.join(out_dir, "tune.json")
        staged.write_json(path, result.as_dict())
        written.append(path)
        path = os.path.join(out_dir, "history.csv")
        rows = "\n".join(
            f"{i + 1},{int(n)},{float(c)!r}"
            for i, (n, c) in enumerate(zip(result.history_nfev, result.history, strict=True))
        )
        staged.write_text(path, "iteration,nfev,best_cost\n" + rows + "\n")
        written.append(path)
        path = os.path.join(out_dir, "convergence.png")
        first = result.problem.scenarios[0]
        with staged.path(path) as tmp:
            plot_convergence(
                {result.optimizer: [(result.history_nfev, result.history)]},
                tmp,
                title=f"{first.plant} {first.controller.name} on "
                f"{', '.join(result.problem.roads)}: {result.problem.objective}, seed "
                f"{first.seed}",
            )
        written.append(path)
        gains = np.array([result.best_gains[n] for n in result.problem.gain_names])
        for sc in result.problem.scenarios:
            road = sc.road.replace(os.sep, "_").replace("/", "_")  # a measured road is a path
            path = os.path.join(out_dir, f"response-{road}.png")
            with staged.path(path) as tmp:
                plot_trace(sc, sc.trace(gains), tmp)
            written.append(path)
    _remove_stale_responses(out_dir, written)
    return written


def _remove_stale_responses(out_dir: str, written: list[str]) -> None:
    """A folder tuned into before keeps one set of files: drop the response plots of roads
    the earlier tune had and this one has not."""
    keep = {os.path.basename(p) for p in written}
    for name in os.listdir(out_dir):
        if name.startswith("response-") and name.endswith(".png") and name not in keep:
            os.unlink(os.path.join(out_dir, name))


def write_interrupted_tune(
    problem: TuningProblem,
    best: tuple[np.ndarray, float, int],
    optimizer: str,
    seed: int,
    out_dir: str,
) -> list[str]:
    """The best so far of an interrupted tune: best_gains.json and tune.json marked
    `"interrupted": true` (no plots: the process is about to end), as one set."""
    gains, cost, nfev = best
    best_gains = dict(zip(problem.gain_names, gains.tolist(), strict=True))
    sc = problem.scenarios[0]
    doc = {
        "interrupted": True,
        "plant": sc.plant,
        "preset": sc.preset,
        "roads": problem.roads,
        "controller": sc.controller.name,
        "optimizer": optimizer,
        "objective": problem.objective,
        "aggregate": problem.aggregate,
        "seed": seed,
        "best_gains": best_gains,
        "best_cost": cost,
        "nfev": nfev,
        "params": sc.params(),
    }
    paths = [os.path.join(out_dir, "best_gains.json"), os.path.join(out_dir, "tune.json")]
    with file_set(out_dir) as staged:
        staged.write_json(paths[0], best_gains)
        staged.write_json(paths[1], doc)
    return paths


@dataclass(frozen=True)
class DemoResult:
    """The demo's table (one row per road and controller), the PID gains and the plots."""

    rows: list[dict[str, Any]]
    pid_gains: dict[str, float]
    plots: list[str]


def write_demo(out_dir: str) -> DemoResult:
    """No ABS against the registry's hand-set PID on the derlsp-ao paper's three roads: the
    table's rows, and one comparison plot per road in `out_dir` (created if missing)."""
    from chassistune.controllers import catalogue
    from chassistune.plots.abs_wheel import plot_comparison
    from chassistune.scenarios.abs_wheel import PLANT

    os.makedirs(out_dir, exist_ok=True)
    pid = catalogue.get("abs-wheel", "pid").default_gains()
    rows, plots = [], []
    for road in PLANT.presets()[DEMO_PRESET].roads:
        runs = []
        for controller, gains in (("none", {}), ("pid", pid)):
            sc = PLANT.scenario(DEMO_PRESET, road, controller)
            tr = sc.trace(sc.gains_array(gains))
            runs.append((controller, tr))
            rows.append(
                {"road": road, "controller": controller, **{k: tr.metrics[k] for k in DEMO_METRICS}}
            )
        path = os.path.join(out_dir, f"abs-wheel-{road}.png")
        plot_comparison(
            sc,
            runs,
            path,
            title=f"abs-wheel, paper-derlsp-ao preset, {road}: "
            "no ABS vs PID (" + ", ".join(f"{k}={v:g}" for k, v in pid.items()) + ")",
        )
        plots.append(path)
    return DemoResult(rows, pid, plots)
