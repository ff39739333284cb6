"""The vehicle kernel's pinned results (tests/golden/abs_vehicle.json) are reproduced bit for bit:
every controller on every road, the options (select-low, driver, per-axle gains, split by road,
high-to-low jump, h = 0) and populations with unstable and NaN gains (`abs_vehicle_pins`)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

import abs_vehicle_pins as pins
from test_abs_wheel_kernel import _has_avx

from chassistune.controllers import laws

PINNED = json.loads(pins.PINNED.read_text())


@pytest.fixture(scope="module")
def computed() -> dict:
    return pins.compute()


def test_every_case_is_pinned(computed):
    assert sorted(computed) == sorted(PINNED)
    n_arrays = sum(len(case["raw"]) + len(case) - 1 for case in PINNED.values())
    assert len(PINNED) == len(pins.SINGLE_CASES) + len(pins.POPULATION_CASES) and n_arrays > 1300


@pytest.mark.parametrize("law", laws.names())
def test_every_vehicle_law_is_pinned(law):
    """A law of the vehicle without pinned runs could change unseen."""
    if laws.get(law).spec(laws.ABS_VEHICLE) is None:
        pytest.skip(f"{law} does not run on the vehicle")
    assert law in pins.CONTROLLERS


@pytest.mark.parametrize("key", sorted(PINNED))
def test_case_is_bitwise_unchanged(computed, key):
    assert computed[key] == PINNED[key]


@pytest.mark.parametrize("law", ["fuzzy-pid", "sliding-mode", "mixed-slip-deceleration", "adrc"])
def test_wild_candidates_end_with_a_status_not_an_exception(law):
    from chassistune.scenarios.abs_vehicle import PLANT
    from chassistune.scenarios.base import PENALTY

    sc = PLANT.scenario(None, "dry-concrete", law)
    pop = pins.population(sc.controller.bounds())
    cost = sc.cost(pop)
    assert np.all(np.isfinite(cost)) and cost[-1] == PENALTY


def test_rows_do_not_depend_on_the_lane_or_the_population():
    """More candidates than lanes (refilled and repacked): each row equals its run alone."""
    from chassistune.scenarios.abs_vehicle import PLANT
    from chassistune.sim import abs_vehicle_layout as VL

    sc = PLANT.scenario(None, "mu-jump", "fuzzy-pid")
    pop = pins.population(sc.controller.bounds())
    pop = np.concatenate([pop, pop[::-1]])[: VL.LANES + 5]
    batch = sc.raw(pop, workers=1)
    for i in (0, 3, VL.LANES - 1, VL.LANES, VL.LANES + 4):
        np.testing.assert_array_equal(sc.raw(pop[i : i + 1], workers=1)[0], batch[i])


@pytest.mark.slow
@pytest.mark.skipif(not _has_avx(), reason="needs an x86 CPU with AVX2")
def test_lane_step_vectorizes():
    """Packed double arithmetic on ymm/zmm registers in the compiled kernel: a call or a branch
    chain added to the lane step would silently fall back to scalar code."""
    import re

    import numba

    from chassistune.scenarios.abs_vehicle import PLANT
    from chassistune.sim import abs_vehicle_kernel as K
    from chassistune.sim import abs_vehicle_layout as VL

    entry = K.entry_point()
    options = {k: v for k, v in entry.targetoptions.items() if k not in ("cache", "nopython")}
    fresh = numba.njit(**options)(entry.py_func)
    sc = PLANT.scenario(None, "dry-concrete", "pid")
    p, geo, surfs, ckind, c, table = sc._kernel_args
    out = np.zeros((1, VL.N_METRICS))
    fresh(
        np.array([[1200.0, 0.0, 20.0]]),
        p,
        geo,
        surfs,
        ckind,
        c,
        table,
        np.zeros((0, VL.N_TRACE)),
        out,
        K.scratch(),
    )
    asm = fresh.inspect_asm(fresh.signatures[0])
    packed = re.findall(r"\bv(?:mul|add|sub|div|fmadd\w*)pd\s[^\n]*%[yz]mm", asm)
    assert len(packed) >= 600, "the lane step no longer vectorizes"


@pytest.mark.slow
@pytest.mark.skipif(not _has_avx(), reason="needs an x86 CPU with AVX2")
def test_general_pass_vectorizes():
    """The general pass (`abs_vehicle_general.general_steps`: split-mu, the driver, an unloaded
    wheel) compiles its stage, load-solve and step-end loops to packed double arithmetic on
    ymm/zmm registers: a call or a branch in their bodies would fall back to scalar code. Every
    division and square root (the kinematics, the load solve's forces and Newton steps, the
    step's end) is packed. The Magic Formula tire's load solve (`magic_formula_load_solve`:
    calls of its force, scalar by nature, in loops of their own) is left out of the inspection:
    an empty function takes its place in the compiled copy."""
    import re
    import types

    import numba

    from chassistune.controllers.laws.dispatch import form_key
    from chassistune.controllers.laws.held_pid import HELD_PID
    from chassistune.scenarios.abs_vehicle import PLANT
    from chassistune.sim import abs_vehicle_general as G
    from chassistune.sim import abs_vehicle_layout as VL
    from chassistune.sim.abs_vehicle_lane import constants, surfaces

    options = {
        k: v for k, v in G.general_steps.targetoptions.items() if k not in ("cache", "nopython")
    }
    source = G.general_steps.py_func
    stub = numba.njit(lambda st, blocks, kc, srf: None)
    bilinear_only = types.FunctionType(
        source.__code__, {**source.__globals__, "magic_formula_load_solve": stub}
    )
    fresh = numba.njit(**options)(bilinear_only)
    p, geo, surfs, _, c, _ = PLANT.scenario(
        None, "split-mu", "pid", {"steering": "driver"}
    )._kernel_args
    args = (np.zeros(VL.N_ROWS * VL.LANES), VL.LANES, constants(p, geo), surfaces(surfs), c, 0)
    fresh(form_key(HELD_PID), args)
    asm = fresh.inspect_asm(fresh.signatures[0])
    packed = re.findall(r"\bv(?:mul|add|sub|div|sqrt|fmadd\w*)pd\s[^\n]*%[yz]mm", asm)
    assert len(packed) >= 600, "the general pass no longer vectorizes"
    scalar = re.findall(r"\bv(?:div|sqrt)sd\s", asm)
    assert not scalar, "a division or square root of the general pass runs on one lane"


@pytest.mark.parametrize("params", [{"steering": "fixed"}, {"steering": "driver"}])
def test_general_path_rows_equal_single_runs_and_threads(params):
    """Split-mu, steering fixed or the driver's: every step of these runs is the general pass's
    (a load solve by Newton's method in each), and a row does not depend on its lane, the
    population (more candidates than lanes: refilled and repacked) or the threads."""
    from chassistune.scenarios.abs_vehicle import PLANT
    from chassistune.sim import abs_vehicle_layout as VL

    sc = PLANT.scenario(None, "split-mu", "pid", params)
    pop = pins.population(sc.controller.bounds())[:12]
    pop = np.concatenate([pop, pop[::-1]])[: VL.LANES + 5]
    batch = sc.raw(pop, workers=1)
    assert np.all(batch[:, VL.M_ITER] > 0), "a run that never needed Newton's method"
    np.testing.assert_array_equal(sc.raw(pop, workers=2), batch)
    for i in range(len(pop)):
        np.testing.assert_array_equal(sc.raw(pop[i : i + 1], workers=1)[0], batch[i])
