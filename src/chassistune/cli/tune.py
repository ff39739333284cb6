"""`chassistune tune PLANT ...`: tune a controller with an optimizer, with a progress bar."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Callable

import click
import numpy as np

from chassistune.cli.common import echo_json, fmt, jsonable
from chassistune.cli.main import cli
from chassistune.errors import InputError
from chassistune.params import parse_assignments
from chassistune.tuning.problem import build_problem
from chassistune.tuning.tune import TuneResult, run_optimizer


def _write_atomic(path: str, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(path)))
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def write_outputs(result: TuneResult, out_dir: str) -> list[str]:
    """best_gains.json, tune.json, history.csv, convergence.png and one response plot per road."""
    from chassistune.plots.convergence import plot_convergence
    from chassistune.plots.registry import plot_trace

    os.makedirs(out_dir, exist_ok=True)
    written = []
    path = os.path.join(out_dir, "best_gains.json")
    _write_atomic(path, json.dumps(jsonable(result.best_gains), indent=1) + "\n")
    written.append(path)
    path = os.path.join(out_dir, "tune.json")
    _write_atomic(path, json.dumps(jsonable(result.as_dict()), indent=1) + "\n")
    written.append(path)
    path = os.path.join(out_dir, "history.csv")
    rows = "\n".join(f"{i + 1},{n},{c!r}" for i, (n, c) in
                     enumerate(zip(result.history_nfev, result.history, strict=True)))
    _write_atomic(path, "iteration,nfev,best_cost\n" + rows + "\n")
    written.append(path)
    path = os.path.join(out_dir, "convergence.png")
    first = result.problem.scenarios[0]
    plot_convergence({result.optimizer: [(result.history_nfev, result.history)]}, path,
                     title=f"{first.plant} {first.controller.name} on "
                     f"{', '.join(result.problem.roads)}: {result.problem.objective}")
    written.append(path)
    gains = np.array([result.best_gains[n] for n in result.problem.gain_names])
    for sc in result.problem.scenarios:
        path = os.path.join(out_dir, f"response-{sc.road}.png")
        plot_trace(sc, sc.trace(gains), path)
        written.append(path)
    return written


@cli.command("tune")
@click.argument("plant", metavar="PLANT")
@click.option("--preset", help="Parameter preset (default: the plant's paper preset).")
@click.option("--road", "roads", multiple=True,
              help="Road; repeat to tune one controller for several roads.")
@click.option("--aggregate", type=click.Choice(["mean", "max"]), default="mean",
              show_default=True, help="How costs on several roads combine.")
@click.option("--controller", required=True, help="Controller whose gains are tuned.")
@click.option("--optimizer", required=True, help="Optimizer (`chassistune list optimizers`).")
@click.option("--pop", "pop_size", default=30, show_default=True, type=int,
              help="Population size.")
@click.option("--iters", type=int, help="Iteration budget (default 100 unless --evals).")
@click.option("--evals", type=int, help="Evaluation budget (exact).")
@click.option("--seed", default=0, show_default=True, type=int, help="Run seed.")
@click.option("--objective", help="Objective (ABS: itae, iae, ise, distance, time).")
@click.option("--param", "params", multiple=True, metavar="NAME=VALUE",
              help="Override a plant, road, solver or controller parameter (repeatable).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@click.option("--out", "out_dir", help="Write best gains, history and plots into this folder.")
def tune_command(plant: str, preset: str | None, roads: tuple[str, ...], aggregate: str,
                 controller: str, optimizer: str, pop_size: int, iters: int | None,
                 evals: int | None, seed: int, objective: str | None, params: tuple[str, ...],
                 as_json: bool, out_dir: str | None) -> None:
    """Tune the gains of a controller of PLANT with an optimizer.

    The box is the registry's tuning bounds (`chassistune list controllers`). The cost of every
    candidate is a closed-loop simulation; a whole population is simulated in one kernel call.
    Example: chassistune tune abs-wheel --road dry-concrete --controller pid --optimizer derlsp-ao
    """
    from chassistune.optimizers.registry import get as get_optimizer

    get_optimizer(optimizer)
    for name, value in (("--iters", iters), ("--evals", evals), ("--pop", pop_size)):
        if value is not None and value < 1:
            raise InputError(name, f"must be a positive whole number, got {value}")
    if iters is None and evals is None:
        iters = 100
    if out_dir is not None:
        parent = os.path.dirname(os.path.abspath(out_dir))
        if not os.path.isdir(parent):
            raise InputError("--out", f"folder {parent!r} does not exist")
    problem = build_problem(plant, controller, preset, roads, objective, aggregate,
                            parse_assignments(params, "--param"), None, seed)
    if as_json:
        result = run_optimizer(problem, optimizer, pop_size, iters, evals, seed)
    else:
        result = _with_progress(lambda cb: run_optimizer(problem, optimizer, pop_size, iters,
                                                         evals, seed, cb), iters, evals)
    written = write_outputs(result, out_dir) if out_dir else []
    if as_json:
        echo_json(result.as_dict())
        return
    click.echo(f"{optimizer} on {plant} {controller}, roads {', '.join(problem.roads)}, "
               f"objective {problem.objective}: best cost {fmt(result.best_cost)} after "
               f"{result.nfev} evaluations, {result.nit} iterations, {result.wall_time_s:.2f} s")
    click.echo("best gains: " + ", ".join(f"{k}={v:.6g}" for k, v in result.best_gains.items()))
    for road, m in result.metrics.items():
        keys = [k for k in ("stop_distance_m", "bound_distance_m", "distance_ratio",
                            "stop_time_s", "slip_itae", "objective_exact", "objective",
                            "body_acc_rms") if k in m]
        click.echo(f"  {road}: " + ", ".join(f"{k}={fmt(m[k])}" for k in keys))
    for path in written:
        click.echo(f"wrote {path}")


def _with_progress(run: Callable[[Callable[[int, int, float], None]], TuneResult],
                   iters: int | None, evals: int | None) -> TuneResult:
    """Run with a rich progress bar on stderr (iterations or evaluations, best cost, ETA)."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    total = float(evals) if evals is not None else float(iters or 1)
    by_evals = evals is not None
    with Progress(TextColumn("tuning"), BarColumn(), TextColumn("{task.description}"),
                  TimeElapsedColumn(), TimeRemainingColumn(), console=Console(stderr=True),
                  transient=True) as bar:
        task = bar.add_task("", total=total)

        def update(nit: int, nfev: int, best: float) -> None:
            done = nfev if by_evals else nit
            bar.update(task, completed=min(done, total),
                       description=f"it {nit}  evals {nfev}  best {best:.6g}")

        return run(update)
