"""`chassistune tune PLANT ...`: tune a controller with an optimizer, with a progress bar."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import click

from chassistune._interrupt import on_interrupt
from chassistune.cli.choices import ChoicesCommand, ChoicesOption
from chassistune.cli.common import check_output_dir, echo_json, fmt
from chassistune.cli.options import ecu_option, param_option, preset_option, tire_option, with_tire
from chassistune.cli.robust_options import (
    echo_validation,
    robust_fields,
    robust_options,
    robust_or_nominal,
)
from chassistune.errors import InputError

if TYPE_CHECKING:
    from chassistune.tuning.run import Incumbent, Progress, TuneResult


@click.command("tune", cls=ChoicesCommand, arguments={"PLANT": "plants"})
@click.argument("plant", metavar="PLANT")
@preset_option
@click.option(
    "--road",
    "roads",
    multiple=True,
    cls=ChoicesOption,
    choices_of="roads",
    help="Road; repeat to tune one controller for several roads.",
)
@click.option(
    "--aggregate",
    default="mean",
    show_default=True,
    help="How costs on several roads (x --scenarios) combine: mean, max, cvar:ALPHA.",
)
@click.option(
    "--controller",
    default="pid",
    show_default=True,
    cls=ChoicesOption,
    choices_of="controllers",
    help="Controller whose gains are tuned.",
)
@click.option(
    "--optimizer",
    cls=ChoicesOption,
    choices_of="optimizers",
    help="Optimizer (`chassistune list optimizers`); required.",
)
@click.option("--pop", "pop_size", default=30, show_default=True, type=int, help="Population size.")
@click.option(
    "--iters",
    type=int,
    help="Iteration budget (default 100 unless --evals; with --evals too, the run "
    "stops at whichever comes first).",
)
@click.option("--evals", type=int, help="Evaluation budget (exact; at least one population).")
@click.option("--seed", default=0, show_default=True, type=int, help="Run seed.")
@ecu_option
@tire_option
@click.option(
    "--objective",
    cls=ChoicesOption,
    choices_of="objectives",
    help="What the tune minimizes (default: the plant's).",
)
@param_option
@click.option(
    "--test-road",
    "test_roads",
    multiple=True,
    metavar="ROAD",
    cls=ChoicesOption,
    choices_of="roads",
    help="Also report the tuned controller's metrics on ROAD (repeatable).",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@click.option("--out", "out_dir", help="Write best gains, history and plots into this folder.")
@robust_options
def tune_command(
    plant: str,
    preset: str | None,
    roads: tuple[str, ...],
    aggregate: str,
    controller: str,
    optimizer: str | None,
    pop_size: int,
    iters: int | None,
    evals: int | None,
    seed: int,
    objective: str | None,
    params: tuple[str, ...],
    test_roads: tuple[str, ...],
    as_json: bool,
    out_dir: str | None,
    ecu: str | None,
    tire: str | None,
    **robust: Any,
) -> None:
    """Tune the gains of a controller of PLANT with an optimizer.

    The box is the registry's tuning bounds (`chassistune list controllers`). The cost of every
    candidate is a closed-loop simulation; a whole population is simulated in one kernel call.
    Example: chassistune tune abs-wheel --road dry-concrete --controller pid --optimizer derlsp-ao
    """
    from chassistune.memory import check_fits, problem_bytes
    from chassistune.optimizers.base import check_covers_population
    from chassistune.optimizers.registry import get as get_optimizer
    from chassistune.optimizers.registry import make
    from chassistune.params import parse_assignments
    from chassistune.reports.outputs import write_tune_outputs
    from chassistune.scenarios.base import PENALTY
    from chassistune.tuning.problem import build_problem
    from chassistune.tuning.run import Incumbent, run_optimizer

    if optimizer is not None:
        get_optimizer(optimizer)
    for name, value in (("--iters", iters), ("--evals", evals), ("--pop", pop_size)):
        if value is not None and value < 1:
            raise InputError(name, f"must be a positive whole number, got {value}")
    if iters is None and evals is None:
        iters = 100
    check_output_dir(out_dir, "--out")
    values = parse_assignments(params, "params")
    if ecu:
        values["ecu"] = ecu
    with_tire(plant, tire, values)
    if tire is not None and robust.get("vary"):
        raise InputError("--tire", "not with --vary: the tire's curve is taken at the nominal load")
    if tire is not None and not roads:
        from chassistune.plants.mf_curve import TIRE_SURFACE

        roads = (TIRE_SURFACE,)
    problem = build_problem(
        plant, controller, preset, roads, objective, aggregate, values, None, seed
    )
    problem = robust_or_nominal(problem, aggregate, robust, values, seed)
    _check_test_roads(plant, preset, controller, values, seed, test_roads)
    if optimizer is None:  # reported once every given option has been checked
        raise InputError("--optimizer", "missing (chassistune list optimizers)")
    check_fits(problem_bytes(problem, pop_size), "--pop", f"a population of {pop_size:,}")
    make(optimizer, problem.bounds, pop_size, seed, max_iter=iters, max_evals=evals)  # checks
    check_covers_population(pop_size, evals)
    incumbent = Incumbent(problem)
    forget = on_interrupt(lambda: _save_interrupted(incumbent, optimizer, seed, out_dir))
    if as_json or not sys.stderr.isatty():
        result = run_optimizer(
            problem, optimizer, pop_size, iters, evals, seed, incumbent=incumbent
        )
    else:
        result = _with_progress(
            lambda cb: run_optimizer(
                problem, optimizer, pop_size, iters, evals, seed, cb, incumbent
            ),
            iters,
            evals,
        )
    forget()
    on_interrupt(lambda: _finished_before_interrupt(result.nfev, out_dir))
    written = write_tune_outputs(result, out_dir) if out_dir else []
    tested = result.test_on(test_roads, values)
    extra = robust_fields(result)
    if as_json:
        echo_json({**result.as_dict(), "test_metrics": tested, **extra})
    else:
        _print_result(result, plant, controller, optimizer, written, extra)
        for road, m in tested.items():
            click.echo(f"  test on {road}: " + _metric_line(m))
    for line in _warnings(result, controller):
        click.echo(f"chassistune: warning: {line}", err=True)
    if result.best_cost >= PENALTY:
        raise click.ClickException(
            f"no candidate of {result.nfev} could be scored (every one got the penalty "
            f"{PENALTY:g}: {_why_penalized(result)}); these gains are not a tuned controller"
        )


def _save_interrupted(
    incumbent: Incumbent, optimizer: str, seed: int, out_dir: str | None
) -> str | None:
    """The Ctrl-C hook: the best so far into `out_dir` (when a batch has been scored)."""
    best = incumbent.best
    if out_dir is None:
        return None
    if best is None:
        return f"no evaluation had finished: nothing written to {out_dir}"
    from chassistune.reports.outputs import write_interrupted_tune

    paths = write_interrupted_tune(incumbent.fun, best, optimizer, seed, out_dir)
    return f"best so far after {best[2]} evaluations (cost {best[1]:.6g}) in {paths[1]}"


def _finished_before_interrupt(nfev: int, out_dir: str | None) -> str:
    """The Ctrl-C hook once the optimizer has finished: the result exists, its files may not
    (they are written as one set: all of them or none)."""
    where = f"; its files in {out_dir} are all written or none is" if out_dir else ""
    return f"the tune had finished ({nfev} evaluations) and was being written out{where}"


def _warnings(result: TuneResult, controller: str) -> list[str]:
    """The tune's warnings: worse than the defaults, not converged in the step, an optimum
    the box plausibly cuts off."""
    lines = [result.worse_than_default(), *result.step_warnings()]
    for hit in result.gains_cut_off():
        lines.append(
            f"{controller} gain {hit.gain}: tuned to {hit.value:.6g}, at its bound "
            f"{hit.bound:g} of the registry's box (chassistune list controllers), and the cost "
            f"is lower past it ({hit.probe_cost:.6g} at {hit.gain}={hit.probe:g}): the best "
            "gains lie outside the box (a study's `bounds` table can widen it)"
        )
    return [line for line in lines if line]


def _why_penalized(result: TuneResult) -> str:
    status = {road: m.get("status") for road, m in result.metrics.items()}
    return ", ".join(f"{road}: {s}" for road, s in status.items() if s) or "unscored"


def _print_result(
    result: TuneResult,
    plant: str,
    controller: str,
    optimizer: str,
    written: list[str],
    extra: dict[str, Any],
) -> None:
    problem = result.problem
    click.echo(
        f"{optimizer} on {plant} {controller}, roads {', '.join(problem.roads)}, "
        f"objective {problem.objective}: best cost {fmt(result.best_cost)} after "
        f"{result.nfev} evaluations, {result.nit} iterations, {result.wall_time_s:.2f} s"
    )
    click.echo("best gains: " + ", ".join(f"{k}={v!r}" for k, v in result.best_gains.items()))
    click.echo(
        f"default gains: cost {fmt(result.default_cost)} with "
        + ", ".join(f"{k}={v:g}" for k, v in result.default_gains.items())
    )
    for road, m in result.metrics.items():
        click.echo(f"  {road}: " + _metric_line(m))
    echo_validation(extra)
    for path in written:
        click.echo(f"wrote {path}")


def _metric_line(m: dict[str, Any]) -> str:
    keys = [
        k
        for k in (
            "stop_distance_m",
            "bound_distance_m",
            "distance_ratio",
            "stop_time_s",
            "slip_itae",
            "objective_exact",
            "objective",
            "body_acc_rms",
            "status",
        )
        if k in m
    ]
    return ", ".join(f"{k}={fmt(m[k])}" for k in keys)


def _check_test_roads(
    plant: str,
    preset: str | None,
    controller: str,
    values: dict[str, str],
    seed: int,
    roads: tuple[str, ...],
) -> None:
    """Refuse an unknown --test-road before tuning."""
    from chassistune.scenarios.registry import get_plant

    for road in roads:
        try:
            get_plant(plant).scenario(preset, road, controller, values, seed)
        except InputError as exc:
            if exc.field == "road":
                raise InputError("--test-road", exc.problem) from None
            raise


def _with_progress(
    run: Callable[[Progress], TuneResult], iters: int | None, evals: int | None
) -> TuneResult:
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
    with Progress(
        TextColumn("tuning"),
        BarColumn(),
        TextColumn("{task.description}"),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    ) as bar:
        task = bar.add_task("", total=total)

        def update(nit: int, nfev: int, best: float) -> None:
            done = nfev if by_evals else nit
            bar.update(
                task,
                completed=min(done, total),
                description=f"it {nit}  evals {nfev}  best {best:.6g}",
            )

        return run(update)
