"""Entry point: the click group, and the error policy of DESIGN 7.

Exit 0 on success, 2 on bad input (one line on stderr naming the field), 1 on anything else.
Command modules register themselves on `cli` when imported at the bottom of this file.
"""

from __future__ import annotations

import sys

import click

from chassistune.errors import InputError


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="chassistune")
def cli() -> None:
    """Tune vehicle chassis controllers (ABS, active suspension) with swarm optimizers.

    All quantities are SI (m, s, kg, N, rad) unless a name says otherwise. Run
    `chassistune COMMAND --help` for the options of each command.
    """


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def main(argv: list[str] | None = None) -> None:
    """Run the CLI, mapping bad input to one stderr line and exit status 2."""
    from chassistune.cli import commands  # noqa: F401  (registers the commands)

    try:
        cli.main(args=argv, prog_name="chassistune", standalone_mode=False)
    except InputError as exc:
        from chassistune.cli.common import cli_field

        click.echo(f"chassistune: error: {cli_field(exc.field)}: {_one_line(exc.problem)}",
                   err=True)
        sys.exit(2)
    except click.UsageError as exc:
        param = getattr(exc, "param", None)
        where = ""
        if param is not None and getattr(param, "opts", None):
            where = f"{param.opts[0]}: "
        elif param is not None:
            where = f"{param.name}: "
        click.echo(f"chassistune: error: {where}{_one_line(exc.format_message())}", err=True)
        sys.exit(2)
    except click.exceptions.Abort:
        click.echo("chassistune: aborted", err=True)
        sys.exit(1)
    except click.exceptions.Exit as exc:
        sys.exit(exc.exit_code)
    except click.ClickException as exc:
        click.echo(f"chassistune: error: {_one_line(exc.format_message())}", err=True)
        sys.exit(exc.exit_code if exc.exit_code else 1)
    except BrokenPipeError:
        sys.exit(1)
    sys.exit(0)
