"""`chassistune reproduce PAPER|all`: rerun the papers' studies and write one report."""

from __future__ import annotations

import click

from chassistune.cli.common import check_output_dir
from chassistune.cli.options import executor_options
from chassistune.papers.keys import PAPER_KEYS

PAPER_CHOICES = [*PAPER_KEYS, "all"]


@click.command("reproduce")
@click.argument("paper", type=click.Choice(PAPER_CHOICES), metavar="PAPER")
@click.option(
    "--quick",
    is_flag=True,
    help="Reduced budgets and seeds (each config's [quick] table): about a minute.",
)
@click.option(
    "--out",
    "out_dir",
    required=True,
    metavar="DIR",
    help="Report folder: DIR/report.html, tables/, figures/, verdicts.csv, studies/ "
    "(an existing one is resumed).",
)
@executor_options
@click.option(
    "--interactive",
    is_flag=True,
    help="Also write DIR/report_interactive.html (plotly, self-contained; needs the "
    "extra chassistune[interactive]).",
)
def reproduce_command(
    paper: str,
    quick: bool,
    out_dir: str,
    executor: str,
    scheduler: str | None,
    workers: int | None,
    interactive: bool,
) -> None:
    """Reproduce PAPER (derlsp-ao-abs, iabc-suspension, deffao-vehicle-abs, fuzzy-immune-abs)
    or all four: the shipped study configs run through the study machinery (resumable after a
    kill), then one report with the papers' numbers beside ours and a verdict per claim.
    Example: chassistune reproduce all --quick --out reproduce-output
    """
    check_output_dir(out_dir, "--out")
    from chassistune.papers.report import counts_text
    from chassistune.papers.reproduce import check_reproduction, reproduce
    from chassistune.studies.executors import check_dask, make_executor

    if interactive:
        from chassistune.reports.interactive import require_plotly

        require_plotly()
    check_reproduction(paper, quick, out_dir)
    if executor == "dask":
        check_dask()
    with make_executor(executor, workers, scheduler) as ex:
        outcome = reproduce(
            paper, quick, out_dir, ex, lambda line: click.echo(line, err=True), interactive
        )
    click.echo(counts_text([v for s in outcome.sections for v in s.verdicts]))
    click.echo(
        f"report: {outcome.files.html} (wall time {outcome.wall_time_s:.1f} s; "
        f"verdicts in {outcome.files.verdicts})"
    )
    if outcome.files.interactive is not None:
        click.echo(f"interactive report: {outcome.files.interactive}")
