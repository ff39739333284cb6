"""The one statistics module (optimizers_design.md, "Statistics"), used by the optimizer
benchmarks and the studies alike. Built on scipy.stats.

- `summary`: mean, std (sample, ddof = 1), best, worst, median of final best costs (minimization).
- `rank_sum`: Wilcoxon rank-sum (Mann-Whitney U, two-sided, scipy's `mannwhitneyu` with its tie
  correction) of a reference (proposed) method against another at alpha = 0.05. The sign is read
  from the reference's side: "+" the reference is significantly better (lower costs), "-"
  significantly worse, "=" no significant difference. Samples in which every value is the same
  (all tied, e.g. every run reached 0) count as "=" with p = 1.
- `rank_sum_counts`: the +/=/- counts over several functions.
- `friedman`: mean ranks per method across problems (rank 1 = lowest cost, ties averaged) and
  Friedman's chi-square test (scipy's `friedmanchisquare`, which needs at least 3 methods).
- `holm` and `posthoc`: z tests on mean-rank differences, z = (R_i - R_j) / sqrt(k (k + 1) / (6 N))
  (Demsar 2006), against a control method or for all pairs, with Holm's step-down correction.
- `convergence_band`: median and interquartile band of best-so-far curves on an evaluation grid.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats as _st

from chassistune.errors import InputError

ALPHA = 0.05


def _sample(values: ArrayLike, name: str) -> NDArray[np.float64]:
    a = np.asarray(values, dtype=float).ravel()
    if a.size == 0:
        raise InputError(name, "empty sample")
    if np.isnan(a).any():
        raise InputError(name, "sample contains NaN")
    return a


def summary(values: ArrayLike) -> dict[str, float]:
    """Mean, std (ddof = 1; 0 for one value), best (min), worst (max), median and n."""
    a = _sample(values, "values")
    return {
        "mean": float(np.mean(a)),
        "std": float(np.std(a, ddof=1)) if a.size > 1 else 0.0,
        "best": float(np.min(a)),
        "worst": float(np.max(a)),
        "median": float(np.median(a)),
        "n": int(a.size),
    }


def summary_table(results: Mapping[str, Mapping[str, ArrayLike]]) -> list[dict[str, object]]:
    """Rows {problem, method, mean, std, best, worst, median, n} of `results[problem][method]`."""
    rows: list[dict[str, object]] = []
    for problem, by_method in results.items():
        for method, values in by_method.items():
            rows.append({"problem": problem, "method": method, **summary(values)})
    return rows


@dataclass(frozen=True)
class RankSum:
    """Wilcoxon rank-sum outcome, read from the reference method's side."""

    statistic: float  # Mann-Whitney U of the reference sample
    p_value: float
    sign: str  # "+", "=" or "-"


def rank_sum(reference: ArrayLike, other: ArrayLike, alpha: float = ALPHA) -> RankSum:
    """Two-sided Wilcoxon rank-sum of `reference` (lower is better) against `other`."""
    a, b = _sample(reference, "reference"), _sample(other, "other")
    pooled = np.concatenate([a, b])
    if np.all(pooled == pooled[0]):
        return RankSum(statistic=a.size * b.size / 2.0, p_value=1.0, sign="=")
    res = _st.mannwhitneyu(a, b, alternative="two-sided")
    u, p = float(res.statistic), float(res.pvalue)
    # U of the reference below n1 n2 / 2: the reference tends to lower costs
    sign = "=" if p >= alpha else "+" if u < a.size * b.size / 2.0 else "-"
    return RankSum(statistic=u, p_value=p, sign=sign)


def rank_sum_counts(
    reference: Mapping[str, ArrayLike], other: Mapping[str, ArrayLike], alpha: float = ALPHA
) -> dict[str, int]:
    """+/=/- counts of `rank_sum` over the problems both mappings share."""
    counts = {"+": 0, "=": 0, "-": 0}
    for problem in reference:
        if problem in other:
            counts[rank_sum(reference[problem], other[problem], alpha).sign] += 1
    return counts


@dataclass(frozen=True)
class Friedman:
    """Mean ranks (1 = best) per method and Friedman's test across problems."""

    methods: tuple[str, ...]
    mean_ranks: tuple[float, ...]
    statistic: float
    p_value: float
    n_problems: int


def _score_matrix(scores: ArrayLike, methods: Sequence[str]) -> NDArray[np.float64]:
    m = np.asarray(scores, dtype=float)
    if m.ndim != 2 or m.shape[1] != len(methods) or m.shape[0] < 1:
        raise InputError("scores", f"expected (problems, {len(methods)}) scores, got {m.shape}")
    if np.isnan(m).any():
        raise InputError("scores", "scores contain NaN")
    return m


