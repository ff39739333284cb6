"""`chassistune transfer --from DIR --out DIR [--quick] [--source STUDY:CELL ...] [--car CAR ...]
[--seeds N] [--pop N] [--evals N] [--executor serial|process|dask]`: the papers' tuned ABS
controllers carried to the real cars, then re-tuned there (docs/transfer.md)."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from chassistune.cli.common import check_output_dir, check_study_folder
from chassistune.cli.options import executor_options
from chassistune.plants.cars import CARS

SOURCE_KEYS = (
    "derlsp-ao-abs:pid-100kg",
    "fuzzy-immune-abs:pid",
    "fuzzy-immune-abs:fuzzy-pid",
    "fuzzy-immune-abs:fuzzy-immune-pid",
    "deffao-vehicle-abs:vehicle-fuzzy-pid",
)
"""`transfer.cells.SOURCES` by key (the CLI stays light at import; a test checks they agree)."""


@click.command("transfer")
@click.option(
    "--from",
    "from_dir",
    required=True,
    metavar="DIR",
    help="A reproduction's output folder: the tuned gains are read from DIR/studies/ (make one "
    "with `chassistune reproduce all --quick --out DIR`; a full reproduction's stores are "
    "preferred where both exist).",
)
@click.option(
    "--out",
    "out_dir",
    required=True,
    metavar="DIR",
    help="DIR/retune/ (the re-tuning studies; an existing one is resumed), DIR/transfer.md, "
    "DIR/transfer_scores.csv and a heatmap per source.",
)
@click.option(
    "--quick",
    is_flag=True,
    help="Re-tune at the reproduction's quick budget (each study's [quick] table: derlsp-ao-abs "
    "2 seeds, population 8, 5 iterations; fuzzy-immune-abs and deffao-vehicle-abs 1 seed, "
    "population 6, 3 iterations). Without it: the full budget of each study.",
)
@click.option(
    "--source",
    "sources",
    multiple=True,
    type=click.Choice(SOURCE_KEYS),
    help="A paper's tuned controller, STUDY:CELL (repeatable; default all five).",
)
@click.option(
    "--car",
    "cars",
    multiple=True,
    type=click.Choice(CARS),
    help="A real car (repeatable; default all three).",
)
@click.option("--seeds", type=click.IntRange(1, 1000), help="Seeds per re-tuning (override).")
@click.option("--pop", type=click.IntRange(min=1), help="Population (override).")
@click.option("--evals", type=click.IntRange(min=1), help="Evaluations per run (override).")
@executor_options
def transfer_command(
    from_dir: str,
    out_dir: str,
    quick: bool,
    sources: tuple[str, ...],
    cars: tuple[str, ...],
    seeds: int | None,
    pop: int | None,
    evals: int | None,
    executor: str,
    scheduler: str | None,
    workers: int | None,
) -> None:
    """Carry the papers' tuned ABS controllers to the real cars; re-tune them there.

    Each tuned controller of the reproduction (derlsp-ao-abs's PID; fuzzy-immune-abs's PID,
    fuzzy PID and fuzzy immune PID; deffao-vehicle-abs's vehicle fuzzy PID: the median run of
    the paper's optimizer) runs with its gains unchanged on its paper plant and on each real car
    (ford-escort, bmw-320i, vw-vanagon: a front wheel of the car on the single wheel, the car on
    the 7-DOF vehicle), on the roads it was tuned on, with the road's tire, CommonRoad's PAC2002
    Magic Formula tire and that tire with the lagged slip, in the ideal and the realistic ECU. A
    cell no kernel runs yet is listed as `not available` with what is missing. Then each
    controller is re-tuned on every runnable cell (its paper's optimizer, objective and roads)
    and scored again: stop distance over the adhesion bound, R13-H utilisation, locked time,
    split-mu yaw. Runs are recorded one by one in DIR/retune/: kill the command and run it again
    to finish. Example (docs/transfer.md):

    \b
    chassistune reproduce all --quick --out repro
    chassistune transfer --quick --from repro --out transfer-quick
    """
    from chassistune.studies.executors import make_executor
    from chassistune.transfer.plan import Setting, check_sources, plans, source_folders
    from chassistune.transfer.run import RETUNE, run_transfer

    setting = Setting(check_sources(sources), cars or CARS, quick, seeds, pop, evals)
    source_folders(from_dir, setting)
    check_output_dir(out_dir, "--out")
    for plan in plans(setting).values():
        folder = Path(out_dir) / RETUNE / plan.config.study.name
        if folder.exists():
            check_study_folder(str(folder), executor)
    with make_executor(executor, workers, scheduler) as ex:
        outcome = run_transfer(setting, from_dir, Path(out_dir), ex)
    if outcome.failed:
        click.echo(
            f"chassistune: {outcome.failed} re-tuning runs failed: their errors are in "
            f"`chassistune study report {out_dir}/retune/<study>`",
            err=True,
        )
        sys.exit(1)
    click.echo(
        f"transfer: {outcome.total} re-tuning runs ({outcome.skipped} stored already), "
        f"{outcome.rows} rows, {outcome.wall_time_s:.1f} s; page {outcome.page}"
    )
