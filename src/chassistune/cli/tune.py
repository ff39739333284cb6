"""`chassistune tune PLANT ...`: tune a controller with an optimizer, with a progress bar."""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import click

from chassistune.cli.common import echo_json, fmt
from chassistune.cli.robust_options import (
    echo_validation,
    robust_fields,
    robust_options,
    robust_or_nominal,
)
from chassistune.errors import InputError

if TYPE_CHECKING:
    from chassistune.tuning.tune import Progress, TuneResult


@click.command("tune")
@click.argument("plant", metavar="PLANT")
@click.option("--preset", help="Parameter preset (default: the plant's paper preset).")
@click.option("--road", "roads", multiple=True,
              help="Road; repeat to tune one controller for several roads.")
@click.option("--aggregate", default="mean", show_default=True,
              help="How costs on several roads (x --scenarios) combine: mean, max, cvar:ALPHA.")
@click.option("--controller", required=True, help="Controller whose gains are tuned.")
@click.option("--optimizer", required=True, help="Optimizer (`chassistune list optimizers`).")
@click.option("--pop", "pop_size", default=30, show_default=True, type=int,
              help="Population size.")
@click.option("--iters", type=int, help="Iteration budget (default 100 unless --evals).")
@click.option("--evals", type=int, help="Evaluation budget (exact).")
@click.option("--seed", default=0, show_default=True, type=int, help="Run seed.")
@click.option("--ecu", type=click.Choice(["ideal", "realistic"]),
              help="abs-wheel: ideal controller or the realistic ECU (docs/ecu.md).")
@click.option("--objective", help="Objective (ABS: itae, iae, ise, distance, time).")
@click.option("--param", "params", multiple=True, metavar="NAME=VALUE",
              help="Override a plant, road, solver or controller parameter (repeatable).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@click.option("--out", "out_dir", help="Write best gains, history and plots into this folder.")
@robust_options
def tune_command(plant: str, preset: str | None, roads: tuple[str, ...], aggregate: str,
                 controller: str, optimizer: str, pop_size: int, iters: int | None,
                 evals: int | None, seed: int, objective: str | None, params: tuple[str, ...],
                 as_json: bool, out_dir: str | None, ecu: str | None, **robust: Any) -> None:
    """Tune the gains of a controller of PLANT with an optimizer.

    The box is the registry's tuning bounds (`chassistune list controllers`). The cost of every
    candidate is a closed-loop simulation; a whole population is simulated in one kernel call.
    Example: chassistune tune abs-wheel --road dry-concrete --controller pid --optimizer derlsp-ao
    """
    from chassistune.optimizers.registry import get as get_optimizer
    from chassistune.params import parse_assignments
    from chassistune.reports.outputs import write_tune_outputs
    from chassistune.tuning.problem import build_problem
    from chassistune.tuning.tune import run_optimizer

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
    values = parse_assignments(params, "--param")
    if ecu:
        values["ecu"] = ecu
    problem = build_problem(plant, controller, preset, roads, objective, aggregate, values, None,
                            seed)
    problem = robust_or_nominal(problem, aggregate, robust, values, seed)
    if as_json:
        result = run_optimizer(problem, optimizer, pop_size, iters, evals, seed)
    else:
        result = _with_progress(lambda cb: run_optimizer(problem, optimizer, pop_size, iters,
                                                         evals, seed, cb), iters, evals)
    written = write_tune_outputs(result, out_dir) if out_dir else []
    extra = robust_fields(result)
    if as_json:
        echo_json({**result.as_dict(), **extra})
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
    echo_validation(extra)
    for path in written:
        click.echo(f"wrote {path}")


def _with_progress(run: Callable[[Progress], TuneResult],
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