def friedman(scores: ArrayLike, methods: Sequence[str]) -> Friedman:
    """`scores[p, j]`: the score (e.g. mean final cost) of method j on problem p (lower: better)."""
    m = _score_matrix(scores, methods)
    ranks = _st.rankdata(m, axis=1)
    mean = ranks.mean(axis=0)
    if len(methods) >= 3 and m.shape[0] >= 2:
        res = _st.friedmanchisquare(*m.T)
        stat, p = float(res.statistic), float(res.pvalue)
    else:
        stat, p = math.nan, math.nan
    return Friedman(tuple(methods), tuple(float(r) for r in mean), stat, p, int(m.shape[0]))


def holm(p_values: ArrayLike) -> NDArray[np.float64]:
    """Holm's step-down adjusted p-values, in the input order."""
    p = np.asarray(p_values, dtype=float).ravel()
    m = p.size
    order = np.argsort(p, kind="stable")
    scaled = np.minimum(1.0, (m - np.arange(m)) * p[order])
    adjusted = np.empty(m)
    adjusted[order] = np.maximum.accumulate(scaled)
    return adjusted


@dataclass(frozen=True)
class Comparison:
    """One post-hoc comparison of mean ranks (a vs b; positive z: b ranks better than a)."""

    a: str
    b: str
    rank_difference: float  # R_a - R_b
    z: float
    p_value: float
    p_holm: float
    reject: bool


def posthoc(
    scores: ArrayLike, methods: Sequence[str], control: str | None = None, alpha: float = ALPHA
) -> list[Comparison]:
    """Friedman post-hoc z tests with Holm's correction, against `control` or for all pairs."""
    m = _score_matrix(scores, methods)
    n, k = m.shape
    if control is not None and control not in methods:
        raise InputError("control", f"unknown method {control!r} (known: {', '.join(methods)})")
    ranks = _st.rankdata(m, axis=1).mean(axis=0)
    se = math.sqrt(k * (k + 1) / (6.0 * n))
    if control is not None:
        c = list(methods).index(control)
        pairs = [(c, j) for j in range(k) if j != c]
    else:
        pairs = [(i, j) for i in range(k) for j in range(i + 1, k)]
    diffs = np.array([ranks[i] - ranks[j] for i, j in pairs])
    z = diffs / se
    p = 2.0 * _st.norm.sf(np.abs(z))
    p_adj = holm(p)
    return [
        Comparison(
            methods[i], methods[j], float(d), float(zz), float(pp), float(pa), bool(pa < alpha)
        )
        for (i, j), d, zz, pp, pa in zip(pairs, diffs, z, p, p_adj, strict=True)
    ]


def convergence_band(
    histories: Sequence[ArrayLike], history_nfevs: Sequence[ArrayLike], grid: ArrayLike
) -> dict[str, NDArray[np.float64]]:
    """Median, 25th and 75th percentiles of best-so-far curves at the evaluation counts `grid`.

    A run's value at g is its best-so-far after the last iteration that ended at or before g
    evaluations (NaN before its first iteration).
    """
    g = np.asarray(grid, dtype=float)
    curves = np.full((len(histories), g.size), np.nan)
    for r, (h, e) in enumerate(zip(histories, history_nfevs, strict=True)):
        hv, ev = np.asarray(h, dtype=float), np.asarray(e, dtype=float)
        idx = np.searchsorted(ev, g, side="right") - 1
        ok = idx >= 0
        curves[r, ok] = hv[idx[ok]]
    with warnings.catch_warnings():  # columns before any run's first iteration are all NaN
        warnings.simplefilter("ignore", RuntimeWarning)
        q25, med, q75 = np.nanpercentile(curves, [25, 50, 75], axis=0)
    return {"nfev": g, "median": med, "q25": q25, "q75": q75}


def median_ci(values: ArrayLike, seed: int = 0, level: float = 0.95) -> tuple[float, float]:
    """Percentile-bootstrap confidence interval of the median (Efron and Tibshirani 1993, 13.3):
    the (1 - level) / 2 and (1 + level) / 2 quantiles of the medians of 9,999 resamples drawn
    with replacement by a seeded Generator; (nan, nan) for fewer than two values."""
    a = _sample(values, "values")
    if a.size < 2:
        return math.nan, math.nan
    picks = np.random.default_rng(seed).integers(0, a.size, (9999, a.size))
    medians = np.median(a[picks], axis=1)
    lo, hi = np.quantile(medians, [(1.0 - level) / 2.0, (1.0 + level) / 2.0])
    return float(lo), float(hi)
