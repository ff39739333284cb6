"""Progress off a terminal: a line with the runs done so far every period, not silence."""

from __future__ import annotations

import time

from studies_helpers import tiny_config, write_plan

import chassistune.studies.progress as progress_module
from chassistune.studies.progress import with_progress


def _until(lines: list[str], text: str, timeout_s: float = 20.0) -> None:
    end = time.monotonic() + timeout_s
    while not any(text in line for line in lines):
        assert time.monotonic() < end, lines
        time.sleep(0.01)


def test_off_a_terminal_a_line_reports_the_runs_done_every_period():
    lines: list[str] = []

    def run(progress):
        progress(1, 0, 4)
        _until(lines, "1 of 4")
        progress(3, 1, 4)
        _until(lines, "3 of 4")
        return "outcome"

    assert with_progress(run, "study s", lines.append, period_s=0.02) == "outcome"
    assert lines[0].startswith("study s: 1 of 4 runs done, 0 failed (")
    assert lines[-1].startswith("study s: 3 of 4 runs done, 1 failed (")


def test_study_run_off_a_terminal_prints_progress_lines(cli, tmp_path, monkeypatch):
    monkeypatch.setattr(progress_module, "PERIOD_S", 0.001)
    config, _ = write_plan(tmp_path, tiny_config(seeds=1))
    r = cli("study", "run", str(config), "--out", str(tmp_path / "st"))
    assert r.code == 0, r.err
    assert "chassistune: study tiny: " in r.err and " of 2 runs done, 0 failed (" in r.err
