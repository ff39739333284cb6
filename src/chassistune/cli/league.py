"""`chassistune league --out DIR [--plant P ...] [--optimizer NAME] [--quick] [--seeds N]
[--pop N] [--evals N] [--seed S] [--executor serial|process|dask]`: every ABS law of the
registry tuned alike on each ABS plant and ranked on held-out cases (docs/league.md)."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import click

from chassistune._interrupt import on_interrupt
from chassistune.cli.choices import ChoicesOption
from chassistune.cli.common import check_study_folder
from chassistune.cli.options import executor_options
from chassistune.league.cases import KNOWLEDGE

LEAGUE_PLANTS = ("abs-wheel", "abs-vehicle")


@click.command("league")
@click.option(
    "--out",
    "out_dir",
    required=True,
    metavar="DIR",
    help="DIR/study.sqlite (the tuning runs; an existing league is resumed), DIR/league.md, "
    "DIR/league_scores.csv and the figures.",
)
@click.option(
    "--plant",
    "plants",
    multiple=True,
    type=click.Choice(LEAGUE_PLANTS),
    help="Plant (repeatable; default both).",
)
@click.option(
    "--optimizer",
    default="cma-es",
    show_default=True,
    cls=ChoicesOption,
    choices_of="optimizers",
    help="The one optimizer every law is tuned with.",
)
@click.option(
    "--quick",
    is_flag=True,
    help="A reduced budget (2 seeds, 18 evaluations, population 6): a look, not a result.",
)
@click.option("--seeds", type=click.IntRange(1, 1000), help="Seeds per law (full: 10).")
@click.option("--pop", type=click.IntRange(min=1), help="Population (full: 20).")
@click.option("--evals", type=click.IntRange(min=1), help="Evaluations per run (full: 2000).")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Root seed.")
@click.option(
    "--road-knowledge",
    type=click.Choice(KNOWLEDGE),
    default="fixed",
    show_default=True,
    help="What a law that regulates a target slip is told of the road: fixed (one target for "
    "every road, tuned with its gains; no vehicle knows its road's peak) or oracle (the road's "
    "optimal slip, the papers' setting).",
)
@executor_options
def league_command(
    out_dir: str,
    plants: tuple[str, ...],
    optimizer: str,
    quick: bool,
    seeds: int | None,
    pop: int | None,
    evals: int | None,
    seed: int,
    road_knowledge: str,
    executor: str,
    scheduler: str | None,
    workers: int | None,
) -> None:
    """Tune every ABS law alike per plant, score it on held-out cases, rank the laws.

    Each law of the registry that runs on the plant is tuned with the same optimizer and
    evaluation budget on the plant's training roads together (the mean stop distance over the
    adhesion bound), on the single wheel in the realistic ECU mode and on the 7-DOF vehicle in
    the ideal mode (it has no ECU mode). Each tuned law is then scored on held-out cases:
    Burckhardt snow and cobblestone, mass +-20 % and sensor noise (single wheel); mu-jumps both
    ways, split-mu with the driver steering and mass +-20 % (vehicle). Runs are recorded one by
    one in DIR/study.sqlite: kill the command and run it again to finish. Example:
    chassistune league --quick --out league-quick
    """
    from dataclasses import replace

    from chassistune.league.page import write_page
    from chassistune.league.plan import FULL, QUICK, Setting, plan
    from chassistune.league.score import score_league, tuned_laws
    from chassistune.studies.executors import make_executor
    from chassistune.studies.runner import run_study

    budget = QUICK if quick else FULL
    budget = replace(
        budget,
        seeds=seeds or budget.seeds,
        pop_size=pop or budget.pop_size,
        evaluations=evals or budget.evaluations,
    )
    setting = Setting(plants or LEAGUE_PLANTS, optimizer.lower(), budget, seed, road_knowledge)
    league_plan = plan(setting)
    check_study_folder(out_dir, executor)
    forget = on_interrupt(
        lambda: f"the finished runs are stored in {out_dir}; run the same command to resume"
    )
    start = time.perf_counter()
    with make_executor(executor, workers, scheduler) as ex:
        outcome = run_study(league_plan, out_dir, ex, progress=_progress)
    forget()
    if outcome.failed:
        click.echo(
            f"chassistune: {outcome.failed} tuning runs failed: their errors are in "
            f"`chassistune study report {out_dir}`",
            err=True,
        )
        sys.exit(1)
    tuned = list(tuned_laws(out_dir, setting))
    scores = score_league(out_dir, setting)
    page = write_page(Path(out_dir), setting, scores, tuned, sum(t.run_time_s for t in tuned))
    click.echo(
        f"league: {outcome.total} tuning runs ({outcome.skipped} stored already), "
        f"{len(scores)} scored cases, {time.perf_counter() - start:.1f} s; page {page}"
    )


def _progress(done: int, failed: int, total: int) -> None:
    if sys.stderr.isatty():
        click.echo(f"\rleague: {done}/{total} tuning runs", nl=done == total, err=True)
