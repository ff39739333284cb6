"""Exact Mamdani inference, vectorized over many input points.

Rule strength is the min of the input memberships (inputs clipped to their universes), each
output set is activated by the max of the strengths of the rules that conclude it, the implication
clips the set at that level (min), the clipped sets are aggregated by max, and the output is the
centroid of the aggregate (design.md 4; deffao-vehicle-abs section 3, fuzzy-immune-abs eq. 11 read
as a centroid).

The centroid is computed without a sampling grid. The aggregate mu(y) = max_s min(a_s, m_s(y)) is
piecewise linear for `tri` and `trap` sets, with breakpoints only at the sets' knots, where two
sets cross (both fixed per variable), and where a set crosses an activation level (found in closed
form per point). Two-point Gauss-Legendre quadrature between consecutive breakpoints integrates the
area and the moment exactly (to rounding error) and never samples a breakpoint, so vertical flanks
are fine. Gaussian sets add a uniform sub-grid (spacing sigma/16) on which the same quadrature is
fourth-order accurate (relative error below 1e-7).

The fuzzification, rule strengths and set activations are numpy over all points at once; the
centroid is a compiled loop over points (numba), since every point has its own breakpoints.

Where no rule fires the output is the middle of its universe (MATLAB's `evalfis` convention;
scikit-fuzzy raises instead). Complete rule tables over covering sets never get there.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from chassistune.errors import InputError
from chassistune.fuzzy.rulebase import RuleBase, Variable
from chassistune.fuzzy.sets import GAUSS, crossings, packed_mf

_CHUNK = 8192  # points per pass: keeps the (points x rules) temporaries in cache
_GAUSS_STEPS_PER_SIGMA = 16
_MAX_SUBGRID = 20001
_GL_HALF = 0.5 / np.sqrt(3.0)  # 2-point Gauss-Legendre nodes: the midpoint -+ h / (2 sqrt 3)


@dataclass(frozen=True, eq=False)
class _OutputPlan:
    """A variable's sets packed for compiled code, plus its fixed breakpoints."""

    lo: float
    hi: float
    kinds: NDArray[np.int64]  # (S,) TRAP or GAUSS
    params: NDArray[np.float64]  # (S, 4) packed parameters
    fixed_nodes: NDArray[np.float64]  # (F,) sorted, inside [lo, hi]


@lru_cache(maxsize=64)
def _plan(var: Variable) -> _OutputPlan:
    lo, hi = var.universe
    nodes: list[float] = [lo, hi, *var.crossings()]
    for s in var.sets:
        nodes.extend(s.knots)
    sigmas = [s.params[1] for s in var.sets if s.kind == GAUSS]
    if sigmas:
        steps = min(_MAX_SUBGRID, int(np.ceil((hi - lo) * _GAUSS_STEPS_PER_SIGMA / min(sigmas))))
        nodes.extend(np.linspace(lo, hi, steps + 1))
    fixed = np.unique(np.clip(np.asarray(nodes, dtype=np.float64), lo, hi))
    kinds = np.array([s.kind for s in var.sets], dtype=np.int64)
    params = np.array([s.packed for s in var.sets], dtype=np.float64).reshape(-1, 4)
    return _OutputPlan(lo, hi, kinds, params, fixed)


@njit(cache=True, nogil=True)
def _aggregate(act, active, k, kinds, params, y):  # pragma: no cover
    """max over the active sets t of min(act[t], m_t(y))."""
    mu = 0.0
    for j in range(k):
        t = active[j]
        mu = max(mu, min(act[t], packed_mf(kinds[t], params[t], y)))
    return mu


