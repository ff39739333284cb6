"""`chassistune study run|report|export`: studies over scenarios x optimizers x seeds."""

from __future__ import annotations

import click

from chassistune.cli.main import cli


@cli.group("study")
def study_group() -> None:
    """Run a study from a TOML config, report on it, export its runs."""
