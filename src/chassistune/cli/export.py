"""`chassistune export [SOURCE] ...`: a tuned controller as C99, an FMI 2.0 source FMU, MATLAB or
JSON. A plain click command; `cli/main.py` adds it to the group."""

from __future__ import annotations

import click

from chassistune.cli.common import check_output_dir
from chassistune.params import parse_assignments


@click.command("export")
@click.argument("source", required=False, metavar="[SOURCE]")
@click.option("--plant", help="Plant when no SOURCE is given (default abs-wheel).")
@click.option(
    "--controller",
    help="Controller when no SOURCE is given (registry defaults for the gains not given).",
)
@click.option("--preset", help="Preset (default: the source's, else the plant's paper preset).")
@click.option("--road", help="Road (default: the source's first road, else the preset's first).")
@click.option(
    "--gains",
    "gains",
    multiple=True,
    metavar="NAME=VALUE,...",
    help="Gains overriding the source's or the registry's.",
)
@click.option(
    "--param",
    "params",
    multiple=True,
    metavar="NAME=VALUE",
    help="Override a scenario parameter, or the export's ecu_ts_s (sample time) and "
    "fuzzy_table_points (repeatable).",
)
@click.option(
    "--format",
    "fmt",
    required=True,
    type=click.Choice(["c", "fmu", "mat", "json"]),
    help="c: controller.h/.c; fmu: FMI 2.0 co-simulation source FMU; mat: .mat and .m; "
    "json: schema-versioned data. Each adds test_vectors.csv.",
)
@click.option("--out", "out_dir", required=True, metavar="DIR", help="Folder to write into.")
def export_command(
    source: str | None,
    plant: str | None,
    controller: str | None,
    preset: str | None,
    road: str | None,
    gains: tuple[str, ...],
    params: tuple[str, ...],
    fmt: str,
    out_dir: str,
) -> None:
    """Export the discrete form of a tuned ABS controller (pid, fuzzy-pid, fuzzy-immune-pid,
    threshold) with test vectors recorded from a closed-loop stop of its scenario.

    SOURCE is a tune result (tune.json) or a stored study run (DIR#RUN, RUN the run key
    scenario|optimizer|seed); without it, --controller with the registry defaults.
    Example: chassistune export runs/tune.json --format c --out ecu/
    """
    from chassistune.export import source as export_source
    from chassistune.export.write import check_folder, write

    check_output_dir(out_dir, "--out", parents=True)  # export creates missing folders
    check_folder(out_dir)
    ec = export_source.resolve(
        source,
        plant,
        controller,
        parse_assignments(gains, "gains"),
        parse_assignments(params, "params"),
        preset,
        road,
    )
    for path in write(ec, fmt, out_dir):
        click.echo(f"wrote {path}")
    click.echo(
        f"sample time {ec.ts_s:g} s ({ec.ts_origin}, in whole steps of dt_s); "
        "--param ecu_ts_s=SECONDS sets another"
    )
