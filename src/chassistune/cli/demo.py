"""`chassistune demo` (`make demo`): a quick look at the single-wheel ABS on three roads.

Simulates the three roads of Tian et al. (derlsp-ao-abs: dry concrete, wet asphalt, ice)
without ABS and with a well-set PID, prints a table (stop time, distance, bound, ratio to
bound) and writes the plots (`reports.outputs.write_demo`).
"""

from __future__ import annotations

import click

from chassistune.cli.common import check_output_dir, echo_json


@click.command("demo")
@click.option(
    "--out",
    "out_dir",
    default="demo-output",
    show_default=True,
    help="Folder for the plots (created if missing).",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
def demo_command(out_dir: str, as_json: bool) -> None:
    """No ABS against a PID ABS on the three roads of derlsp-ao-abs: table and plots."""
    from chassistune.reports.outputs import write_demo

    check_output_dir(out_dir, "--out")
    demo = write_demo(out_dir)
    if as_json:
        echo_json({"rows": demo.rows, "out": out_dir})
        return
    click.echo(
        "Single-wheel ABS, preset paper-derlsp-ao (M = 100 kg, v0 = 30 m/s, v_stop = 0.5 m/s)"
    )
    click.echo("PID gains: " + ", ".join(f"{k}={v:g}" for k, v in demo.pid_gains.items()))
    click.echo(
        f"{'road':<14}{'controller':<11}{'stop time s':>12}{'distance m':>12}"
        f"{'bound m':>10}{'ratio':>8}{'lock at s':>11}"
    )
    for r in demo.rows:
        lock = r["wheel_lock_time_s"]
        click.echo(
            f"{r['road']:<14}{r['controller']:<11}{r['stop_time_s']:>12.3f}"
            f"{r['stop_distance_m']:>12.2f}{r['bound_distance_m']:>10.2f}"
            f"{r['distance_ratio']:>8.3f}{'-' if lock is None else f'{lock:.3f}':>11}"
        )
    click.echo(f"plots: {out_dir}/abs-wheel-{{dry-concrete,wet-asphalt,ice}}.png")
