"""`chassistune bench [--quick] [--json]`: the speed and accuracy figures of design.md 8.

Every ratio is measured against its baseline in the same run. Figures of areas not installed
yet are skipped with a note.
"""

from __future__ import annotations

import importlib

import click

from chassistune.cli.common import echo_json, fmt
from chassistune.perf.targets import verdict

AREAS = (
    "abs",
    "tires",
    "jax_peer",
    "optimizer",
    "tuning",
    "fuzzy",
    "suspension",
    "vehicle",
    "ecu",
    "robust",
    "scaling",
)


@click.command("bench")
@click.option("--quick", is_flag=True, help="Fewer repetitions and a smaller baseline sample.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@click.option(
    "--only",
    type=click.Choice(AREAS),
    multiple=True,
    help="Measure only these areas (repeatable); 'scaling': cost against population, iterations.",
)
@click.option(
    "--plot",
    "plot_path",
    type=click.Path(dir_okay=False),
    help="Write the scaling curves to this image file (needs the 'scaling' area measured).",
)
def bench_command(quick: bool, as_json: bool, only: tuple[str, ...], plot_path: str | None) -> None:
    """Measure speed and accuracy: simulations/s, errors, speedups against baselines.

    Every ratio is measured against its baseline (scipy solve_ivp, JAX, mealpy, scikit-fuzzy,
    the simulated objective) in the same run; `--quick` uses fewer repetitions. Each figure with
    a target (docs/design.md 8) says whether this run met it. The last area,
    'scaling', measures the cost against population and iterations (about 3 minutes).
    """
    if plot_path is not None and only and "scaling" not in only:
        raise click.UsageError("--plot draws the scaling curves: add --only scaling")
    figures: dict[str, float] = {}
    notes: dict[str, str] = {}
    for area in only or AREAS:
        try:
            module = importlib.import_module(f"chassistune.perf.{area}")
        except ModuleNotFoundError as exc:
            notes[area] = f"not available: {exc}"
            continue
        if not as_json:
            click.echo(f"measuring {area} ...", err=True)
        figures.update(module.figures(quick))
    if plot_path is not None:
        from chassistune.perf.scaling import curves
        from chassistune.plots.bench_scaling import plot_scaling

        plot_scaling(*curves(figures), plot_path)
    if as_json:
        echo_json({**figures, "notes": notes} if notes else figures)
        return
    for name, value in figures.items():
        click.echo(f"{name:<36} {fmt(value):<10} {verdict(name, value)}".rstrip())
    for area, note in notes.items():
        click.echo(f"{area:<36} {note}")
