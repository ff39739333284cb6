"""`chassistune fuzzy show|eval`: inspect and evaluate fuzzy rule bases (DESIGN 7)."""

from __future__ import annotations

import click

from chassistune.cli.main import cli


@cli.group("fuzzy")
def fuzzy_group() -> None:
    """Show and evaluate fuzzy rule bases (a built-in name or a TOML file)."""
