"""Run the CLI in-process and capture its exit status, stdout and stderr."""

from __future__ import annotations

import contextlib
import fcntl
import io
import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager
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


@contextmanager
def _shared_once(tmp_path_factory: pytest.TempPathFactory, name: str) -> Iterator[Path]:
    """A folder shared by every xdist worker of this test run, entered by one worker at a time
    (a file lock): a session fixture computes into it once and the other workers reuse it."""
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent  # the run's folder, above each worker's own
    folder = root / name
    folder.mkdir(exist_ok=True)
    with open(root / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield folder
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


@pytest.fixture(scope="session")
def reproduced(tmp_path_factory: pytest.TempPathFactory) -> Reproduced:
    """`chassistune reproduce all --quick` into a temporary folder, once per test run however
    many workers ask (the tests of tests/papers and the browser test of tests/reports)."""
    with _shared_once(tmp_path_factory, "reproduce") as folder:
        out = folder / "report"
        stdout = folder / "stdout.txt"
        if not stdout.exists():
            buf = io.StringIO()
            with contextlib.redirect_stdout(buf), pytest.raises(SystemExit) as exc:
                main(["reproduce", "all", "--quick", "--interactive", "--out", str(out)])
            assert exc.value.code == 0
            stdout.write_text(buf.getvalue())
    return Reproduced(out, stdout.read_text())
