"""Fuzzy figure `fuzzy_speedup_vs_skfuzzy` (design.md 8), and the scikit-fuzzy reference system.

The figure: fuzzy PID gain evaluations per second (`fuzzy_pid_gains` on the compiled `deffao`
surface, one call per (e, de) point, in a compiled loop on one core, as a closed-loop kernel calls
it) against scikit-fuzzy's `ControlSystemSimulation.compute` for the same rule base built from its
`fuzzy show --json` description with universes at step 0.01, one call per point, measured in the
same run. The one-off compilation of the surface is reported apart (`fuzzy_compile_s`).

scikit-fuzzy (and networkx, which its `control` module needs) is imported by this module only; the
tests use `skfuzzy_simulation` as their reference.
"""

from __future__ import annotations

import time
import warnings
from typing import Any

import numpy as np
import skfuzzy as fuzz
from numba import njit
from numpy.typing import NDArray
from skfuzzy import control as ctrl

from chassistune._rng import make_rng
from chassistune.controllers.fuzzy_pid import fuzzy_pid_gains
from chassistune.fuzzy.loader import load_rulebase
from chassistune.fuzzy.surface import SurfaceTable, compile_rulebase
from chassistune.perf.timing import best_time

# Quantization and scale factors of the benchmark: e in [-0.3, 0.3] and de/dt in [-60, 60] map
# onto [-3, 3]; any values would do (the cost does not depend on them).
KE, KEC = 10.0, 0.05
KU = (500.0, 50.0, 100.0)
K0 = (2000.0, 10.0, 200.0)


def skfuzzy_simulation(description: dict[str, Any], step: float) -> Any:
    """A scikit-fuzzy `ControlSystemSimulation` (clipping on, cache off) for a description."""

    def variable(cls: Any, spec: dict[str, Any]) -> Any:
        lo, hi = spec["universe"]
        var = cls(np.linspace(lo, hi, round((hi - lo) / step) + 1), spec["name"])
        if cls is ctrl.Consequent:
            var.defuzzify_method = "centroid"
        for s in spec["sets"]:
            shape, p = s["shape"], s["params"]
            if shape == "tri":
                var[s["name"]] = fuzz.trimf(var.universe, p)
            elif shape == "trap":
                var[s["name"]] = fuzz.trapmf(var.universe, p)
            else:
                var[s["name"]] = fuzz.gaussmf(var.universe, p[0], p[1])
        return var

    inputs = [variable(ctrl.Antecedent, v) for v in description["inputs"]]
    outputs = [variable(ctrl.Consequent, v) for v in description["outputs"]]
    rules = []
    for row in description["rules"]:
        antecedent = inputs[0][row[0]]
        for var, name in zip(inputs[1:], row[1 : len(inputs)], strict=True):
            antecedent = antecedent & var[name]  # scikit-fuzzy's & is min
        consequents = [var[name] for var, name in zip(outputs, row[len(inputs) :], strict=True)]
        rules.append(ctrl.Rule(antecedent, consequents))
    return ctrl.ControlSystemSimulation(ctrl.ControlSystem(rules), clip_to_bounds=True, cache=False)


def skfuzzy_evaluate(
    simulation: Any, description: dict[str, Any], points: NDArray[np.float64]
) -> NDArray[np.float64]:
    """scikit-fuzzy outputs (n, n_outputs) at points (n, n_inputs); arrays go in one call."""
    names = [v["name"] for v in description["inputs"]]
    scalar = points.shape[0] == 1
    for k, name in enumerate(names):
        column = np.ascontiguousarray(points[:, k], dtype=np.float64)
        simulation.input[name] = float(column[0]) if scalar else column
    with warnings.catch_warnings():  # scikit-fuzzy 0.5.0 calls np.maximum with 3 positionals
        warnings.simplefilter("ignore", DeprecationWarning)
        simulation.compute()
    outs = [np.atleast_1d(np.asarray(simulation.output[v["name"]])) for v in description["outputs"]]
    return np.stack(outs, axis=1)


@njit(cache=True, nogil=True)
def _gain_loop(
    table: SurfaceTable, e: NDArray[np.float64], de: NDArray[np.float64]
) -> float:  # pragma: no cover
    total = 0.0
    for p in range(e.size):
        kp, ki, kd = fuzzy_pid_gains(
            table, e[p], de[p], KE, KEC, KU[0], KU[1], KU[2], K0[0], K0[1], K0[2]
        )
        total += kp + ki + kd
    return total


def figures(quick: bool) -> dict[str, float]:
    """`fuzzy_speedup_vs_skfuzzy` with the two rates it divides and the surface compile time."""
    rb = load_rulebase("deffao")
    rng = make_rng(12345)
    n_fast, n_slow = (200_000, 5) if quick else (2_000_000, 30)
    e = rng.uniform(-0.3, 0.3, n_fast)
    de = rng.uniform(-60.0, 60.0, n_fast)

    t0 = time.perf_counter()
    surface = compile_rulebase(rb)
    compile_s = time.perf_counter() - t0
    table = surface.table
    _gain_loop(table, e[:10], de[:10])  # compile the loop before timing it
    fast = best_time(lambda: _gain_loop(table, e, de), repeats=3 if quick else 5) / n_fast

    description = rb.as_dict()
    simulation = skfuzzy_simulation(description, step=0.01)
    points = np.stack([KE * e[:n_slow], KEC * de[:n_slow]], axis=1)
    skfuzzy_evaluate(simulation, description, points[:1])  # first call builds its caches
    t0 = time.perf_counter()
    for p in range(n_slow):
        skfuzzy_evaluate(simulation, description, points[p : p + 1])
    slow = (time.perf_counter() - t0) / n_slow
    return {
        "fuzzy_speedup_vs_skfuzzy": slow / fast,
        "fuzzy_gain_evals_per_s": 1.0 / fast,
        "skfuzzy_evals_per_s": 1.0 / slow,
        "fuzzy_compile_s": compile_s,
    }
