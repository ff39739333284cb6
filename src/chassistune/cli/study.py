"""`chassistune study run|report|export`: studies over scenarios x optimizers x seeds."""

from __future__ import annotations

import click

from chassistune.errors import InputError


@click.group("study")
def study_group() -> None:
    """Run a study from a TOML config, report on it, export its runs (docs/studies.md)."""


@study_group.command("run")
@click.argument("config", metavar="CONFIG.toml")
@click.option("--out", "out_dir", required=True, metavar="DIR",
              help="Study folder: DIR/study.sqlite (created; an existing study is resumed).")
@click.option("--executor", default="serial", show_default=True,
              type=click.Choice(["serial", "process", "dask"]), help="Where the runs execute.")
@click.option("--scheduler", metavar="ADDRESS",
              help="Dask scheduler address (default: a LocalCluster on loopback).")
@click.option("--workers", type=int, help="Worker processes (default: the cores).")
@click.option("--retry-failed", is_flag=True, help="Redo runs recorded as failed.")
def run_command(config: str, out_dir: str, executor: str, scheduler: str | None,
                workers: int | None, retry_failed: bool) -> None:
    """Run every run of CONFIG.toml that DIR does not hold yet.

    Each finished run is one transaction in DIR/study.sqlite: kill the study at any moment
    and run the same command again to finish it. Example:
    chassistune study run examples/studies/abs-dry-pid.toml --out abs-dry-pid
    """
    from chassistune.studies.executors import check_dask, make_executor
    from chassistune.studies.runner import check_out_dir, pending_runs, rich_progress, run_study
    from chassistune.studies.spec import load_plan

    plan = load_plan(config)
    check_out_dir(out_dir)
    pending_runs(plan, out_dir, retry_failed)  # refuses a folder made from another config
    if executor == "dask":
        check_dask()
    with make_executor(executor, workers, scheduler) as ex:
        outcome = rich_progress(
            lambda progress: run_study(plan, out_dir, ex, retry_failed, progress),
            f"study {plan.config.study.name}")
    click.echo(f"study {plan.config.study.name}: {outcome.total} runs, {outcome.skipped} "
               f"already done, {outcome.completed} completed and {outcome.failed} failed now "
               f"({executor}, {outcome.wall_time_s:.2f} s); store {outcome.store}")
    if outcome.failed:
        click.echo(f"chassistune: {outcome.failed} runs failed: their errors are in the store "
                   "and in `chassistune study report`", err=True)


@study_group.command("report")
@click.argument("study_dir", metavar="DIR")
@click.option("--reference", metavar="OPTIMIZER",
              help="Optimizer the others are compared with (default: the first of the config).")
@click.option("--interactive", is_flag=True,
              help="Also write DIR/report_interactive.html (plotly; needs the [interactive] "
                   "extra).")
def report_command(study_dir: str, reference: str | None, interactive: bool) -> None:
    """Statistics, tables and figures of a study: DIR/report.html, CSV and PNG files."""
    from chassistune.reports.build import build_report

    if interactive:
        from chassistune.reports.interactive import build_interactive, require_plotly

        require_plotly()  # refused before anything is written
    written = build_report(study_dir, reference)
    click.echo(f"wrote {written.html} ({len(written.tables)} tables, {len(written.figures)} "
               f"figures in {written.folder})")
    if interactive:
        click.echo(f"wrote {build_interactive(study_dir, reference).html}")


@study_group.command("export")
@click.argument("study_dir", metavar="DIR")
@click.option("--format", "fmt", required=True, type=click.Choice(["csv", "parquet"]),
              help="File format.")
@click.option("--output", required=True, metavar="FILE", help="File to write.")
def export_command(study_dir: str, fmt: str, output: str) -> None:
    """One row per run: scenario, plant, road, controller, optimizer, seed, status, cost, gains."""
    from chassistune.cli.common import check_output_file
    from chassistune.reports.tables import runs_table, write_table
    from chassistune.studies.store import open_study

    check_output_file(output, "--output")
    with open_study(study_dir) as store:
        table = runs_table(list(store.records()))
    if table.empty:
        raise InputError("DIR", f"{study_dir!r} holds no finished runs yet")
    write_table(table, output, fmt)
    click.echo(f"wrote {output} ({len(table)} runs, {len(table.columns)} columns)")
