"""`chassistune bbob --optimizer NAME [--optimizer NAME ...] [--dim D ...] [--function F ...]
[--budget EVALS_PER_DIM] [--instances LIST] [--pop N] [--seed S] [--no-postprocess]
[--executor serial|process|dask] [--workers N] [--scheduler ADDRESS] --out DIR`:
registered optimizers on the COCO/BBOB suite (docs/bbob.md)."""

from __future__ import annotations

import contextlib
import sys
from pathlib import Path

import click

from chassistune.cli.choices import ChoicesOption
from chassistune.cli.common import check_output_dir
from chassistune.cli.options import executor_options
from chassistune.errors import InputError

DIMENSIONS = ("2", "3", "5", "10", "20")


def parse_instances(text: str) -> tuple[int, ...]:
    """Instance numbers from `1,2,5-8` (InputError naming `--instances`)."""
    out: list[int] = []
    for part in text.split(","):
        lo, dash, hi = part.strip().partition("-")
        try:
            first, last = int(lo), int(hi if dash else lo)
        except ValueError:
            raise InputError(
                "--instances", f"expected numbers and ranges like 1-5, got {text!r}"
            ) from None
        if not 1 <= first <= last <= 9999:
            raise InputError("--instances", f"expected instances in 1..9999, got {part.strip()!r}")
        out.extend(range(first, last + 1))
    if len(set(out)) != len(out):
        raise InputError("--instances", f"an instance is listed twice in {text!r}")
    return tuple(out)


@click.command("bbob")
@click.option(
    "--optimizer",
    "optimizers",
    required=True,
    multiple=True,
    cls=ChoicesOption,
    choices_of="optimizers",
    help="Optimizer name (repeatable; see `chassistune list optimizers`).",
)
@click.option(
    "--dim",
    "dims",
    multiple=True,
    type=click.Choice(DIMENSIONS),
    help="Dimension (repeatable; default 2, 3, 5, 10, 20).",
)
@click.option(
    "--function",
    "functions",
    multiple=True,
    type=click.IntRange(1, 24),
    help="BBOB function 1-24 (repeatable; default all 24).",
)
@click.option(
    "--budget",
    type=click.IntRange(min=1),
    default=1000,
    show_default=True,
    help="Evaluations per dimension of each run.",
)
@click.option(
    "--instances",
    metavar="LIST",
    help="Instances, e.g. 1-5,71-80 (default: the suite's current ones).",
)
@click.option(
    "--pop",
    type=click.IntRange(min=1),
    default=30,
    show_default=True,
    help="Population of every optimizer (CMA-ES: its first one).",
)
@click.option(
    "--seed",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="Root seed; run seeds are its children by instance.",
)
@click.option("--no-postprocess", is_flag=True, help="Write the COCO data folder, skip cocopp.")
@click.option(
    "--out",
    "out_dir",
    required=True,
    metavar="DIR",
    help="DIR/study.sqlite (the runs; an existing one is resumed), DIR/coco/, DIR/ppdata/.",
)
@executor_options
def bbob_command(
    optimizers: tuple[str, ...],
    dims: tuple[str, ...],
    functions: tuple[int, ...],
    budget: int,
    instances: str | None,
    pop: int,
    seed: int,
    no_postprocess: bool,
    out_dir: str,
    executor: str,
    scheduler: str | None,
    workers: int | None,
) -> None:
    """Run optimizers on BBOB through cocoex; write COCO's data folder and cocopp's ECDFs.

    Runs execute on --executor (serial, process or dask: the same numbers on each) and are
    recorded one by one in DIR/study.sqlite: kill the command at any moment and run it again
    to finish. Example (a quick look):
    chassistune bbob --optimizer cma-es --optimizer ao --dim 2 --dim 5 --budget 100
    --instances 1-3 --out bbob-quick
    """
    from chassistune.optimizers.base import check_covers_population
    from chassistune.optimizers.registry import make
    from chassistune.plots.coco_ecdf import PP_FOLDER, postprocess
    from chassistune.studies.bbob import (
        DIMENSIONS as ALL_DIMS,
    )
    from chassistune.studies.bbob import (
        FUNCTIONS,
        BBOBPlan,
        default_instances,
    )
    from chassistune.studies.bbob_runner import run_plan
    from chassistune.studies.coco_data import write_coco_data
    from chassistune.studies.executors import make_executor
    from chassistune.studies.runner import check_out_dir

    names = tuple(dict.fromkeys(o.lower() for o in optimizers))
    dimensions = tuple(sorted({int(d) for d in dims})) if dims else ALL_DIMS
    plan = BBOBPlan(
        name="bbob",
        optimizers=names,
        functions=tuple(sorted(set(functions))) if functions else FUNCTIONS,
        dimensions=dimensions,
        instances=parse_instances(instances) if instances else default_instances(),
        evals_per_dim=budget,
        pop_size=pop,
        root_seed=seed,
    )
    for name in names:
        make(name, [(-5.0, 5.0)] * 2, pop, 0, max_evals=budget * 2)  # --pop below its minimum
    try:
        check_covers_population(pop, budget * min(dimensions))
    except InputError as exc:
        raise InputError("--budget", f"{exc.problem} in dimension {min(dimensions)}") from None
    check_output_dir(out_dir, "--out")
    check_out_dir(out_dir)

    def progress(done: int, total: int) -> None:
        click.echo(f"\rbbob: {done}/{total} runs", nl=done == total, err=True)

    with make_executor(executor, workers, scheduler) as ex:
        ran = run_plan(plan, out_dir, ex, progress if sys.stderr.isatty() else None)
    folders = write_coco_data(out_dir, names)
    click.echo(f"{ran} runs done now, {len(list(plan.runs())) - ran} were stored already")
    for folder in folders:
        click.echo(f"COCO data: {folder}")
    if not no_postprocess:
        with contextlib.redirect_stdout(sys.stderr):
            index = postprocess(folders, Path(out_dir) / PP_FOLDER)
        click.echo(f"cocopp: {index}")
