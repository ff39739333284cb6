"""The persistent-lane ABS kernel: vectorized, lane-independent, per-row plant parameters,
cached across processes."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numba
import numpy as np
import pytest

from chassistune._branchfree import stack_copy
from chassistune.controllers import laws
from chassistune.controllers.laws.held_pid import HELD_PID
from chassistune.plants.tires import KIND_BILINEAR, KIND_BURCKHARDT, KIND_TABLE
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario
from chassistune.sim import abs_wheel_kernel as K
from chassistune.sim import abs_wheel_layout as KL
from chassistune.sim.abs_wheel_tires import table_tuples, tire_law_mu
from tire_oracle import tire_mu

ROADS = {
    KIND_BILINEAR: ("paper-derlsp-ao", "wet-asphalt"),
    KIND_BURCKHARDT: ("paper-derlsp-ao", "burckhardt-wet-asphalt"),
    KIND_TABLE: ("sldemo", "sldemo-table"),
}
CONTROLLERS = [s.name for s in laws.for_plant(laws.ABS_WHEEL)]


def _population(sc: AbsWheelScenario, n: int, seed: int) -> np.ndarray:
    """n gain rows uniform in the tuning box, the first five scaled far outside it."""
    bounds = [(g.lo, g.hi) for g in sc.controller.gains]
    if not bounds:
        return np.zeros((n, 0))
    rng = np.random.default_rng(seed)
    lo, hi = np.array(bounds).T
    g = lo + (hi - lo) * rng.random((n, len(bounds)))
    g[:5] *= rng.uniform(2.0, 50.0, (5, len(bounds)))
    return g


@pytest.mark.parametrize("law", sorted(ROADS))
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_batch_row_equals_single_run_and_threads_agree(law: int, controller: str) -> None:
    sc = PLANT.scenario(*ROADS[law], controller)
    n = K.LANES + 13  # more candidates than lanes: lanes are refilled and repacked
    g = _population(sc, n, law * 10 + CONTROLLERS.index(controller))
    batch = sc.raw(g, workers=1)
    assert np.all(np.isin(batch[:, KL.METRICS["status"]], [0, 1, 2, 3]))
    for i in range(0, n, 4):
        assert sc.raw(g[i : i + 1], workers=1).tobytes() == batch[i : i + 1].tobytes()
    assert sc.raw(g, workers=2).tobytes() == batch.tobytes()


def test_an_unknown_law_kind_runs_no_law_and_diverges() -> None:
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "bang-bang")
    p, kind, coef, xs, ys, _, c, table = sc._kernel_args
    out = np.zeros((1, len(KL.METRICS)))
    unknown = len(laws.names())
    empty = np.zeros((0, len(KL.TRACE)))
    K.simulate_abs_wheel(np.zeros((1, 0)), p, kind, coef, xs, ys, unknown, c, table, empty, out)
    assert KL.STATUS_NAMES[int(out[0, KL.METRICS["status"]])] == "diverged"


def test_diverging_candidates_end_diverged_with_finite_penalty() -> None:
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    g = np.array([[5000.0, 0.0, 230.0], [1e308, 1e308, 0.0], [-1e4, 0.0, -1e3]])
    m = sc.metrics(g)
    assert m["status"][0] == "stopped" and m["status"][1] == "diverged"
    assert np.all(np.isfinite(sc.cost(g)))


@numba.njit
def _tire_law_many(law, s, c4, xc_tuple, xs_tuple, ys_tuple):  # type: ignore[no-untyped-def]
    xc, xs, ys = stack_copy(xc_tuple), stack_copy(xs_tuple), stack_copy(ys_tuple)
    out = np.empty(s.size)
    for i in range(s.size):
        out[i] = tire_law_mu(law, s[i], c4[0], c4[1], c4[2], c4[3], xc, xs, ys)
    return out


def test_tire_laws_equal_the_physics_module_bitwise() -> None:
    s = np.concatenate([np.linspace(0.0, 1.0, 2001), [0.05, 0.2, 0.95, np.nan]])
    for preset, road in ROADS.values():
        tire = PLANT.scenario(preset, road, "pid").tire
        kind, coef, xs, ys = tire.kernel_data()
        c4 = np.zeros(4)
        c4[: len(coef)] = coef
        xc, xp, yp = table_tuples(xs, ys)
        ours = _tire_law_many(kind, s, c4, xc, xp, yp)
        ref = np.array([tire_mu(kind, coef, xs, ys, x) for x in s])
        assert ours.tobytes() == ref.tobytes(), road


def test_per_row_plant_parameters() -> None:
    """A plant row per candidate gives what a scenario with those parameters gives."""
    base = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    heavy = PLANT.scenario(
        "paper-derlsp-ao",
        "dry-concrete",
        "pid",
        {"mass_kg": 130.0, "actuator_tau_s": 0.02, "v0_m_s": 25.0},
    )
    g = _population(base, 40, 3)
    p_base, kind, coef, xs, ys, ck, c, table = base._kernel_args
    p_heavy = heavy._kernel_args[0]
    rows = np.where((np.arange(40) % 3 == 1)[:, None], p_heavy, p_base)
    out = np.zeros((40, len(KL.METRICS)))
    K.simulate_abs_wheel(g, rows, kind, coef, xs, ys, ck, c, table, np.zeros((0, 10)), out)
    assert out[0::3].tobytes() == base.raw(g[0::3], workers=1).tobytes()
    assert out[1::3].tobytes() == heavy.raw(g[1::3], workers=1).tobytes()


def _has_avx() -> bool:
    try:
        return " avx2 " in Path("/proc/cpuinfo").read_text().replace("\n", " ")
    except OSError:
        return False


@pytest.mark.slow
@pytest.mark.skipif(not _has_avx(), reason="needs an x86 CPU with AVX2")
@pytest.mark.parametrize("method", [K.RK3, K.RK4])
@pytest.mark.parametrize("law", sorted(ROADS))
def test_vector_loops_vectorize(law: int, method: int) -> None:
    """Packed double arithmetic on ymm/zmm registers in each compiled vector loop: a call or a
    branch chain added to the lane step would silently fall back to scalar code."""
    steps = K._lane_steps_of(law, method, HELD_PID)

    @numba.njit(_nrt=False)  # type: ignore[misc]
    def run(st, c4, xc_tuple, xs_tuple, ys_tuple, c):  # type: ignore[no-untyped-def]
        xc, xs, ys = stack_copy(xc_tuple), stack_copy(xs_tuple), stack_copy(ys_tuple)
        tire = (c4[0], c4[1], c4[2], c4[3], xc, xs, ys, K._NO_POLY)
        return steps(st, K.LANES, 1e-3, 5e-4, 1e-3 / 6.0, 100.0, 0.1, 0, tire, c)

    _p, _kind, coef, xs, ys, _ck, c, _table = PLANT.scenario(*ROADS[law], "pid")._kernel_args
    c4 = np.zeros(4)
    c4[: len(coef)] = coef
    run(np.zeros(K.N_ROWS * K.LANES), c4, *table_tuples(xs, ys), c)
    asm = steps.inspect_asm(steps.signatures[0])
    packed = re.findall(r"\bv(?:mul|add|sub|div|fmadd\w*)pd\s[^\n]*%[yz]mm", asm)
    scalar = re.findall(r"\bv(?:mul|add|sub|div)sd\s", asm)
    print(f"law {law}, RK{method}: {len(packed)} packed, {len(scalar)} scalar arithmetic")
    assert len(packed) >= 150, "the lane step no longer vectorizes"


_CACHE_PROBE = """
import json, os, numpy as np
from chassistune.scenarios.abs_wheel import PLANT
from chassistune.sim import abs_wheel_kernel as K
for preset, road in %r:
    PLANT.scenario(preset, road, "pid").raw(np.array([[5000.0, 0.0, 230.0]]), workers=1)
f = K.entry_point()
stats = {"entry": [sum(f.stats.cache_hits.values()), sum(f.stats.cache_misses.values())]}
print(json.dumps({"cache_dir": os.environ["NUMBA_CACHE_DIR"], "stats": stats}))
"""


@pytest.mark.slow
def test_numba_cache_hits_in_a_second_process(tmp_path: Path) -> None:
    """The entry point loads from numba's disk cache in a new process: no compilation, no new
    cache files (the package's own source-keyed cache folder, in a private cache home: the
    user's cache neither helps nor is touched)."""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path)
    code = _CACHE_PROBE % (list(ROADS.values()),)

    def probe() -> dict:
        res = subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
        )
        return json.loads(res.stdout.strip().splitlines()[-1])

    folder = Path(probe()["cache_dir"])  # compiles and stores: the private cache is cold
    assert folder.is_relative_to(tmp_path / "chassistune")
    files = sorted(str(p) for p in folder.rglob("*"))
    assert any(p.endswith(".nbi") for p in files)
    second = probe()
    assert sorted(str(p) for p in folder.rglob("*")) == files
    hits, misses = second["stats"]["entry"]
    assert hits >= 1 and misses == 0, f"entry point: {hits} hits, {misses} misses"
