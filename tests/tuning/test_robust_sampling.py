"""Training and Monte Carlo sets: reproducible, inside their ranges, stratified."""

from __future__ import annotations

import math
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from chassistune.tuning.robust.sampling import (
    TRAINING,
    VALIDATION,
    monte_carlo_set,
    scenario_stream,
    training_set,
)
from chassistune.tuning.robust.spec import ParamRange, UncertainParam

PARAMS = (
    UncertainParam("mass_kg", "uniform", lo=80.0, hi=120.0),
    UncertainParam(
        "mu_scale", "normal", mean=0.3, sd=0.5, valid=ParamRange(0.0, math.inf, lo_open=True)
    ),
    UncertainParam("v0_m_s", "uniform", lo=20.0, hi=35.0),
)


def draw(seed: int, sampler: str = "sobol", k: int = 16) -> np.ndarray:
    return training_set(PARAMS, k, sampler, scenario_stream(seed, TRAINING)).values


def test_the_training_set_is_fixed_by_the_seed_in_this_and_other_processes():
    a = draw(7)
    np.testing.assert_array_equal(a, draw(7))
    with ProcessPoolExecutor(1) as pool:  # another interpreter: no shared state
        np.testing.assert_array_equal(a, pool.submit(draw, 7).result())
    assert not np.array_equal(a, draw(8))
    assert a.shape == (16, 3)


def test_the_streams_are_independent_and_accept_every_seed_form():
    assert scenario_stream(3, TRAINING).random() != scenario_stream(3, VALIDATION).random()
    first = scenario_stream(3, TRAINING).random(4)
    np.testing.assert_array_equal(
        scenario_stream(np.random.SeedSequence(3), TRAINING).random(4), first
    )
    # the run's Generator (seeded from the same seed) gives the same sets
    np.testing.assert_array_equal(
        scenario_stream(np.random.default_rng(3), TRAINING).random(4), first
    )
    # and the optimizer's own stream is not one of them
    assert np.random.default_rng(3).random() != first[0]
    child = np.random.SeedSequence(3, spawn_key=(2,))  # a study's run seed
    assert scenario_stream(child, TRAINING).random() != first[0]


def test_uniform_draws_are_stratified_and_normal_draws_clipped_to_the_valid_range():
    for sampler in ("sobol", "lhs"):
        v = draw(1, sampler, 64)
        # one point in each of the 64 equal slices of each uniform range (Sobol for 2^m points
        # is a (0, m, d)-net in base 2: its one-dimensional projections are stratified too)
        for col, (lo, hi) in ((0, (80.0, 120.0)), (2, (20.0, 35.0))):
            cells = np.floor((v[:, col] - lo) / (hi - lo) * 64).astype(int)
            assert sorted(cells) == list(range(64)), sampler
        assert np.all(v[:, 1] > 0.0)
    mc = monte_carlo_set(PARAMS, 5000, np.random.default_rng(2)).values
    # normal(0.3, 0.5) clipped at 0: P(x <= 0) = Phi(-0.6) = 0.274 of the draws sit at the edge
    edge = mc[:, 1] == math.nextafter(0.0, 1.0)
    assert abs(edge.mean() - 0.2743) < 0.02
    assert np.all(mc[:, 1] > 0.0)
    assert np.all((mc[:, 0] >= 80.0) & (mc[:, 0] <= 120.0))
