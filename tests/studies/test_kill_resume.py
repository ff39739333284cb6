"""Kill `study run` with SIGKILL at random moments, rerun: every run once, same final table."""

from __future__ import annotations

import random
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest
from studies_helpers import write_plan

from chassistune.reports.tables import runs_table
from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.store import open_study

CONFIG = """
[study]
name = "kill"
seeds = 8
seed = 5

[[scenarios]]
name = "qc"
plant = "quarter-car"
roads = ["iso-b", "iso-c"]
controller = "pid"
objective = "rms-ratio-exact"

[[optimizers]]
name = "pso"

[[optimizers]]
name = "de"

[budget]
pop_size = 10
iterations = 100
"""
RUNS = 32
KILLS = 5
CLI = "import sys; from chassistune.cli import main; main(sys.argv[1:])"


def _count(store: Path) -> int:
    if not store.exists():
        return 0
    try:
        conn = sqlite3.connect(f"{store.as_uri()}?mode=ro", uri=True, timeout=0.05)
        try:
            return int(conn.execute("SELECT count(*) FROM runs").fetchone()[0])
        finally:
            conn.close()
    except sqlite3.Error:  # not created yet, or busy: try again
        return 0


def _start(config: Path, out: Path) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        [sys.executable, "-c", CLI, "study", "run", str(config), "--out", str(out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )


def _table(folder: Path):
    with open_study(folder) as store:
        return runs_table(list(store.records())).drop(columns=["wall_time_s", "versions"])


@pytest.mark.slow
def test_sigkilled_study_resumes_to_the_uninterrupted_result(tmp_path):
    config, plan = write_plan(tmp_path, CONFIG)
    assert len(plan.runs) == RUNS
    run_study(plan, tmp_path / "reference", SerialExecutor())
    out = tmp_path / "killed"
    store = out / "study.sqlite"
    rng = random.Random(2024)
    counts = []
    attempts = 0
    targets = sorted(rng.sample(range(RUNS), KILLS))  # kill once this many runs are stored...
    while targets and attempts < 3 * KILLS:
        attempts += 1
        target = targets.pop(0)
        proc = _start(config, out)
        deadline = time.monotonic() + 60
        while proc.poll() is None and _count(store) < target and time.monotonic() < deadline:
            time.sleep(0.002)
        time.sleep(rng.uniform(0.0, 0.05))  # ...plus a random moment into the next run
        if proc.poll() is None:
            proc.send_signal(signal.SIGKILL)
            proc.wait()
            assert proc.returncode == -signal.SIGKILL
            counts.append(_count(store))
        if _count(store) == RUNS:
            break
    print(
        f"\nkill-and-resume: {len(counts)} SIGKILLs at {counts} stored runs ({attempts} attempts)"
    )
    assert sum(c < RUNS for c in counts) >= 3, counts  # most kills left runs to do
    final = subprocess.run(
        [sys.executable, "-c", CLI, "study", "run", str(config), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert final.returncode == 0, final.stderr
    conn = sqlite3.connect(store)
    assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
    keys = [k for (k,) in conn.execute("SELECT key FROM runs")]
    conn.close()
    assert sorted(keys) == sorted(s.key for s in plan.runs)  # every run exactly once
    reference = _table(tmp_path / "reference")
    assert (reference["status"] == "completed").all()
    assert _table(out).equals(reference)
