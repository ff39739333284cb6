"""`chassistune study run|report|export`: studies over scenarios x optimizers x seeds."""

from __future__ import annotations

import os
import sys

import click

from chassistune._interrupt import on_interrupt
from chassistune.cli.common import check_output_dir, check_output_file, check_study_folder
from chassistune.cli.options import executor_options
from chassistune.errors import InputError


@click.group("study")
def study_group() -> None:
    """Run a study from a TOML config, report on it, export its runs (docs/studies.md)."""


@study_group.command("run")
@click.argument("config", metavar="CONFIG.toml")
@click.option(
    "--out",
    "out_dir",
    required=True,
    metavar="DIR",
    help="Study folder: DIR/study.sqlite (created; an existing study is resumed).",
)
@executor_options
@click.option("--retry-failed", is_flag=True, help="Redo runs recorded as failed.")
def run_command(
    config: str,
    out_dir: str,
    executor: str,
    scheduler: str | None,
    workers: int | None,
    retry_failed: bool,
) -> None:
    """Run every run of CONFIG.toml that DIR does not hold yet.

    Each finished run is one transaction in DIR/study.sqlite: kill the study at any moment
    and run the same command again to finish it. Example:
    chassistune study run examples/studies/abs-dry-pid.toml --out abs-dry-pid
    """
    from chassistune.studies.executors import make_executor
    from chassistune.studies.progress import with_progress
    from chassistune.studies.runner import Progress, pending_runs, run_study
    from chassistune.studies.spec import load_plan

    plan = load_plan(config)
    check_study_folder(out_dir, executor)
    stored = [len(plan.runs) - len(pending_runs(plan, out_dir, retry_failed)), len(plan.runs)]

    def count(progress: Progress) -> Progress:
        def update(done: int, failed: int, total: int) -> None:
            stored[:] = [done, total]
            progress(done, failed, total)

        return update

    forget = on_interrupt(
        lambda: (
            f"{stored[0]} of {stored[1]} runs are stored in {out_dir}; "
            "run the same command to resume"
        )
    )
    with make_executor(executor, workers, scheduler) as ex:
        outcome = with_progress(
            lambda progress: run_study(
                plan, out_dir, ex, retry_failed, count(progress), _stderr_line
            ),
            f"study {plan.config.study.name}",
            _stderr_line,
        )
    forget()
    click.echo(
        f"study {plan.config.study.name}: {outcome.total} runs, {outcome.skipped} "
        f"already done, {outcome.completed} completed and {outcome.failed} failed now "
        f"({executor}, {outcome.wall_time_s:.2f} s); store {outcome.store}"
    )
    if not outcome.completed_in_study:
        click.echo(
            f"chassistune: every run of study {plan.config.study.name} failed: their errors "
            "are in the store and in `chassistune study export`",
            err=True,
        )
        sys.exit(1)
    if outcome.failed:
        click.echo(
            f"chassistune: {outcome.failed} runs failed: their errors are in the store "
            "and in `chassistune study report`",
            err=True,
        )
    _warn_unequal_budgets(out_dir)


def _stderr_line(text: str) -> None:
    click.echo(f"chassistune: {text}", err=True)


def _warn_unequal_budgets(study_dir: str) -> None:
    """One stderr line per scenario whose optimizers spent unequal evaluations (> 5 %)."""
    from chassistune.reports.tables import budget_warnings, load_study
    from chassistune.studies.store import open_study

    with open_study(study_dir) as store:
        data = load_study(store)
    for line in budget_warnings(data):
        click.echo(f"chassistune: warning: {line}", err=True)


@study_group.command("report")
@click.argument("study_dir", metavar="DIR")
@click.option(
    "--reference",
    metavar="OPTIMIZER",
    help="Optimizer the others are compared with (default: the first of the config).",
)
@click.option(
    "--interactive",
    is_flag=True,
    help="Also write DIR/report_interactive.html (plotly; needs the [interactive] extra).",
)
def report_command(study_dir: str, reference: str | None, interactive: bool) -> None:
    """Statistics, tables and figures of a study: DIR/report.html, CSV and PNG files."""
    check_output_dir(study_dir, "DIR")
    from chassistune.reports.build import build_report

    if interactive:
        from chassistune.reports.interactive import build_interactive, require_plotly

        require_plotly()  # refused before anything is written
    written = build_report(study_dir, reference)
    _warn_unequal_budgets(study_dir)
    click.echo(
        f"wrote {written.html} ({len(written.tables)} tables, {len(written.figures)} "
        f"figures in {written.folder})"
    )
    if interactive:
        click.echo(f"wrote {build_interactive(study_dir, reference).html}")


