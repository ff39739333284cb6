"""Click options that several commands share word for word, each defined once.

Light at import (no numpy), like every CLI module.
"""

from __future__ import annotations

from collections.abc import Callable, MutableMapping
from typing import Any, TypeVar

import click

from chassistune.cli.choices import ChoicesOption

F = TypeVar("F", bound=Callable[..., Any])


def stacked(*options: Callable[[F], F]) -> Callable[[F], F]:
    """One decorator adding `options` to a command, in the order given (as in `--help`)."""

    def add(command: F) -> F:
        for option in reversed(options):
            command = option(command)
        return command

    return add


preset_option = click.option(
    "--preset",
    cls=ChoicesOption,
    choices_of="presets",
    help="Parameter preset (default: the plant's paper preset).",
)
param_option = click.option(
    "--param",
    "params",
    multiple=True,
    metavar="NAME=VALUE",
    help="Override a plant, road, solver or controller parameter (repeatable).",
)
ecu_option = click.option(
    "--ecu",
    type=click.Choice(["ideal", "realistic"]),
    help="abs-wheel: ideal controller or the realistic ECU (docs/ecu.md).",
)
tire_option = click.option(
    "--tire",
    metavar="FILE.tir",
    help="abs-wheel and abs-vehicle: the Magic Formula tire of a tyre property file "
    "(docs/tires.md) at the wheel's load; without --road on the file's own surface (road "
    "tire-surface), with --road its friction scaled to the road's peak through LMUX and LMUY.",
)
executor_options = stacked(
    click.option(
        "--executor",
        default="serial",
        show_default=True,
        type=click.Choice(["serial", "process", "dask"]),
        help="Where the runs execute.",
    ),
    click.option(
        "--scheduler",
        metavar="ADDRESS",
        help="Dask scheduler address (default: a LocalCluster on loopback).",
    ),
    click.option("--workers", type=int, help="Worker processes (default: the cores)."),
)
"""--executor, --scheduler and --workers (keyword arguments executor, scheduler, workers)."""


def with_tire(plant: str, tire: str | None, values: MutableMapping[str, Any]) -> None:
    """`--tire FILE.tir` into the run's parameters (`tire`): the ABS plants (the others refuse
    it, naming --tire)."""
    if tire is None:
        return
    if plant not in ("abs-wheel", "abs-vehicle"):
        from chassistune.errors import InputError

        raise InputError("--tire", f"the Magic Formula tire runs on the ABS plants, not on {plant}")
    values["tire"] = tire
