"""Helpers shared by the commands: output checks, JSON printing, number formatting.

Light on purpose (no numpy at import): every command module imports it at start-up.
"""

from __future__ import annotations

import math
import os
from typing import Any

import click

from chassistune.errors import InputError

_FLAGS = {
    "params": "--param", "gains": "--gains", "road": "--road", "roads": "--road",
    "preset": "--preset", "controller": "--controller", "objective": "--objective",
    "aggregate": "--aggregate", "seed": "--seed", "optimizer": "--optimizer", "pop_size": "--pop",
    "max_iter": "--iters", "max_evals": "--evals", "dim": "--dim", "plant": "PLANT",
    "function": "FUNCTION", "source": "SOURCE", "out": "--out", "format": "--format",
    "vary": "--vary", "scenarios": "--scenarios", "sampler": "--sampler", "validate": "--validate",
    "beta": "--beta",
}
"""The command line's word for the head of a domain field path."""

_COMMAND_FLAGS = {"export": {"plant": "--plant"}}
"""Where a command spells a head otherwise (export takes the plant as an option)."""


def cli_field(field: str, command: str | None = None) -> str:
    """The command-line words for a domain field path (the one mapping): `params.v0_m_s` ->
    `--param v0_m_s`, `gains.kp` -> `--gains kp`, `roads` -> `--road`, `plant` -> `PLANT` (or
    `--plant` in the command `export`); others unchanged."""
    head, dot, rest = field.partition(".")
    flag = _COMMAND_FLAGS.get(command or "", {}).get(head) or _FLAGS.get(head)
    if flag is None:
        return field
    return f"{flag} {rest}" if dot else flag


def check_output_file(path: str | None, option: str, suffix: str | None = None) -> None:
    """Refuse an output path whose folder does not exist (before any work is done)."""
    if path is None:
        return
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InputError(option, f"folder {folder!r} does not exist")
    if suffix and not path.lower().endswith(suffix):
        raise InputError(option, f"expected a {suffix} file name, got {path!r}")


def echo_json(obj: dict[str, Any]) -> None:
    """Print exactly one JSON object on stdout (normalized by `_io.jsonable`)."""
    from chassistune._io import dumps

    click.echo(dumps(obj, indent=1))


def fmt(x: Any) -> str:
    """A short human rendering of a metric value."""
    import numpy as np

    if x is None:
        return "-"
    if isinstance(x, bool | np.bool_):
        return "yes" if x else "no"
    if isinstance(x, float | np.floating):
        if not math.isfinite(float(x)):
            return "-"
        return f"{float(x):.4g}"
    return str(x)
