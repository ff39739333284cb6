"""Ctrl-C at random moments: every try ends within 2 s with exit 130 and one
line on stderr; an interrupted `tune --out` leaves its best so far, marked interrupted, exactly
when an evaluation had finished (the line says which), and `study run` says what is stored.

The signal goes to real `chassistune` processes: during the package's imports (numpy, numba,
click), kernel compilation or loading, and large populations, with the kernels on threads and
(CHASSISTUNE_THREADS=1) in the main thread, where a compiled loop keeps Python's own signal
handling waiting.
"""

from __future__ import annotations

import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

CLI = [
    sys.executable,
    "-c",
    "import sys; sys.argv[0] = 'chassistune'; from chassistune.cli import main; main()",
]

STUDY = """
[study]
name = "ctrl-c"
seeds = 200
seed = 1
[[scenarios]]
name = "qc"
plant = "quarter-car"
roads = ["iso-b", "iso-c"]
controller = "pid"
objective = "rms-ratio-exact"
[[optimizers]]
name = "pso"
[budget]
pop_size = 10
iterations = 2000
"""


def _interrupt(args: list[str], delay_s: float, threads: str) -> tuple[int, str, float]:
    env = dict(os.environ, CHASSISTUNE_THREADS=threads)
    proc = subprocess.Popen(
        CLI + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env
    )
    time.sleep(delay_s)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=2.0)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        pytest.fail(f"{args[0]} did not stop within 2 s of SIGINT at {delay_s:.2f} s")
    return proc.returncode, err, time.monotonic() - sent


def _tune(out: Path, pop: int) -> list[str]:
    return [
        "tune",
        "abs-wheel",
        "--controller",
        "pid",
        "--optimizer",
        "pso",
        "--pop",
        str(pop),
        "--iters",
        "100000",
        "--out",
        str(out),
    ]  # never finishes before the signal


def _one_line(err: str) -> bool:
    """One interruption line, last; before it at most the first-use compile notice."""
    lines = err.splitlines()
    return (
        len(lines) >= 1
        and lines[-1].startswith("chassistune: interrupted")
        and all("compiling kernels (first use" in x for x in lines[:-1])
    )


def _check_tune(code: int, err: str, out: Path) -> bool:
    """The one line and the files agree; True when a best so far was saved."""
    assert code == 130, err
    assert _one_line(err), err
    if "best so far" in err:
        doc = json.loads((out / "tune.json").read_text())
        assert doc["interrupted"] is True and doc["nfev"] >= 1
        assert set(json.loads((out / "best_gains.json").read_text())) == {"kp", "ki", "kd"}
        assert doc["best_cost"] < 1e9
        return True
    assert not (out / "tune.json").exists(), err
    return False


@pytest.mark.slow
def test_ctrl_c_at_random_moments_stops_at_once_with_130_and_one_line(tmp_path):
    warm = subprocess.run(
        CLI + _tune(tmp_path / "warm", 4)[:-4] + ["--iters", "1"], capture_output=True, text=True
    )  # compiles the kernel once
    assert warm.returncode == 0, warm.stderr
    rng = random.Random(20261123)
    # from 0.3 s: before that the interpreter itself may still be starting (site, encodings),
    # before any code of the package can run; the package's own imports take a second or more
    tries = [(rng.uniform(0.3, 3.0), 2000, str(1 + i % 2)) for i in range(18)]
    tries += [(8.0, 300, "1"), (8.0, 300, "2")]  # well after the first population
    saved = 0
    for i, (delay, pop, threads) in enumerate(tries):
        out = tmp_path / f"t{i}"
        code, err, _ = _interrupt(_tune(out, pop), delay, threads)
        saved += _check_tune(code, err, out)
        shutil.rmtree(out, ignore_errors=True)
    assert saved >= 2


def test_ctrl_c_during_a_study_says_how_many_runs_are_stored(tmp_path):
    config = tmp_path / "study.toml"
    config.write_text(STUDY)
    for delay in (1.0, 5.0):  # still importing; then running
        code, err, _ = _interrupt(
            ["study", "run", str(config), "--out", str(tmp_path / "st")], delay, "1"
        )
        assert code == 130 and _one_line(err), err
    assert "runs are stored in" in err and "same command to resume" in err, err
