"""`abs_speedup_vs_jax` (DESIGN 8): our single-wheel kernel against its JAX peer (`perf.jax_abs`),
both on one core, the PID on paper-derlsp-ao dry concrete, the bench population (50) and the
same tiled to 1000, CPU time (the machine is shared), measured in the same run.

JAX runs in a child process (`python -m chassistune.perf.jax_peer`) that holds XLA to one
thread (XLA_FLAGS, set before jax is imported) and to one CPU (`os.sched_setaffinity`), so that
neither leaks into the bench; its CPU time is the process's (XLA's runtime threads included). Its
compile time (`lower().compile()`) is excluded and reported apart (`jax_compile_s`). Without
JAX (`pip install chassistune[bench]`) the bench notes the figures as not measured.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
import time
from typing import Any

import numpy as np

from chassistune.perf.abs import bench_population
from chassistune.perf.timing import best_cpu_time, best_time
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario
from chassistune.sim import abs_wheel_layout as KL

if importlib.util.find_spec("jax") is None:
    raise ModuleNotFoundError(
        "abs_speedup_vs_jax not measured: jax is not installed (pip install chassistune[bench])",
        name="jax",
    )

XLA_ONE_THREAD = "--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1"
POPULATIONS = (50, 1000)


def _scenario() -> AbsWheelScenario:
    """The timed scenario: the PID on paper-derlsp-ao, dry concrete."""
    return PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")


def _gains(n: int) -> np.ndarray:
    """The bench population tiled to n rows."""
    return np.resize(bench_population(), (n, 3))


def _repeats(n: int, quick: bool) -> int:
    """Timed repetitions at population n (best of them is kept)."""
    return 3 if quick or n >= 1000 else 7


def measure_jax(quick: bool) -> dict[str, Any]:
    """In this process (the child): per population, the compile time, the best process CPU
    time and wall time of a run, and the stop distances."""
    from chassistune.perf.jax_abs import build_simulate

    simulate = build_simulate(_scenario())
    out: dict[str, Any] = {}
    for n in POPULATIONS:
        g = _gains(n)
        t0 = time.perf_counter()
        compiled = simulate.lower(g).compile()
        out[f"compile_s_{n}"] = time.perf_counter() - t0
        distances = np.asarray(compiled(g))[:, 0]

        def run(c: Any = compiled, x: np.ndarray = g) -> None:
            c(x).block_until_ready()

        repeats = _repeats(n, quick)
        out[f"cpu_s_{n}"] = best_time(run, repeats, time.process_time)
        out[f"wall_s_{n}"] = best_time(run, repeats)
        out[f"distance_m_{n}"] = distances.tolist()
    return out


def _child(quick: bool) -> dict[str, Any]:
    """`measure_jax` in a child process held to one thread and one CPU."""
    env = {**os.environ, "XLA_FLAGS": XLA_ONE_THREAD, "JAX_PLATFORMS": "cpu"}
    args = [sys.executable, "-m", "chassistune.perf.jax_peer", *(["--quick"] if quick else [])]
    done = subprocess.run(args, env=env, capture_output=True, text=True, check=True)
    return dict(json.loads(done.stdout.strip().splitlines()[-1]))


def figures(quick: bool = False) -> dict[str, float]:
    """Speedups of our kernel (thread CPU, one core) over JAX (process CPU, one core) at the
    bench population and at 1000, JAX's compile time and its largest stop-distance difference."""
    jax = _child(quick)
    if len(jax["cpus"]) != 1:
        raise RuntimeError(f"the JAX child was not held to one CPU: it ran on {jax['cpus']}")
    sc = _scenario()
    out: dict[str, float] = {"jax_compile_s": float(jax["compile_s_50"])}
    for n in POPULATIONS:
        g = _gains(n)
        ours = sc.raw(g, workers=1)

        def run(x: np.ndarray = g) -> None:
            sc.raw(x, workers=1)

        cpu = best_cpu_time(run, _repeats(n, quick))
        suffix = "" if n == 50 else f"_pop{n}"
        jax_cpu = float(jax[f"cpu_s_{n}"])
        out[f"abs_speedup_vs_jax{suffix}"] = jax_cpu / cpu
        out[f"abs_jax_sims_per_s_cpu{suffix}"] = n / jax_cpu
        stopped = ours[:, KL.METRICS["status"]] == KL.STATUS_NAMES.index("stopped")
        d = ours[stopped, KL.METRICS["stop_distance_m"]]
        peer = np.asarray(jax[f"distance_m_{n}"])[stopped]
        out[f"abs_jax_max_rel_err{suffix}"] = float(np.max(np.abs(peer - d) / d))
    return out


def _main() -> None:
    """The child: hold this process to its first allowed CPU, then measure and print JSON."""
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    out = measure_jax("--quick" in sys.argv)
    print(json.dumps({**out, "cpus": sorted(os.sched_getaffinity(0))}))


if __name__ == "__main__":
    _main()