@njit(cache=True, nogil=True)
def _centroid_kernel(act, kinds, params, fixed, lo, hi, out):  # pragma: no cover
    n, n_sets = act.shape
    active = np.empty(n_sets, dtype=np.int64)
    ys = np.empty(fixed.size + 2 + 2 * n_sets * n_sets)
    for p in range(n):
        a = act[p]
        k = 0
        sup_lo, sup_hi = hi, lo
        for s in range(n_sets):
            if a[s] > 0.0:
                active[k] = s
                k += 1
                if kinds[s] == GAUSS:
                    sup_lo, sup_hi = lo, hi
                else:
                    sup_lo = min(sup_lo, params[s, 0])
                    sup_hi = max(sup_hi, params[s, 3])
        sup_lo, sup_hi = max(sup_lo, lo), min(sup_hi, hi)
        if k == 0 or sup_hi <= sup_lo:
            out[p] = 0.5 * (lo + hi)
            continue
        # Breakpoints of the aggregate inside the active support: fixed nodes, and where every
        # active set crosses every activation level not above its own.
        m = 0
        ys[m] = sup_lo
        ys[m + 1] = sup_hi
        m += 2
        for f in fixed:
            if sup_lo < f < sup_hi:
                ys[m] = f
                m += 1
        for jt in range(k):
            t = active[jt]
            for js in range(k):
                if a[active[js]] > a[t]:
                    continue  # min(a_t, m_t) never reaches a higher level: no breakpoint
                left, right = crossings(kinds[t], params[t], a[active[js]])
                ys[m] = min(max(left, sup_lo), sup_hi)
                ys[m + 1] = min(max(right, sup_lo), sup_hi)
                m += 2
        seg = ys[:m]
        seg.sort()
        # The aggregate is linear between breakpoints (tri/trap): 2-point Gauss-Legendre is exact
        # for its area and moment, and never samples a breakpoint (vertical flanks are fine).
        area = 0.0
        moment = 0.0
        for j in range(m - 1):
            h = seg[j + 1] - seg[j]
            if h <= 0.0:
                continue
            mid = 0.5 * (seg[j] + seg[j + 1])
            y1 = mid - _GL_HALF * h
            y2 = mid + _GL_HALF * h
            f1 = _aggregate(a, active, k, kinds, params, y1)
            f2 = _aggregate(a, active, k, kinds, params, y2)
            area += 0.5 * h * (f1 + f2)
            moment += 0.5 * h * (y1 * f1 + y2 * f2)
        out[p] = moment / area if area > 1e-300 else 0.5 * (lo + hi)


def centroid(var: Variable, activation: ArrayLike) -> NDArray[np.float64]:
    """Centroid of max_s min(activation[:, s], m_s(y)) over `var`'s universe, shape (n,)."""
    act = np.ascontiguousarray(np.atleast_2d(np.asarray(activation, dtype=np.float64)))
    plan = _plan(var)
    out = np.empty(act.shape[0])
    _centroid_kernel(act, plan.kinds, plan.params, plan.fixed_nodes, plan.lo, plan.hi, out)
    return out


def firing_strengths(rb: RuleBase, x: ArrayLike) -> NDArray[np.float64]:
    """Rule strengths min_i m_{rule,i}(x_i) for inputs `x` of shape (n, n_inputs): (n, n_rules)."""
    x = np.asarray(x, dtype=np.float64)
    strength = np.ones((x.shape[0], len(rb.rules)))
    for i, var in enumerate(rb.inputs):
        memberships = var.memberships(x[:, i])  # (n, S_i)
        np.minimum(strength, memberships[:, rb.rule_indices[:, i]], out=strength)
    return strength


def set_activations(
    rb: RuleBase, strength: NDArray[np.float64], output: int
) -> NDArray[np.float64]:
    """Activation of every set of output `output`: the max strength of its rules, (n, S)."""
    var = rb.outputs[output]
    column = rb.rule_indices[:, len(rb.inputs) + output]
    act = np.zeros((strength.shape[0], len(var.sets)))
    for s in range(len(var.sets)):
        rules = np.flatnonzero(column == s)
        if rules.size:
            act[:, s] = strength[:, rules].max(axis=1)
    return act


def evaluate(rb: RuleBase, x: ArrayLike) -> NDArray[np.float64]:
    """Exact Mamdani inference: inputs (n, n_inputs) or (n_inputs,) -> outputs (n, n_outputs)."""
    arr = np.asarray(x, dtype=np.float64)
    points = arr.reshape(1, -1) if arr.ndim == 1 else arr
    if points.ndim != 2 or points.shape[1] != len(rb.inputs):
        raise InputError("inputs", f"expected shape (n, {len(rb.inputs)}), got {arr.shape}")
    out = np.empty((points.shape[0], len(rb.outputs)))
    for start in range(0, points.shape[0], _CHUNK):
        strength = firing_strengths(rb, points[start : start + _CHUNK])
        for k, var in enumerate(rb.outputs):
            out[start : start + _CHUNK, k] = centroid(var, set_activations(rb, strength, k))
    return out


def evaluate_named(rb: RuleBase, inputs: Mapping[str, ArrayLike]) -> dict[str, NDArray[np.float64]]:
    """Exact inference from {input name: values}; every input is required, no other names."""
    for name in inputs:
        if name not in rb.input_names:
            raise InputError(
                "inputs",
                f"unknown input {name!r} of rule base {rb.name!r} "
                f"(inputs: {', '.join(rb.input_names)})",
            )
    missing = [n for n in rb.input_names if n not in inputs]
    if missing:
        raise InputError(
            "inputs", f"missing a value for input {missing[0]!r} of rule base {rb.name!r}"
        )
    columns = np.broadcast_arrays(
        *(np.asarray(inputs[n], dtype=np.float64) for n in rb.input_names)
    )
    shape = columns[0].shape
    result = evaluate(rb, np.stack([c.ravel() for c in columns], axis=1))
    return {name: result[:, k].reshape(shape) for k, name in enumerate(rb.output_names)}
