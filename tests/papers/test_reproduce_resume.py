"""A reproduction killed in the middle (SIGKILL, during its second study) and run again writes
the same report numbers as an uninterrupted one, which itself ran on the process executor: the
numbers depend neither on interruptions nor on where the runs executed. Tiny budget."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

SCRIPT = Path(__file__).with_name("tiny_reproduce.py")
SECOND_STORE = Path("studies") / "derlsp-ao-abs-functions-quick" / "study.sqlite"


def _run(out: Path, *args: str) -> subprocess.Popen[bytes]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    return subprocess.Popen(
        [sys.executable, str(SCRIPT), str(out), *args],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )


def _tables(out: Path) -> dict[str, bytes]:
    files = [*sorted((out / "tables").glob("*.csv")), out / "verdicts.csv"]
    return {f.name: f.read_bytes() for f in files}


@pytest.mark.slow
def test_killed_and_rerun_gives_the_report_of_an_uninterrupted_run(tmp_path: Path) -> None:
    whole = _run(tmp_path / "whole", "--executor", "process", "--workers", "2")
    killed = _run(tmp_path / "killed")
    deadline = time.monotonic() + 600
    while not (tmp_path / "killed" / SECOND_STORE).exists():
        assert killed.poll() is None, killed.stderr.read() if killed.stderr else ""
        assert time.monotonic() < deadline
        time.sleep(0.05)
    killed.send_signal(signal.SIGKILL)
    killed.wait()
    assert not (tmp_path / "killed" / "report.html").exists()  # it died before its report
    resumed = _run(tmp_path / "killed")
    for proc in (whole, resumed):
        _, err = proc.communicate(timeout=600)
        assert proc.returncode == 0, err.decode()
    assert b"done before" in err  # the rerun kept the first study's runs
    whole_tables = _tables(tmp_path / "whole")
    assert len(whole_tables) > 20
    assert _tables(tmp_path / "killed") == whole_tables
