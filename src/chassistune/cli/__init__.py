"""The `chassistune` command line. Each command group lives in its own module of this package."""

from chassistune.cli.main import main

__all__ = ["main"]
