"""The CLI's shape: every command added by `cli.main`, help without a command, and the fast paths
(`--help`, `--version`, `list plants`) importing neither numba nor the kernels."""

from __future__ import annotations

import subprocess
import sys

import pytest

from chassistune.cli.main import cli

COMMANDS = {
    "list",
    "simulate",
    "tune",
    "optimize",
    "study",
    "fuzzy",
    "export",
    "bench",
    "demo",
    "reproduce",
    "warmup",
    "bbob",
    "tire",
    "league",
    "transfer",
}

PROBE = """
import sys
from chassistune.cli import main
try:
    main({args!r})
except SystemExit as exc:
    code = exc.code
heavy = sorted(m for m in ("numba", "chassistune.sim.abs_wheel_kernel", "chassistune.fuzzy.sets")
               if m in sys.modules)
print("HEAVY", code, ",".join(heavy) or "-", file=sys.stderr)
"""


def _probe(*args: str) -> tuple[str, str]:
    done = subprocess.run(
        [sys.executable, "-c", PROBE.format(args=list(args))],
        capture_output=True,
        text=True,
        check=True,
    )
    last = done.stderr.strip().splitlines()[-1].split()
    assert last[0] == "HEAVY" and last[1] == "0", done.stderr
    return done.stdout, last[2]


def test_every_command_is_added_once() -> None:
    assert set(cli.commands) == COMMANDS


def test_no_arguments_prints_the_multi_line_help(cli) -> None:  # type: ignore[no-untyped-def]
    res = cli()
    assert res.code == 0 and res.err == ""
    assert res.out.startswith("Usage: chassistune [OPTIONS] COMMAND [ARGS]...")
    assert len(res.out.splitlines()) > 10 and "Commands:" in res.out


@pytest.mark.parametrize(
    "args",
    [
        ("--help",),
        ("--version",),
        ("study", "--help"),
        ("export", "--help"),
        ("transfer", "--help"),
        ("list", "plants"),
        ("list", "plants", "--json"),
        ("list", "controllers"),
    ],
)
def test_fast_paths_import_no_numba(args: tuple[str, ...]) -> None:
    out, heavy = _probe(*args)
    assert out and heavy == "-"
