"""`chassistune warmup` on a fresh cache compiles every kernel variant the README and docs/ reach:
afterwards none of their commands compiles (no notice, no new file in numba's cache)."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

RUN = "import sys; from chassistune.cli.main import main; main()"

TIRES = files("chassistune") / "data" / "tires"
CHRONO = str(TIRES / "chrono_185_80R14_pac2002.tir")
COMMONROAD = str(TIRES / "commonroad_pac2002.tir")

DOCUMENTED = [
    "simulate abs-wheel --road wet-asphalt --controller pid --gains kp=5000,kd=230 --csv run.csv",
    "simulate abs-wheel --preset sldemo --controller bang-bang --param v_stop_m_s=0.01",
    "simulate abs-wheel --road burckhardt-dry-asphalt --controller threshold --json",
    "simulate abs-wheel --road ice --controller fuzzy-immune-pid --ecu realistic",
    "simulate quarter-car --road iso-b --param speed_m_s=20",
    "simulate abs-vehicle --road split-mu --controller fuzzy-pid",
    "tune abs-wheel --road dry-concrete --controller pid --optimizer derlsp-ao --pop 10 --iters 3"
    " --out tuned",
    "tune abs-wheel --road dry-concrete --road ice --aggregate max --controller fuzzy-pid"
    " --optimizer pso --evals 40",
    "tune quarter-car --controller pid --optimizer iabc --pop 10 --iters 3",
    "optimize F9 --dim 30 --optimizer ao --iters 5 --json",
    "fuzzy eval immune --input e=0.3 --input ec=-0.2",
    "export tuned/tune.json --format c --out ecu",
    "export --controller fuzzy-pid --gains ke=12 --format mat --out mat",
    "simulate --from tuned/tune.json --compare none,pid,threshold",
    "league --quick --seeds 1 --out league-quick",
    f"tire --lateral {CHRONO}",
    f"tire {COMMONROAD}",
    f"simulate abs-wheel --tire {CHRONO} --param relaxation_length_m=tire",
    f"simulate abs-wheel --tire {COMMONROAD} --ecu realistic --param relaxation_length_m=0.3",
    f"simulate abs-vehicle --tire {CHRONO} --road split-mu --param dt_s=0.0002"
    " --param relaxation_length_m=tire --param lateral_relaxation_length_m=tire",
]
"""The README's tour and docs/ commands, one per kernel variant they reach (budgets cut: the
budget picks no kernel)."""


@dataclass(frozen=True)
class Warmed:
    env: dict[str, str]
    numba_dir: Path
    stdout: str
    stale: Path


def _chassistune(args: list[str], env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", RUN, *args], env=env, cwd=cwd, capture_output=True, text=True
    )


def _cache_files(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*.nb[ic]")}


@pytest.fixture(scope="module")
def warmed(tmp_path_factory: pytest.TempPathFactory) -> Warmed:
    """`warmup` in a fresh cache home (with a stale cache of other sources, a month old)."""
    home = tmp_path_factory.mktemp("cache-home")
    stale = home / "chassistune" / "numba-0000000000000000"
    stale.mkdir(parents=True)
    month_ago = time.time() - 30 * 86400
    os.utime(stale, (month_ago, month_ago))
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(home)
    done = _chassistune(["warmup"], env, home)
    assert done.returncode == 0, done.stderr
    (numba_dir,) = (p for p in (home / "chassistune").glob("numba-*") if p != stale)
    return Warmed(env, numba_dir, done.stdout, stale)


def test_warmup_reports_what_it_compiled_and_prunes(warmed: Warmed) -> None:
    first = warmed.stdout.splitlines()[0]
    assert first.startswith("warmup: ") and " functions compiled (" in first and " s on " in first
    for kernel in (
        "abs_wheel_kernel.simulate_abs_wheel",
        "abs_wheel_ecu_kernel.simulate_abs_wheel_ecu",
        "abs_vehicle_kernel.simulate_abs_vehicle",
        "quarter_car_kernel.simulate_batch",
        "closed_loop.advance",
    ):
        assert f"  {kernel}: " in warmed.stdout
    assert not warmed.stale.exists()


def test_no_documented_command_compiles_after_warmup(warmed: Warmed, tmp_path: Path) -> None:
    for command in DOCUMENTED:
        before = _cache_files(warmed.numba_dir)
        done = _chassistune(command.split(), warmed.env, tmp_path)
        assert done.returncode == 0, f"{command}: {done.stderr}"
        assert "compiling" not in done.stderr, f"{command}: {done.stderr}"
        assert _cache_files(warmed.numba_dir) == before, command


def test_a_second_warmup_compiles_nothing(warmed: Warmed, tmp_path: Path) -> None:
    done = _chassistune(["warmup", "--processes", "1"], warmed.env, tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("warmup: 0 functions compiled (0 s of CPU)")
