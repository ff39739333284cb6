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
    "params": "--param",
    "gains": "--gains",
    "road": "--road",
    "roads": "--road",
    "preset": "--preset",
    "controller": "--controller",
    "objective": "--objective",
    "aggregate": "--aggregate",
    "seed": "--seed",
    "optimizer": "--optimizer",
    "pop_size": "--pop",
    "max_iter": "--iters",
    "max_evals": "--evals",
    "dim": "--dim",
    "plant": "PLANT",
    "plants": "--plant",
    "function": "FUNCTION",
    "source": "SOURCE",
    "out": "--out",
    "format": "--format",
    "vary": "--vary",
    "scenarios": "--scenarios",
    "sampler": "--sampler",
    "validate": "--validate",
    "beta": "--beta",
    "inputs": "--input",
    "executor": "--executor",
    "scheduler": "--scheduler",
    "workers": "--workers",
}
"""The command line's word for the head of a domain field path."""

_COMMAND_FLAGS = {
    "export": {"plant": "--plant"},
    "simulate": {"tire": "--tire"},
    "tune": {"tire": "--tire"},
    "transfer": {"reproduction": "--from", "sources": "--source"},
}
"""Where a command spells a head otherwise (export takes the plant as an option; simulate and
tune take a TIR file as --tire, the command `tire` as its argument; transfer reads a
reproduction's output from --from and its sources from --source)."""


def cli_field(field: str, command: str | None = None) -> str:
    """The command-line words for a domain field path (the one mapping): `params.v0_m_s` ->
    `--param v0_m_s`, `gains.kp` -> `--gains kp`, `roads` -> `--road`, `plant` -> `PLANT` (or
    `--plant` in the command `export`); others unchanged, among them a file's location such as
    `params.tir:12` (its tail is no field name)."""
    head, dot, rest = field.partition(".")
    flag = _COMMAND_FLAGS.get(command or "", {}).get(head) or _FLAGS.get(head)
    if flag is None or (dot and not all(name.isidentifier() for name in rest.split("."))):
        return field
    return f"{flag} {rest}" if dot else flag


def _probe_writable(folder: str, option: str) -> None:
    """Create and remove an empty file in `folder`: the only honest test that a write will work
    (permission bits say nothing for root, nor for /proc or a read-only mount)."""
    import secrets

    probe = os.path.join(folder, f".chassistune-probe-{secrets.token_hex(4)}")
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as exc:
        raise InputError(option, f"cannot write in {folder!r}: {exc.strerror or exc}") from None
    os.close(fd)
    os.unlink(probe)


def _existing_folder(folder: str, option: str) -> None:
    if not os.path.exists(folder):
        raise InputError(option, f"folder {folder!r} does not exist")
    if not os.path.isdir(folder):
        raise InputError(option, f"{folder!r} is a file, not a folder")


def check_output_file(
    path: str | None, option: str, suffixes: tuple[str, ...] = (), stdout_ok: bool = False
) -> None:
    """Refuse, before any work, an output file that could not be written: its folder missing,
    a file, read-only or not a real file system (/proc), the path a folder, a wrong suffix.
    Nothing is left behind; `-` means stdout when `stdout_ok`."""
    if path is None or (stdout_ok and path == "-"):
        return
    if not path or os.path.isdir(path):
        raise InputError(option, f"{path!r} is a folder, not a file name")
    if suffixes and not path.lower().endswith(suffixes):
        raise InputError(option, f"expected a file ending in {', '.join(suffixes)}, got {path!r}")
    folder = os.path.dirname(os.path.abspath(path))
    _existing_folder(folder, option)
    _probe_writable(folder, option)


def check_output_dir(path: str | None, option: str, parents: bool = False) -> None:
    """Refuse, before any work, an output folder that could not be written: a file in its place,
    its parent missing (unless `parents`: then the nearest existing ancestor is checked),
    read-only or not a real file system. Nothing is created here."""
    if path is None:
        return
    full = os.path.abspath(path)
    if os.path.exists(full):
        if not os.path.isdir(full):
            raise InputError(option, f"{path!r} exists and is not a folder")
        _probe_writable(full, option)
        return
    parent = os.path.dirname(full)
    while parents and not os.path.lexists(parent) and parent != os.path.dirname(parent):
        parent = os.path.dirname(parent)
    _existing_folder(parent, option)
    _probe_writable(parent, option)


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


def check_study_folder(out_dir: str, executor: str) -> None:
    """Before a study's runs: its folder writable (`--out`), a study folder or new, not locked
    by another run; dask importable when asked for."""
    from chassistune.studies.executors import check_dask
    from chassistune.studies.lock import refuse_if_locked
    from chassistune.studies.runner import check_out_dir

    check_output_dir(out_dir, "--out")
    check_out_dir(out_dir)
    refuse_if_locked(out_dir)
    if executor == "dask":
        check_dask()
