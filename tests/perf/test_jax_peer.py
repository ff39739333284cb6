"""The JAX peer of the bench (`perf.jax_abs`) simulates the same closed loop as our kernel: the
same runs stop, at stop distances equal to 1e-6 relative, on a bilinear and a Burckhardt road.
(Slip ITAE is not compared: a chattering run's ITAE is ill-conditioned, docs/abs.md Numerics, and
rounding differences of 1e-16 move it by 1e-4 on the Burckhardt road.) The bench reports the
peer's figures under their names, JAX held to one CPU and agreeing on the timed populations; no
speed is asserted."""

from __future__ import annotations

import importlib.util
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner

from chassistune.cli.bench import bench_command
from chassistune.perf.abs import box_population
from chassistune.scenarios.abs_wheel import PLANT
from chassistune.sim import abs_wheel_layout as KL

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("jax") is None,
    reason="jax (the bench extra, chassistune[bench]) not installed",
)

PEER = """
import json, sys
import numpy as np
from chassistune.perf.jax_abs import simulate
from chassistune.scenarios.abs_wheel import PLANT
road, gains = json.load(sys.stdin)
sc = PLANT.scenario("paper-derlsp-ao", road, "pid")
json.dump(simulate(sc, np.array(gains)).tolist(), sys.stdout)
"""
"""The peer's run in a child process: JAX starts threads when imported, and a test worker that
imported it would later fork (the studies' process executor) with them running."""


def peer_simulate(road: str, gains: np.ndarray) -> np.ndarray:
    done = subprocess.run(
        [sys.executable, "-c", PEER],
        input=json.dumps([road, gains.tolist()]),
        capture_output=True,
        text=True,
        check=True,
    )
    return np.array(json.loads(done.stdout))


@pytest.mark.parametrize("road", ["dry-concrete", "burckhardt-wet-asphalt"])
def test_jax_peer_matches_kernel_on_stop_distance(road: str) -> None:
    sc = PLANT.scenario("paper-derlsp-ao", road, "pid")
    default = [[g.default for g in sc.controller.gains]]
    gains = np.vstack([default, box_population(sc, 7, seed=3)])
    ours = sc.raw(gains, workers=1)
    stopped = ours[:, KL.METRICS["status"]] == KL.STATUS_NAMES.index("stopped")
    peer = peer_simulate(road, gains)
    assert stopped.sum() >= 4  # enough stopped runs for the comparison to mean something
    np.testing.assert_array_equal(peer[:, 2] == 1.0, stopped)
    ref = ours[stopped, KL.METRICS["stop_distance_m"]]
    np.testing.assert_allclose(peer[stopped, 0], ref, rtol=1e-6)


JAX_FIGURES = {
    "jax_compile_s",
    *(
        f"{name}{suffix}"
        for name in ("abs_speedup_vs_jax", "abs_jax_sims_per_s_cpu", "abs_jax_max_rel_err")
        for suffix in ("", "_pop1000")
    ),
}


def test_bench_reports_the_jax_figures() -> None:
    result = CliRunner().invoke(bench_command, ["--only", "jax_peer", "--quick", "--json"])
    assert result.exit_code == 0, result.output
    out = json.loads(result.output)
    assert set(out) == JAX_FIGURES  # no "notes": measured, and the child ran on one CPU
    assert all(math.isfinite(v) and v > 0.0 for k, v in out.items() if "max_rel_err" not in k)
    assert out["abs_jax_max_rel_err"] <= 1e-6 and out["abs_jax_max_rel_err_pop1000"] <= 1e-6
