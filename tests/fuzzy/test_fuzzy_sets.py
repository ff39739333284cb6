"""Membership functions against scikit-fuzzy's, shoulders included."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.fuzzy.sets import FuzzySet, params_problem

skfuzzy = pytest.importorskip("skfuzzy")

X = np.linspace(-4.0, 4.0, 8001)


@pytest.mark.parametrize(
    ("shape", "params"),
    [
        ("tri", (-1.0, 0.5, 2.0)),
        ("tri", (-3.0, -3.0, -2.0)),  # left shoulder
        ("tri", (2.0, 3.0, 3.0)),  # right shoulder
        ("trap", (-2.0, -1.0, 1.0, 3.0)),
        ("trap", (-3.0, -3.0, 0.0, 1.0)),
        ("trap", (0.0, 1.0, 2.0, 2.0)),
        ("gauss", (0.3, 0.7)),
    ],
)
def test_membership_matches_skfuzzy(shape: str, params: tuple[float, ...]) -> None:
    ours = FuzzySet("A", shape, params).mf(X)
    if shape == "tri":
        ref = skfuzzy.trimf(X, list(params))
    elif shape == "trap":
        ref = skfuzzy.trapmf(X, list(params))
    else:
        ref = skfuzzy.gaussmf(X, *params)
    np.testing.assert_allclose(ours, ref, atol=1e-12)


def test_shoulder_peak_is_one_and_triangle_is_a_trapezoid() -> None:
    left = FuzzySet("NB", "tri", (-3.0, -3.0, -2.0))
    assert left.mf(-3.0) == 1.0 and left.mf(-2.5) == 0.5 and left.mf(-3.5) == 0.0
    tri = FuzzySet("T", "tri", (0.0, 1.0, 3.0))
    trap = FuzzySet("T", "trap", (0.0, 1.0, 1.0, 3.0))
    np.testing.assert_array_equal(tri.mf(X), trap.mf(X))
    assert tri.knots == (0.0, 1.0, 3.0) and tri.core == (1.0, 1.0)


@pytest.mark.parametrize(
    ("shape", "params", "words"),
    [
        ("bell", (1.0, 2.0), "unknown shape"),
        ("tri", (0.0, 1.0), "takes 3 parameters"),
        ("trap", (0.0, 1.0, 2.0), "takes 4 parameters"),
        ("tri", (0.0, 2.0, 1.0), "non-decreasing"),
        ("tri", (1.0, 1.0, 1.0), "zero width"),
        ("gauss", (0.0, 0.0), "sigma"),
        ("gauss", (0.0, float("nan")), "finite"),
    ],
)
def test_bad_parameters_are_explained(shape: str, params: tuple[float, ...], words: str) -> None:
    problem = params_problem(shape, params)
    assert problem is not None and words in problem


def test_good_parameters_pass() -> None:
    assert params_problem("tri", (-1.0, 0.0, 1.0)) is None
    assert params_problem("trap", (-1.0, -1.0, 0.0, 1.0)) is None
    assert params_problem("gauss", (0.0, 0.5)) is None
