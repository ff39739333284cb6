"""n candidates x K scenarios on the abs-wheel plant: common random numbers, aggregates equal to
single-scenario runs, mu_scale, validation of a robust and a fragile controller."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.errors import InputError
from chassistune.tuning.problem import build_problem
from chassistune.tuning.robust.aggregate import Aggregate, parse_aggregate
from chassistune.tuning.robust.problem import (
    controller_sensitivity,
    known_for,
    robust_problem,
    validate_gains,
    validation_set,
)
from chassistune.tuning.robust.run import tune_robust
from chassistune.tuning.robust.spec import (
    PassCriterion,
    UncertaintySpec,
    parse_vary,
    spec_from_options,
)

VARY = ["mass_kg=80:120", "mu_scale=0.85:1.15", "v0_m_s=20:35", "actuator_tau_s=0.007:0.013"]
GAINS = np.array(
    [[5000.0, 0.0, 230.0], [1000.0, 0.0, 100.0], [2000.0, 10.0, 50.0], [1.0, 0.0, 0.0]]
)


def spec(aggregate: str = "max", k: int = 8, validate: int = 0) -> UncertaintySpec:
    nominal = build_problem("abs-wheel", "pid")
    return UncertaintySpec(
        parse_vary(VARY, known_for(nominal)), k, "sobol", parse_aggregate(aggregate), validate
    )


def test_max_over_k_scenarios_equals_the_max_of_k_single_scenario_runs_bit_for_bit():
    s = spec("max")
    rp = robust_problem(build_problem("abs-wheel", "pid"), s, seed=11)
    singles = np.stack(
        [build_problem("abs-wheel", "pid", params=row)(GAINS) for row in rp.training.rows()], axis=1
    )
    assert singles.shape == (4, 8)
    np.testing.assert_array_equal(rp(GAINS), singles.max(axis=1))
    np.testing.assert_array_equal(rp.costs(GAINS)[:, :, 0], singles)
    assert rp(GAINS)[3] == 1e9  # a gain row that locks the wheel costs the penalty everywhere


def test_every_candidate_sees_the_same_k_scenarios():
    rp = robust_problem(build_problem("abs-wheel", "pid"), spec("cvar:0.25"), seed=4)
    again = robust_problem(build_problem("abs-wheel", "pid"), spec("cvar:0.25"), seed=4)
    np.testing.assert_array_equal(rp.training.values, again.training.values)
    whole = rp(GAINS)
    for i in range(len(GAINS)):  # a row scored alone, or in another population, costs the same
        np.testing.assert_array_equal(rp(GAINS[i : i + 1]), whole[i : i + 1])
    np.testing.assert_array_equal(rp(GAINS[::-1]), whole[::-1])
    # the grid's scenarios are the draws
    names = rp.training.names
    for row, (sc,) in zip(rp.training.values, rp.grid, strict=True):
        draw = dict(zip(names, row, strict=True))
        assert sc.plant_params.mass_kg == draw["mass_kg"]
        assert sc.plant_params.v0_m_s == draw["v0_m_s"]
        assert sc.plant_params.actuator_tau_s == draw["actuator_tau_s"]
        assert sc.mu_peak == pytest.approx(0.9 * draw["mu_scale"], rel=1e-15)
    agg = Aggregate("cvar", 0.25)
    np.testing.assert_array_equal(whole, np.minimum(agg(rp.costs(GAINS)), 1e9))


@pytest.mark.parametrize("road", ["wet-asphalt", "burckhardt-dry-asphalt", "sldemo-table"])
def test_mu_scale_multiplies_the_whole_curve_and_the_bound_follows(road):
    nominal = build_problem("abs-wheel", "pid", roads=[road]).scenarios[0]
    scaled = build_problem("abs-wheel", "pid", roads=[road], params={"mu_scale": 0.8}).scenarios[0]
    s = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(scaled.tire.mu(s), 0.8 * nominal.tire.mu(s), rtol=1e-14, atol=1e-16)
    assert scaled.target_slip == pytest.approx(nominal.target_slip, rel=1e-6)
    assert scaled.bound_distance_m == pytest.approx(nominal.bound_distance_m / 0.8, rel=1e-12)


def test_mu_scale_is_offered_on_every_road_and_unknown_names_are_refused():
    sldemo = build_problem("abs-wheel", "pid", preset="sldemo")
    assert {"mu_scale", "mass_kg"} <= set(known_for(sldemo))
    assert "slips" not in known_for(sldemo)
    with pytest.raises(InputError, match=r"^vary\.mu_scale: range \[-0\.1, 1\.1\] outside"):
        parse_vary(["mu_scale=-0.1:1.1"], known_for(sldemo))
    with pytest.raises(InputError, match=r"^vary\.dt_s: unknown uncertain parameter"):
        parse_vary(["dt_s=0.001:0.002"], known_for(build_problem("abs-wheel", "pid")))


def test_validation_certifies_a_robust_pid_and_reports_failures_of_a_fragile_one():
    s = spec(validate=300)
    rp = robust_problem(build_problem("abs-wheel", "pid"), s, seed=0)
    draws = validation_set(s, 0)
    assert len(draws) == 300
    np.testing.assert_array_equal(draws.values, validation_set(s, 0).values)
    assert not np.any(np.isin(draws.values, rp.training.values))  # a fresh set
    good = rp.validate(GAINS[0], draws)
    assert (good.failures, good.pass_rate) == (0, 1.0)
    assert good.certificate is not None and good.certificate.eps < 0.01
    # kp 1000, kd 100: within 1.08 x the bound on the nominal road, too long on some draws
    nominal = rp.scenarios[0].metrics(GAINS[1:2])
    assert nominal["stopped"][0] and nominal["distance_ratio"][0] < 1.10
    fragile = rp.validate(GAINS[1], draws)
    assert fragile.failures > 0 and fragile.certificate is None
    assert fragile.as_dict()["certificate"] is None
    assert fragile.as_dict()["worst_distance_ratio"] > 1.10


def test_several_roads_are_scenarios_too():
    s = spec("mean", k=4)
    roads = ["dry-concrete", "wet-asphalt"]
    rp = robust_problem(build_problem("abs-wheel", "pid", roads=roads), s, seed=2)
    c = rp.costs(GAINS[:2])
    assert c.shape == (2, 4, 2)
    for r, road in enumerate(roads):
        single = robust_problem(build_problem("abs-wheel", "pid", roads=[road]), s, seed=2)
        np.testing.assert_array_equal(single.costs(GAINS[:2])[:, :, 0], c[:, :, r])
    np.testing.assert_array_equal(rp(GAINS[:2]), c.reshape(2, -1).mean(axis=1))


def test_the_quarter_car_varies_its_sprung_mass_and_tire_stiffness():
    nominal = build_problem("quarter-car", "pid")
    known = known_for(nominal)
    s = UncertaintySpec(
        parse_vary(["sprung_mass_kg=256:384", "tire_stiffness_n_m=160000:240000"], known),
        8,
        "lhs",
        Aggregate("max"),
    )
    rp = robust_problem(nominal, s, seed=1)
    gains = np.array([[0.0, 0.0, 0.0], [200.0, 50.0, 100.0]])
    costs = rp.costs(gains)
    assert costs.shape == (2, 8, 1)
    np.testing.assert_allclose(costs[0], 3.0, rtol=1e-9)  # zero gains: the passive car, Q = 3
    assert np.all(costs[1] < 3.0)
    assert [sc.vehicle.sprung_mass_kg for (sc,) in rp.grid] == list(rp.training.values[:, 0])
    # no stop in a suspension: validated on its objective, "no worse than passive" (Q <= 3)
    s = UncertaintySpec(
        s.params, 8, "lhs", Aggregate("max"), 16, criterion=PassCriterion(False, True, 0.0, 3.0)
    )
    draws = validation_set(s, 0)
    good = validate_gains(rp.builders, rp.objective, gains[1], draws, s)
    assert good.failures == 0 and good.as_dict()["worst_cost"] < 3.0
    # a negative kp removes damping: worse than passive on every draw
    worse = validate_gains(rp.builders, rp.objective, np.array([-2000.0, 0.0, 0.0]), draws, s)
    assert worse.failures == 16 and worse.as_dict()["worst_cost"] > 3.0


def test_the_known_parameters_of_several_roads_are_those_every_road_has():
    both = known_for(build_problem("abs-wheel", "pid", roads=["dry-concrete", "burckhardt-snow"]))
    assert "mu_scale" in both and "mass_kg" in both
    assert "mu_peak" not in both and "c1" not in both


def test_a_pid_holding_the_peak_slip_is_insensitive_to_the_locked_wheel_friction():
    # the PID keeps the slip at the peak: the falling branch (mu_lock) is hardly visited, so its
    # Sobol indices vanish; the initial speed carries nearly all the variance of the distance
    # ratio (the pressure build-up costs about a fixed distance: a larger share of a short stop)
    nominal = build_problem("abs-wheel", "pid")
    s = UncertaintySpec(parse_vary(["v0_m_s=20:35", "mu_lock=0.6:0.8"], known_for(nominal)), 4)
    rp = robust_problem(nominal, s)
    res = controller_sensitivity(rp.builders[0], s, GAINS[0], n=64, seed=0)
    assert res.names == ("v0_m_s", "mu_lock")
    assert res.total[0] > 0.9 and res.first_order[0] > 0.9
    assert abs(res.total[1]) < 0.02 and abs(res.first_order[1]) < 0.02


def test_a_draw_the_plant_refuses_is_reported_under_the_varied_name():
    nominal = build_problem("abs-wheel", "pid")
    s = UncertaintySpec(parse_vary(["v0_m_s=0.1:0.6"], known_for(nominal)), 4)
    with pytest.raises(
        InputError,
        match=r"^vary\.v0_m_s: a draw the plant refuses: must "
        r"exceed v_stop_m_s = 0.5",
    ):
        robust_problem(nominal, s)


def test_tune_robust_reports_training_and_validation():
    nominal = build_problem("abs-wheel", "pid", seed=3)
    s = spec_from_options(known_for(nominal), VARY, 4, "sobol", "max", 60)
    res = tune_robust(nominal, s, "pso", pop_size=6, max_iter=3, seed=3)
    d = res.as_dict()
    assert d["aggregate"] == "max" and d["uncertainty"]["scenarios"] == 4
    assert d["uncertainty"]["vary"][0] == "mass_kg uniform on [80, 120]"
    assert d["best_cost"] == max(d["training"]["costs"].ravel())
    assert d["training"]["values"].shape == (4, 4)
    v = d["validation"]
    assert v["n"] == 60 and v["failures"] + round(v["pass_rate"] * 60) == 60
    assert (v["certificate"] is None) == (v["failures"] > 0)
    again = tune_robust(
        build_problem("abs-wheel", "pid", seed=3), s, "pso", pop_size=6, max_iter=3, seed=3
    )
    assert again.result.best_gains == res.result.best_gains
    np.testing.assert_array_equal(again.training_costs, res.training_costs)


def test_no_training_scenarios_is_nominal_tuning_validated_on_the_same_draws():
    nominal = build_problem("abs-wheel", "pid")
    s = spec_from_options(known_for(nominal), VARY, 0, "sobol", "max", 20)
    rp = robust_problem(nominal, s, seed=0)
    assert len(rp.training) == 0 and rp.grid == [nominal.scenarios]
    np.testing.assert_array_equal(rp(GAINS), nominal(GAINS))
    robust = robust_problem(
        nominal, spec_from_options(known_for(nominal), VARY, 4, "sobol", "max", 20), seed=0
    )
    np.testing.assert_array_equal(
        validation_set(rp.spec, 0).values, validation_set(robust.spec, 0).values
    )
    assert rp.validate(GAINS[0]).passed.tolist() == robust.validate(GAINS[0]).passed.tolist()


def test_the_distance_ratio_objective_is_the_distance_cost_over_the_bound():
    for road in ("dry-concrete", "wet-asphalt"):
        sc = build_problem("abs-wheel", "pid", roads=[road], params={"v0_m_s": 24.0}).scenarios[0]
        distance = sc.cost(GAINS, "distance")
        ratio = sc.cost(GAINS, "distance_ratio")
        ok = distance < 1e9
        assert ok[:3].all() and not ok[3]
        np.testing.assert_array_equal(ratio[ok], distance[ok] / sc.bound_distance_m)
        assert ratio[3] == 1e9 and np.all(ratio[ok] >= 1.0)  # no run beats the adhesion bound


def test_cvar_aggregates_across_roads_too():
    roads = ["dry-concrete", "wet-asphalt", "burckhardt-snow"]
    per_road = np.stack(
        [build_problem("abs-wheel", "pid", roads=[r])(GAINS) for r in roads], axis=1
    )
    for text, agg in (("cvar:0.5", Aggregate("cvar", 0.5)), ("max", Aggregate("max"))):
        problem = build_problem("abs-wheel", "pid", roads=roads, aggregate=text)
        assert problem.aggregate == text
        np.testing.assert_array_equal(problem(GAINS), np.minimum(agg(per_road), 1e9))
    with pytest.raises(InputError, match=r"^aggregate: cvar ALPHA must be in \(0, 1\]"):
        build_problem("abs-wheel", "pid", aggregate="cvar:1.5")


def test_chassistune_tune_with_uncertainty_does_what_tune_vary_does():
    import chassistune

    table = {
        "vary": {"mass_kg": "80:120", "mu_scale": [0.85, 1.15]},
        "scenarios": 4,
        "aggregate": "cvar:0.5",
        "validate": 10,
    }
    res = chassistune.tune(
        "abs-wheel", "pid", "pso", pop_size=6, max_iter=2, seed=5, uncertainty=table
    )
    nominal = build_problem("abs-wheel", "pid", seed=5)
    s = spec_from_options(
        known_for(nominal), ["mass_kg=80:120", "mu_scale=0.85:1.15"], 4, "sobol", "cvar:0.5", 10
    )
    same = tune_robust(nominal, s, "pso", pop_size=6, max_iter=2, seed=5)
    assert res.result.best_gains == same.result.best_gains
    np.testing.assert_array_equal(res.problem.training.values, same.problem.training.values)
    assert res.as_dict()["validation"] == same.as_dict()["validation"]
    assert res.validation is not None and res.validation.n == 10
