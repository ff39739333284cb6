"""A scikit-fuzzy ControlSystem built from a `fuzzy show --json` description (tests only)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np


def _membership(fuzz: Any, universe: np.ndarray, shape: str, params: list[float]) -> np.ndarray:
    if shape == "tri":
        return fuzz.trimf(universe, params)
    if shape == "trap":
        return fuzz.trapmf(universe, params)
    return fuzz.gaussmf(universe, params[0], params[1])


def build_simulation(description: dict[str, Any], step: float) -> Any:
    """A `ControlSystemSimulation` (cache off, clipping on) for the description."""
    import skfuzzy as fuzz
    from skfuzzy import control as ctrl

    def variable(cls: Any, spec: dict[str, Any]) -> Any:
        lo, hi = spec["universe"]
        n = round((hi - lo) / step)
        var = cls(np.linspace(lo, hi, n + 1), spec["name"])
        if cls is ctrl.Consequent:
            var.defuzzify_method = "centroid"
        for s in spec["sets"]:
            var[s["name"]] = _membership(fuzz, var.universe, s["shape"], s["params"])
        return var

    inputs = [variable(ctrl.Antecedent, v) for v in description["inputs"]]
    outputs = [variable(ctrl.Consequent, v) for v in description["outputs"]]
    rules = []
    for row in description["rules"]:
        antecedent = inputs[0][row[0]]
        for var, name in zip(inputs[1:], row[1 : len(inputs)], strict=True):
            antecedent = antecedent & var[name]
        consequents = [var[name] for var, name in zip(outputs, row[len(inputs) :], strict=True)]
        rules.append(ctrl.Rule(antecedent, consequents))
    return ctrl.ControlSystemSimulation(ctrl.ControlSystem(rules), clip_to_bounds=True, cache=False)


def evaluate(simulation: Any, description: dict[str, Any], points: np.ndarray) -> np.ndarray:
    """scikit-fuzzy outputs (n, n_outputs) at input points (n, n_inputs), in one array call."""
    for k, spec in enumerate(description["inputs"]):
        simulation.input[spec["name"]] = np.ascontiguousarray(points[:, k], dtype=np.float64)
    with warnings.catch_warnings():  # scikit-fuzzy 0.5.0 calls np.maximum with 3 positionals
        warnings.simplefilter("ignore", DeprecationWarning)
        simulation.compute()
    return np.stack(
        [np.asarray(simulation.output[v["name"]]) for v in description["outputs"]], axis=1
    )
