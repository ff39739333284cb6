"""Run the CLI in-process and capture its exit status, stdout and stderr."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

from chassistune.cli.main import main


@dataclass
class CliResult:
    code: int
    out: str
    err: str


@pytest.fixture
def cli(capsys: pytest.CaptureFixture[str]) -> Callable[..., CliResult]:
    def run(*args: str) -> CliResult:
        with pytest.raises(SystemExit) as exc:
            main(list(args))
        captured = capsys.readouterr()
        code = exc.value.code if isinstance(exc.value.code, int) else 1
        return CliResult(code, captured.out, captured.err)

    return run


@dataclass(frozen=True)
class Reproduced:
    """The quick reproduction of all four papers, run once per test session."""

    out: Path
    stdout: str


@pytest.fixture(scope="session")
def reproduced(tmp_path_factory: pytest.TempPathFactory) -> Reproduced:
    """`chassistune reproduce all --quick` into a temporary folder (shared by the tests of
    tests/papers and the browser test of tests/reports)."""
    import contextlib
    import io

    out = tmp_path_factory.mktemp("reproduce") / "report"
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), pytest.raises(SystemExit) as exc:
        main(["reproduce", "all", "--quick", "--interactive", "--out", str(out)])
    assert exc.value.code == 0
    return Reproduced(out, buf.getvalue())
