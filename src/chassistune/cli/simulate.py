"""`chassistune simulate PLANT ...`: one closed-loop run, its metrics, plot and trace."""

from __future__ import annotations

import csv
from typing import TYPE_CHECKING

import click

from chassistune.cli.common import check_output_file, echo_json, fmt

if TYPE_CHECKING:
    from chassistune.simulate import SimulationResult


def write_csv(result: SimulationResult, path: str) -> None:
    """The trace as CSV, one row per step, written atomically."""
    import numpy as np

    from chassistune._io import atomic_path

    sig = result.trace.signals
    names = list(sig)
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        units = result.trace.units
        w.writerow([f"{n} [{units[n]}]" if n in units else n for n in names])
        w.writerows(np.column_stack([sig[n] for n in names]).tolist())


def _print_metrics(metrics: dict[str, object]) -> None:
    """Metrics as a list; those with a `passive_` twin as an active / passive / ratio table."""
    paired = [k for k in metrics if f"passive_{k}" in metrics]
    alone = [k for k in metrics if k not in paired and not (
        k.startswith("passive_") and k[len("passive_"):] in paired)]
    width = max(len(k) for k in metrics)
    if paired:
        click.echo(f"  {'':<{width}}  {'active':>10}  {'passive':>10}  {'ratio':>7}")
        for k in paired:
            a, b = metrics[k], metrics[f"passive_{k}"]
            ratio = a / b if isinstance(a, float) and isinstance(b, float) and b else None
            click.echo(f"  {k:<{width}}  {fmt(a):>10}  {fmt(b):>10}  {fmt(ratio):>7}")
    for k in alone:
        click.echo(f"  {k:<{width}}  {fmt(metrics[k])}")


@click.command("simulate")
@click.argument("plant", metavar="PLANT")
@click.option("--preset", help="Parameter preset (default: the plant's paper preset).")
@click.option("--road", help="Road (default: the preset's first road).")
@click.option("--controller", default="pid", show_default=True,
              help="Controller structure; `chassistune list controllers` shows them.")
@click.option("--param", "params", multiple=True, metavar="NAME=VALUE",
              help="Override a plant, road, solver or controller parameter (repeatable).")
@click.option("--gains", "gains", multiple=True, metavar="NAME=VALUE,...",
              help="Controller gains (default: the registry's defaults).")
@click.option("--seed", default=0, show_default=True, type=int,
              help="Seed of any random draw (road realizations).")
@click.option("--ecu", type=click.Choice(["ideal", "realistic"]),
              help="abs-wheel: ideal controller or the realistic ECU (docs/ecu.md).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@click.option("--plot", "plot_path", metavar="FILE.png", help="Draw the response into FILE.png.")
@click.option("--csv", "csv_path", metavar="FILE.csv", help="Write the time series to FILE.csv.")
def simulate_command(plant: str, preset: str | None, road: str | None, controller: str,
                     params: tuple[str, ...], gains: tuple[str, ...], seed: int, as_json: bool,
                     plot_path: str | None, csv_path: str | None, ecu: str | None) -> None:
    """Simulate one closed-loop run of PLANT and report its metrics.

    PLANT is one of the plants of `chassistune list plants` (abs-wheel, quarter-car). Units are SI.
    Example: chassistune simulate abs-wheel --road wet-asphalt --gains kp=5000,kd=230 --plot out.png
    """
    from chassistune.params import parse_assignments
    from chassistune.plots.registry import plot_trace
    from chassistune.scenarios.registry import get_plant, plant_names
    from chassistune.simulate import simulate

    if plant not in plant_names():
        get_plant(plant)  # raises the one-line error listing the plants
    check_output_file(plot_path, "--plot", ".png")
    check_output_file(csv_path, "--csv", ".csv")
    values = parse_assignments(params, "--param")
    if ecu:
        values["ecu"] = ecu
    result = simulate(plant, preset=preset, road=road, controller=controller, params=values,
                      gains=parse_assignments(gains, "--gains"), seed=seed)
    if plot_path:
        plot_trace(result.scenario, result.trace, plot_path)
    if csv_path:
        write_csv(result, csv_path)
    if as_json:
        echo_json(result.as_dict())
        return
    sc = result.scenario
    click.echo(f"{plant}  preset {sc.preset}  road {sc.road}  controller {sc.controller.name}")
    if result.gains:
        click.echo("gains: " + ", ".join(f"{k}={fmt(v)}" for k, v in result.gains.items()))
    _print_metrics(result.metrics)
    for path in (plot_path, csv_path):
        if path:
            click.echo(f"wrote {path}")
