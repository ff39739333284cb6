"""`chassistune demo`: the README's main job until the paper reproduction replaces it.

Simulates the three roads of seed 000 (dry concrete, wet asphalt, ice) without ABS and with a
well-set PID, prints a table (stop time, distance, bound, ratio to bound) and writes the plots.
"""

from __future__ import annotations

import os

import click

from chassistune.cli.common import echo_json
from chassistune.cli.main import cli
from chassistune.errors import InputError


@cli.command("demo")
@click.option("--out", "out_dir", default="demo-output", show_default=True,
              help="Folder for the plots (created if missing).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
def demo_command(out_dir: str, as_json: bool) -> None:
    """No ABS against a PID ABS on seed 000's three roads: table and plots."""
    from chassistune.controllers import catalogue
    from chassistune.plots.abs_wheel import plot_comparison
    from chassistune.scenarios.abs_wheel import PLANT

    parent = os.path.dirname(os.path.abspath(out_dir))
    if not os.path.isdir(parent):
        raise InputError("--out", f"folder {parent!r} does not exist")
    os.makedirs(out_dir, exist_ok=True)
    pid = catalogue.get("abs-wheel", "pid").default_gains()  # the hand-set PID of the registry
    rows = []
    for road in PLANT.presets()["paper-derlsp-ao"].roads:
        runs = []
        for controller, gains in (("none", {}), ("pid", pid)):
            sc = PLANT.scenario("paper-derlsp-ao", road, controller)
            tr = sc.trace(sc.gains_array(gains))
            runs.append((controller, tr))
            m = tr.metrics
            rows.append({
                "road": road, "controller": controller, "stop_time_s": m["stop_time_s"],
                "stop_distance_m": m["stop_distance_m"], "bound_distance_m": m["bound_distance_m"],
                "distance_ratio": m["distance_ratio"], "wheel_lock_time_s": m["wheel_lock_time_s"],
            })
        path = os.path.join(out_dir, f"abs-wheel-{road}.png")
        plot_comparison(sc, runs, path, title=f"abs-wheel, seed 000 preset, {road}: "
                        "no ABS vs PID (" + ", ".join(f"{k}={v:g}" for k, v in pid.items()) + ")")
    if as_json:
        echo_json({"rows": rows, "out": out_dir})
        return
    click.echo("Single-wheel ABS, preset paper-derlsp-ao "
               "(M = 100 kg, v0 = 30 m/s, v_stop = 0.5 m/s)")
    click.echo("PID gains: " + ", ".join(f"{k}={v:g}" for k, v in pid.items()))
    click.echo(f"{'road':<14}{'controller':<11}{'stop time s':>12}{'distance m':>12}"
               f"{'bound m':>10}{'ratio':>8}{'lock at s':>11}")
    for r in rows:
        lock = r["wheel_lock_time_s"]
        click.echo(f"{r['road']:<14}{r['controller']:<11}{r['stop_time_s']:>12.3f}"
                   f"{r['stop_distance_m']:>12.2f}{r['bound_distance_m']:>10.2f}"
                   f"{r['distance_ratio']:>8.3f}{'-' if lock is None else f'{lock:.3f}':>11}")
    click.echo(f"plots: {out_dir}/abs-wheel-{{dry-concrete,wet-asphalt,ice}}.png")