@study_group.command("status")
@click.argument("study_dir", metavar="DIR")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
def status_command(study_dir: str, as_json: bool) -> None:
    """What a study folder holds: runs completed, failed and missing, and its config."""
    from chassistune.cli.common import echo_json
    from chassistune.studies.status import study_status

    st = study_status(study_dir)
    b = st.config.budget
    budget = {"pop_size": b.pop_size, "iterations": b.iterations, "evaluations": b.evaluations}
    if as_json:
        echo_json(
            {
                "study": st.name,
                "total": st.total,
                "completed": st.completed,
                "failed": st.failed,
                "missing": st.missing,
                "scenarios": st.scenarios,
                "optimizers": st.optimizers,
                "seeds": len(st.config.study.seeds),
                "budget": budget,
                "running_pid": st.running_pid,
                "damaged": [{"key": d.key, "problem": d.problem} for d in st.damaged],
                "other_config_runs": st.others,
                "kept_unrecorded": st.kept,
            }
        )
        return
    click.echo(
        f"study {st.name}: {st.total} runs, {st.completed} completed, {st.failed} "
        f"failed, {st.missing} missing"
        + (f"; running now (process {st.running_pid})" if st.running_pid else "")
    )
    click.echo(f"  scenarios: {', '.join(st.scenarios)}")
    click.echo(f"  optimizers: {', '.join(st.optimizers)}; seeds: {len(st.config.study.seeds)}")
    click.echo("  budget: " + ", ".join(f"{k} {v}" for k, v in budget.items() if v is not None))
    for d in st.damaged:
        click.echo(f"  damaged: run {d.key!r} does not read back ({d.problem})")
    if st.kept:
        runs = "1 finished run waits" if st.kept == 1 else f"{st.kept} finished runs wait"
        click.echo(
            f"  {runs} in {os.path.join(study_dir, 'unrecorded')} (the store was locked): the "
            "next `study run` stores them"
        )
    if st.others:
        click.echo(
            f"  {st.others} stored runs of an earlier config (other scenarios, optimizers or "
            "seeds) are not part of the study"
        )
    if st.missing and not st.running_pid and not st.damaged:
        click.echo(
            "  `chassistune study run CONFIG.toml --out DIR` with the same config finishes it"
        )


EXPORT_SUFFIXES = {".csv": "csv", ".parquet": "parquet"}


def export_format(output: str, fmt: str | None) -> str:
    """The export format: --format if given, else from the file name; a mismatch is refused;
    `-` (stdout) is CSV."""
    if output == "-":
        if fmt not in (None, "csv"):
            raise InputError("--output", f"stdout takes csv, not {fmt}")
        return "csv"
    suffix = os.path.splitext(output)[1].lower()
    implied = EXPORT_SUFFIXES.get(suffix)
    if fmt is None:
        if implied is None:
            raise InputError(
                "--output",
                f"cannot tell the format from {output!r}: name it "
                ".csv or .parquet, or give --format",
            )
        return implied
    if implied is not None and implied != fmt:
        raise InputError("--format", f"{fmt} does not match the file name {output!r}")
    return fmt


@study_group.command("export")
@click.argument("study_dir", metavar="DIR")
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["csv", "parquet"]),
    help="File format (default: from the --output suffix).",
)
@click.option(
    "--output",
    required=True,
    metavar="FILE|-",
    help="File to write (.csv or .parquet); - writes CSV to stdout.",
)
def export_command(study_dir: str, fmt: str | None, output: str) -> None:
    """One row per run: scenario, plant, road, controller, optimizer, seed, status, cost, gains."""
    from chassistune.reports.tables import runs_table, write_table
    from chassistune.studies.store import open_study

    fmt = export_format(output, fmt)
    check_output_file(output, "--output", stdout_ok=True)
    with open_study(study_dir) as store:
        table = runs_table(list(store.records()))
    if table.empty:
        raise InputError("DIR", f"{study_dir!r} holds no finished runs yet")
    if output == "-":
        click.echo(table.to_csv(index=False), nl=False)
        return
    write_table(table, output, fmt)
    click.echo(f"wrote {output} ({len(table)} runs, {len(table.columns)} columns)")
