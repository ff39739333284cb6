"""Exact Mamdani inference against scikit-fuzzy's ControlSystem built from the same description."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from test_fuzzy_schema import SMALL_TOML

from chassistune.errors import InputError
from chassistune.fuzzy import RuleBase, compiled, evaluate, evaluate_named, rulebase_from_dict

pytest.importorskip("skfuzzy")
pytest.importorskip("networkx")
from chassistune.perf.fuzzy import skfuzzy_evaluate, skfuzzy_simulation

TOLERANCE = 5e-4  # exact inference, of the output range
SURFACE_TOLERANCE = 1e-3  # compiled surface


def random_points(rb: RuleBase, n: int, seed: int) -> np.ndarray:
    """Uniform points over the input universes widened by 10 % on each side (tests clipping)."""
    rng = np.random.default_rng(seed)
    lo = np.array([v.universe[0] - 0.1 * v.span for v in rb.inputs])
    hi = np.array([v.universe[1] + 0.1 * v.span for v in rb.inputs])
    return rng.uniform(lo, hi, (n, len(rb.inputs)))


def skfuzzy_at_random_points(rb: RuleBase, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Random points and scikit-fuzzy's outputs there (universe step 1e-3)."""
    description = rb.as_dict()
    simulation = skfuzzy_simulation(description, step=1e-3)
    points = random_points(rb, n, seed)
    return points, skfuzzy_evaluate(simulation, description, points)


def test_builtin_agrees_with_skfuzzy(builtin: RuleBase) -> None:
    points, reference = skfuzzy_at_random_points(builtin, 200, seed=2024)
    spans = np.array([v.span for v in builtin.outputs])
    exact_err = np.abs(evaluate(builtin, points) - reference) / spans
    surface_err = np.abs(compiled(builtin).lookup(points[:, 0], points[:, 1]) - reference) / spans
    print(
        f"{builtin.name}: max error vs scikit-fuzzy, exact {exact_err.max():.2e}, "
        f"compiled surface {surface_err.max():.2e} of the output range"
    )
    assert exact_err.max() < TOLERANCE
    assert surface_err.max() < SURFACE_TOLERANCE


def test_trapezoids_and_gaussians_agree_with_skfuzzy() -> None:
    rb = rulebase_from_dict(tomllib.loads(SMALL_TOML), "small")
    points, reference = skfuzzy_at_random_points(rb, 120, seed=7)
    assert np.max(np.abs(evaluate(rb, points) - reference)) / rb.outputs[0].span < TOLERANCE


def test_skfuzzy_array_mode_matches_its_scalar_mode() -> None:
    rb = rulebase_from_dict(tomllib.loads(SMALL_TOML), "small")
    description = rb.as_dict()
    points = random_points(rb, 3, seed=1)
    batch = skfuzzy_evaluate(skfuzzy_simulation(description, 1e-3), description, points)
    single = skfuzzy_simulation(description, 1e-3)
    for p in range(points.shape[0]):  # one point at a time: scalar inputs
        row = skfuzzy_evaluate(single, description, points[p : p + 1])
        assert row[0, 0] == pytest.approx(batch[p, 0], abs=1e-12)


def test_known_values() -> None:
    classic = load_classic()
    # e = ec = 0: only (ZO, ZO) fires, fully: dkp = ZO, dki = ZO, dkd = NS -> -1 exactly.
    np.testing.assert_allclose(evaluate(classic, [0.0, 0.0])[0], [0.0, 0.0, -1.0], atol=1e-12)
    # At e = 3, ec = -3 only (PB, NB) fires, fully: dkp = ZO, dki = ZO, dkd = PB, a half triangle
    # on [2, 3] whose centroid is 8/3.
    np.testing.assert_allclose(evaluate(classic, [3.0, -3.0])[0], [0.0, 0.0, 8 / 3], atol=1e-12)
    # Inputs are clipped to the universe.
    np.testing.assert_array_equal(evaluate(classic, [9.0, -7.0]), evaluate(classic, [3.0, -3.0]))


def load_classic() -> RuleBase:
    from chassistune.fuzzy import load_rulebase

    return load_rulebase("classic")


def test_batch_rows_equal_single_points(builtin: RuleBase) -> None:
    points = random_points(builtin, 50, seed=3)
    batch = evaluate(builtin, points)
    for p, row in zip(points[:5], batch[:5], strict=True):
        np.testing.assert_array_equal(evaluate(builtin, p)[0], row)


def test_no_rule_fires_gives_the_middle_of_the_universe() -> None:
    description = {
        "inputs": [
            {
                "name": "x",
                "universe": [-1.0, 1.0],
                "sets": [
                    {"name": "A", "shape": "tri", "params": [-1.0, -1.0, -0.5]},
                    {"name": "B", "shape": "tri", "params": [0.5, 1.0, 1.0]},
                ],
            }
        ],
        "outputs": [
            {
                "name": "u",
                "universe": [0.0, 4.0],
                "sets": [
                    {"name": "LO", "shape": "tri", "params": [0.0, 0.0, 1.0]},
                    {"name": "HI", "shape": "tri", "params": [3.0, 4.0, 4.0]},
                ],
            }
        ],
        "rules": [["A", "LO"], ["B", "HI"]],
    }
    rb = rulebase_from_dict(description, "gap")
    np.testing.assert_allclose(evaluate(rb, [[0.0], [-1.0], [1.0]])[:, 0], [2.0, 1 / 3, 11 / 3])


def test_evaluate_named() -> None:
    classic = load_classic()
    out = evaluate_named(classic, {"e": [0.0, 1.0], "ec": 0.0})
    assert set(out) == {"dkp", "dki", "dkd"} and out["dkd"].shape == (2,)
    with pytest.raises(InputError, match=r"unknown input 'de'.*inputs: e, ec"):
        evaluate_named(classic, {"e": 0.0, "de": 1.0})
    with pytest.raises(InputError, match="missing a value for input 'ec'"):
        evaluate_named(classic, {"e": 0.0})
    with pytest.raises(InputError, match="expected shape"):
        evaluate(classic, np.zeros((4, 3)))
