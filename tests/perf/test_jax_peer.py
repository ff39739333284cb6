"""The JAX peer of the bench (`perf.jax_abs`) simulates the same closed loop as our kernel: the
same runs stop, at stop distances equal to 1e-6 relative, on a bilinear and a Burckhardt road.
(Slip ITAE is not compared: a chattering run's ITAE is ill-conditioned, docs/abs.md Numerics, and
rounding differences of 1e-16 move it by 1e-4 on the Burckhardt road.)"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("jax", reason="jax (the bench extra, chassistune[bench]) not installed")

from chassistune.perf.abs import box_population
from chassistune.perf.jax_abs import simulate
from chassistune.scenarios.abs_wheel import PLANT
from chassistune.sim import abs_wheel_layout as KL


@pytest.mark.parametrize("road", ["dry-concrete", "burckhardt-wet-asphalt"])
def test_jax_peer_matches_kernel_on_stop_distance(road: str) -> None:
    sc = PLANT.scenario("paper-derlsp-ao", road, "pid")
    default = [[g.default for g in sc.controller.gains]]
    gains = np.vstack([default, box_population(sc, 7, seed=3)])
    ours = sc.raw(gains, workers=1)
    stopped = ours[:, KL.METRICS["status"]] == KL.STATUS_NAMES.index("stopped")
    peer = simulate(sc, gains)
    assert stopped.sum() >= 4  # enough stopped runs for the comparison to mean something
    np.testing.assert_array_equal(peer[:, 2] == 1.0, stopped)
    ref = ours[stopped, KL.METRICS["stop_distance_m"]]
    np.testing.assert_allclose(peer[stopped, 0], ref, rtol=1e-6)
