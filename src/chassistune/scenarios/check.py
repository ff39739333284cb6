"""Conformance check of a registered plant, as Gymnasium's `check_env` checks an environment.

`check_plant(name)` builds the plant's default scenario (or a named preset's, on its first road)
with each of its controllers and demands:
batch row i equals the single run of row i bit for bit; finite gain bounds and a finite penalty;
a finite cost, at most PENALTY, for random gains inside the bounds and wild gains outside them;
the spec's key metrics among the scenario's metrics, every trace signal with a unit and of one
length; a plot drawn by the spec's plot function; parameters and metrics that survive a JSON
round trip. The first failure raises `ConformanceError` naming the plant, controller and check.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from chassistune._registry import resolve
from chassistune._rng import make_rng
from chassistune.scenarios.base import PENALTY, Scenario
from chassistune.scenarios.registry import get_plant, plant_spec

N_RANDOM = 4
WILD_SCALES = (-1e3, -1.0, 0.0, 1e3, 1e9)
"""Wild gains: each gain at these multiples of its upper bound (and of 1 when that bound is 0)."""
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


class ConformanceError(AssertionError):
    """A plant that breaks the contract every plant keeps."""


def _fail(plant: str, controller: str, problem: str) -> ConformanceError:
    return ConformanceError(f"plant {plant!r} with controller {controller!r}: {problem}")


def _population(sc: Scenario, rng: np.random.Generator) -> np.ndarray:
    """N_RANDOM rows inside the bounds, then one row per wild scale."""
    k = len(sc.gain_names)
    box = np.array(sc.controller.bounds(), dtype=np.float64).reshape(k, 2)
    inside = box[:, 0] + rng.random((N_RANDOM, k)) * (box[:, 1] - box[:, 0])
    top = np.where(box[:, 1] != 0.0, box[:, 1], 1.0)
    wild = np.array([s * top for s in WILD_SCALES]).reshape(len(WILD_SCALES), k)
    return np.vstack([inside, wild])


def _check_costs(sc: Scenario, gains: np.ndarray, fail: Callable[[str], ConformanceError]) -> None:
    for objective in sc.objectives:
        batch = np.asarray(sc.cost(gains, objective), dtype=np.float64)
        if batch.shape != (gains.shape[0],):
            raise fail(f"cost of {gains.shape[0]} rows has shape {batch.shape} ({objective})")
        if not np.all(np.isfinite(batch)) or np.any(batch > PENALTY):
            rows = np.flatnonzero(~np.isfinite(batch) | (batch > PENALTY)).tolist()
            raise fail(
                f"cost not finite or above PENALTY for rows {rows} ({objective}): "
                f"{batch[rows].tolist()} at gains {gains[rows].tolist()}"
            )
        if objective != sc.default_objective:
            continue  # rows are computed by the same kernel call whatever the objective
        for i in range(gains.shape[0]):
            single = np.asarray(sc.cost(gains[i : i + 1], objective), dtype=np.float64)
            if single.tobytes() != batch[i : i + 1].tobytes():
                raise fail(
                    f"batch row {i} differs from its single run ({objective}): "
                    f"{batch[i]!r} != {single[0]!r}"
                )


def _check_metrics(
    sc: Scenario,
    gains: np.ndarray,
    key_metrics: tuple[str, ...],
    fail: Callable[[str], ConformanceError],
) -> None:
    batch = sc.metrics(gains)
    missing = [m for m in key_metrics if m not in batch]
    if missing:
        raise fail(
            f"key metrics {missing} of the spec are not among the scenario's metrics "
            f"({', '.join(batch)})"
        )
    for name, values in batch.items():
        if np.shape(values) != (gains.shape[0],):
            raise fail(f"metric {name!r} has shape {np.shape(values)}, not ({gains.shape[0]},)")
    for i in range(gains.shape[0]):
        single = sc.metrics(gains[i : i + 1])
        for name, values in batch.items():
            if np.asarray(single[name]).tobytes() != np.asarray(values[i : i + 1]).tobytes():
                raise fail(f"metric {name!r} of batch row {i} differs from its single run")


def _json_round_trip(
    obj: Mapping[str, Any], what: str, fail: Callable[[str], ConformanceError]
) -> None:
    try:
        back = json.loads(json.dumps(obj, allow_nan=False))
    except (TypeError, ValueError) as exc:
        raise fail(f"{what} is not plain JSON: {exc}") from None
    if back != obj:
        raise fail(f"{what} changes in a JSON round trip")


def check_scenario(
    sc: Scenario, key_metrics: tuple[str, ...], plot: str | None, seed: int = 0
) -> None:
    """Every check on one resolved scenario (plot drawn by "module:attr" `plot` unless None)."""

    def fail(problem: str) -> ConformanceError:
        return _fail(sc.plant, sc.controller.name, problem)

    for lo, hi in sc.controller.bounds():
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise fail(f"gain bounds must be finite with lo < hi, got [{lo}, {hi}]")
    if not math.isfinite(PENALTY):
        raise fail("PENALTY is not finite")
    gains = _population(sc, make_rng(seed))
    _check_costs(sc, gains, fail)
    _check_metrics(sc, gains, key_metrics, fail)
    trace = sc.trace(sc.gains_array(None))
    lengths = {len(v) for v in trace.signals.values()}
    if len(lengths) != 1:
        raise fail(f"trace signals differ in length: {sorted(lengths)}")
    no_unit = [s for s in trace.signals if s not in trace.units]
    if no_unit:
        raise fail(f"trace signals without a unit: {no_unit}")
    _json_round_trip(sc.params(), "params()", fail)
    _json_round_trip(trace.metrics, "the trace's metrics", fail)
    if plot is not None:
        fd, path = tempfile.mkstemp(suffix=".png")
        os.close(fd)
        try:
            resolve(plot)(sc, trace, path)  # type: ignore[operator]
            with open(path, "rb") as fh:
                if fh.read(8) != PNG_MAGIC:
                    raise fail(f"plot {plot} wrote no PNG file")
        finally:
            os.remove(path)


def check_plant(
    name: str,
    params: Mapping[str, object] | None = None,
    plot: bool = True,
    preset: str | None = None,
) -> None:
    """Check the registered plant `name` with every controller on `preset` (default: the
    plant's default preset) and that preset's first road.

    `params` overrides parameters (e.g. a shorter simulated time); raises ConformanceError.
    """
    spec = plant_spec(name)
    plant = get_plant(name)
    if spec.default_preset not in plant.presets():
        raise _fail(name, "-", f"default preset {spec.default_preset!r} is not a preset")
    for controller in plant.controllers():
        sc = plant.scenario(preset, None, controller.name, params or {}, 0)
        check_scenario(sc, spec.key_metrics, spec.plot if plot else None)
