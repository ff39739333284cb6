"""Step-refinement check of a winner: exact at factor 1, converging, warning above 1e-3."""

from __future__ import annotations

import numpy as np

from chassistune.scenarios.abs_wheel import PLANT
from chassistune.scenarios.refine import refined_scenario, step_refinement


def test_refined_scenario_rebuilds_the_same_scenario() -> None:
    sc = PLANT.scenario("sldemo", "sldemo-table", "bang-bang", {"ts_s": 2e-3})
    same = refined_scenario(sc, 1, {"ts_s": 2e-3})
    g = np.zeros((1, 0))
    assert same.raw(g).tobytes() == sc.raw(g).tobytes()
    fine = refined_scenario(sc, 4, {"ts_s": 2e-3})
    assert fine.plant_params.dt_s == sc.plant_params.dt_s / 4
    assert fine.controller_params == sc.controller_params  # the sample period does not follow dt


def test_smooth_candidate_is_converged_and_chattering_one_warns() -> None:
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    smooth = step_refinement(sc, np.array([500.0, 10.0, 1.0]), {})
    assert smooth.max_rel_change < 1e-3 and smooth.warning is None
    assert smooth.as_dict()["cost_refined"] > 0.0
    chatter = step_refinement(sc, np.array([1e4, 1e4, 1e3]), {})  # 1-5 % off at 1 ms
    assert chatter.max_rel_change > 1e-3 and "dt/4" in (chatter.warning or "")


def test_the_overrides_are_kept_at_the_finer_step() -> None:
    base = {"v0_m_s": 20.0, "mass_kg": 300.0}
    sc = PLANT.scenario("paper-derlsp-ao", "wet-asphalt", "pid", base)
    fine = refined_scenario(sc, 4, base)
    assert (fine.plant_params.v0_m_s, fine.plant_params.mass_kg) == (20.0, 300.0)
    check = step_refinement(sc, np.array([500.0, 10.0, 1.0]), base)
    assert check.cost == float(sc.cost(np.array([[500.0, 10.0, 1.0]]))[0])
