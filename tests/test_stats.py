"""The statistics module against hand-computed cases and scipy."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats as st

from chassistune import stats


def test_summary_by_hand() -> None:
    s = stats.summary([4.0, 1.0, 3.0, 2.0])
    assert s == {
        "mean": 2.5,
        "std": pytest.approx(math.sqrt(5 / 3)),
        "best": 1.0,
        "worst": 4.0,
        "median": 2.5,
        "n": 4,
    }
    assert stats.summary([7.0])["std"] == 0.0
    rows = stats.summary_table({"F1": {"ao": [1, 2], "de": [3, 3]}})
    assert [(r["problem"], r["method"], r["mean"]) for r in rows] == [
        ("F1", "ao", 1.5),
        ("F1", "de", 3.0),
    ]
    with pytest.raises(ValueError, match="NaN"):
        stats.summary([1.0, float("nan")])


def test_rank_sum_signs_by_hand() -> None:
    low, high = [1, 2, 3, 4, 5], [6, 7, 8, 9, 10]
    r = stats.rank_sum(low, high)
    assert r.sign == "+" and r.statistic == 0.0
    assert r.p_value == pytest.approx(2 / 252)  # exact: 2 of C(10, 5) orderings are as extreme
    assert stats.rank_sum(high, low).sign == "-"
    assert stats.rank_sum([1, 2, 3], [1, 2, 3]).sign == "="


def test_all_tied_samples_count_as_equal() -> None:
    r = stats.rank_sum([0.0] * 30, [0.0] * 30)
    assert (r.sign, r.p_value) == ("=", 1.0)
    assert stats.rank_sum([0.0] * 30, [1.0] * 30).sign == "+"


def test_rank_sum_agrees_with_scipy() -> None:
    rng = np.random.default_rng(0)
    for shift in (0.0, 0.3, 1.0, -1.0):
        a, b = rng.normal(0, 1, 30), rng.normal(shift, 1, 30)
        r = stats.rank_sum(a, b)
        ref = st.mannwhitneyu(a, b, alternative="two-sided")
        assert r.p_value == pytest.approx(ref.pvalue) and r.statistic == ref.statistic
        z = st.ranksums(a, b)  # no ties here: the normal approximation tells the same story
        assert (r.p_value < 0.05) == (z.pvalue < 0.05)
        if r.sign != "=":
            assert (r.sign == "+") == (np.median(a) < np.median(b))


def test_rank_sum_counts() -> None:
    ref = {"F1": [1, 2, 3, 4, 5], "F2": [0, 0, 0], "F3": [9, 9.5, 10, 11, 12], "F4": [1]}
    other = {"F1": [6, 7, 8, 9, 10], "F2": [0, 0, 0], "F3": [1, 2, 3, 4, 5]}
    assert stats.rank_sum_counts(ref, other) == {"+": 1, "=": 1, "-": 1}


def test_friedman_by_hand_and_against_scipy() -> None:
    scores = [[1.0, 2.0, 3.0], [0.1, 0.2, 0.3], [5.0, 6.0, 7.0]]
    fr = stats.friedman(scores, ["a", "b", "c"])
    assert fr.mean_ranks == (1.0, 2.0, 3.0)
    # chi2 = 12 N / (k (k + 1)) sum R_j^2 - 3 N (k + 1) = 3 * 14 - 36 = 6, p = exp(-3)
    assert fr.statistic == pytest.approx(6.0) and fr.p_value == pytest.approx(math.exp(-3))
    rng = np.random.default_rng(1)
    m = rng.random((12, 4))
    m[3, 1] = m[3, 2]  # a tie: averaged ranks
    fr = stats.friedman(m, list("abcd"))
    ref = st.friedmanchisquare(*m.T)
    assert fr.statistic == pytest.approx(ref.statistic) and fr.p_value == pytest.approx(ref.pvalue)
    assert fr.mean_ranks == pytest.approx(tuple(st.rankdata(m, axis=1).mean(axis=0)))
    with pytest.raises(ValueError, match="scores"):
        stats.friedman(m, ["a", "b"])


def test_holm_by_hand() -> None:
    np.testing.assert_allclose(stats.holm([0.01, 0.04, 0.03]), [0.03, 0.06, 0.06])
    np.testing.assert_allclose(stats.holm([0.5, 0.001]), [0.5, 0.002])


def test_posthoc_by_hand() -> None:
    scores = [[1.0, 2.0, 3.0], [0.1, 0.2, 0.3], [5.0, 6.0, 7.0]]
    comps = stats.posthoc(scores, ["a", "b", "c"], control="a")
    se = math.sqrt(3 * 4 / (6 * 3))
    assert [(c.a, c.b) for c in comps] == [("a", "b"), ("a", "c")]
    assert comps[1].z == pytest.approx(-2.0 / se)
    p_ac = 2 * st.norm.sf(2.0 / se)
    p_ab = 2 * st.norm.sf(1.0 / se)
    assert comps[1].p_value == pytest.approx(p_ac)
    assert comps[1].p_holm == pytest.approx(min(1, 2 * p_ac))
    assert comps[0].p_holm == pytest.approx(max(min(1, 2 * p_ac), p_ab))
    assert comps[1].reject == (2 * p_ac < 0.05)
    assert len(stats.posthoc(scores, ["a", "b", "c"])) == 3
    with pytest.raises(ValueError, match="unknown method"):
        stats.posthoc(scores, ["a", "b", "c"], control="z")


def test_convergence_band() -> None:
    hist = [[5.0, 3.0, 1.0], [4.0, 4.0, 2.0], [6.0, 2.0, 0.0]]
    nfev = [[10, 20, 30], [10, 20, 30], [10, 20, 30]]
    band = stats.convergence_band(hist, nfev, [5, 10, 25, 30])
    assert np.isnan(band["median"][0])
    np.testing.assert_allclose(band["median"][1:], [5.0, 3.0, 1.0])
    np.testing.assert_allclose(band["q25"][1:], [4.5, 2.5, 0.5])


def test_median_ci_brackets_the_median_and_narrows_with_more_seeds() -> None:
    rng = np.random.default_rng(3)
    small, large = rng.normal(1.1, 0.05, 10), rng.normal(1.1, 0.05, 200)
    lo, hi = stats.median_ci(small, seed=1)
    assert lo <= np.median(small) <= hi
    assert stats.median_ci(small, seed=1) == (lo, hi)  # same seed, same interval
    lo2, hi2 = stats.median_ci(large, seed=1)
    assert hi2 - lo2 < hi - lo and lo2 < 1.1 < hi2
    assert all(math.isnan(x) for x in stats.median_ci([1.0]))
