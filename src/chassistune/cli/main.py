"""Entry point: the click group with every command added, and the error policy of design.md 7.

Exit 0 on success, 2 on bad input (one line on stderr naming the field; an output the system
refuses to write is bad input too), 130 on Ctrl-C (`_interrupt`), 1 on anything else.
Each command module defines a plain click command (or group) and imports its heavy modules
inside it, so that `--help`, `--version` and `list` answer without importing numba.
"""

from __future__ import annotations

import functools
import sys
import warnings
from collections.abc import Callable
from typing import Any

import click

from chassistune.cli.bbob import bbob_command
from chassistune.cli.bench import bench_command
from chassistune.cli.demo import demo_command
from chassistune.cli.export import export_command
from chassistune.cli.fuzzy import fuzzy_group
from chassistune.cli.league import league_command
from chassistune.cli.list_cmd import list_command
from chassistune.cli.optimize import optimize_command
from chassistune.cli.reproduce import reproduce_command
from chassistune.cli.simulate import simulate_command
from chassistune.cli.study import study_group
from chassistune.cli.tire import tire_command
from chassistune.cli.transfer import transfer_command
from chassistune.cli.tune import tune_command
from chassistune.cli.warmup import warmup_command
from chassistune.errors import InputError


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="chassistune")
def cli() -> None:
    """Tune vehicle chassis controllers (ABS, active suspension) with swarm optimizers.

    All quantities are SI (m, s, kg, N, rad) unless a name says otherwise. Run
    `chassistune COMMAND --help` for the options of each command.
    """


for _command in (
    list_command,
    simulate_command,
    tune_command,
    optimize_command,
    study_group,
    fuzzy_group,
    export_command,
    bench_command,
    demo_command,
    reproduce_command,
    warmup_command,
    bbob_command,
    tire_command,
    league_command,
    transfer_command,
):
    cli.add_command(_command)


def _announcing_compiles(command: click.Command) -> None:
    """Make `command` (a group: each of its commands) say which kernels it compiles as numba
    starts each (`_compile_notice`); `list` answers from the registries without numba, and
    `warmup` reports what it compiled itself."""
    if isinstance(command, click.Group):
        for sub in command.commands.values():
            _announcing_compiles(sub)
        return
    callback = command.callback
    if callback is None or command.name in ("list", "warmup"):
        return

    @functools.wraps(callback)
    def run(*args: Any, **kwargs: Any) -> Any:
        from chassistune._compile_notice import announcing

        with announcing(_echo_err):
            return callback(*args, **kwargs)

    command.callback = run


def _echo_err(line: str) -> None:
    click.echo(line, err=True)


_announcing_compiles(cli)


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _warning_printer() -> Callable[..., None]:
    """`warnings.showwarning` for one command: a warning as one stderr line, a parameter's field
    named as on the command line, and a line already shown not again (a TIR file read for every
    case of a study would repeat its warning once per case)."""
    shown: set[str] = set()

    def show(
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        file: object = None,
        line: str | None = None,
    ) -> None:
        from chassistune.cli.common import cli_field
        from chassistune.params import ImplausibleValue

        text = (
            f"{cli_field(message.field)}: {message.problem}"
            if isinstance(message, ImplausibleValue)
            else str(message)
        )
        out = f"chassistune: warning: {_one_line(text)}"
        if out not in shown:
            shown.add(out)
            click.echo(out, err=True)

    return show


def main(argv: list[str] | None = None) -> None:
    """Run the CLI, mapping bad input to one stderr line and exit status 2."""
    if argv is None:  # a real command line (tests call main in-process with a list)
        from chassistune._interrupt import install

        install()
    args = sys.argv[1:] if argv is None else argv
    warnings.showwarning = _warning_printer()
    if not args:  # no command: the usual help, as `--help` prints it
        args = ["--help"]
    try:
        cli.main(args=args, prog_name="chassistune", standalone_mode=False)
    except InputError as exc:
        from chassistune.cli.common import cli_field

        # the command's name: the first word that is not an option (the group's take no value)
        command = next((a for a in args if not a.startswith("-")), None)
        click.echo(
            f"chassistune: error: {cli_field(exc.field, command)}: {_one_line(exc.problem)}",
            err=True,
        )
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
    except OSError as exc:  # e.g. a write the pre-flight checks could not foresee (disk full)
        where = f"{exc.filename}: " if exc.filename else ""
        click.echo(f"chassistune: error: {where}{_one_line(exc.strerror or str(exc))}", err=True)
        sys.exit(2)
    except KeyboardInterrupt:  # in-process callers, where `interrupt.install` is not active
        click.echo("chassistune: interrupted", err=True)
        sys.exit(130)
    sys.exit(0)
