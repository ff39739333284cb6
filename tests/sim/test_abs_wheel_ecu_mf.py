"""The Magic Formula tire in the realistic ECU kernel: the friction it reads is the TIR curve's,
no stop beats the curve's adhesion bound, and a batch row is its single run."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_abs_wheel_mf import CHRONO, COMMONROAD

from chassistune.plants.mf_curve import TIRE_SURFACE, MagicFormulaCurve
from chassistune.plants.tir import TirWarning
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario

CASES = [(CHRONO, TIRE_SURFACE), (COMMONROAD, TIRE_SURFACE), (CHRONO, "ice")]


def _scenario(path: str, road: str, controller: str = "pid", **extra: object) -> AbsWheelScenario:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TirWarning)
        sc = PLANT.scenario(
            "paper-derlsp-ao", road, controller, {"tire": path, "ecu": "realistic", **extra}
        )
    assert isinstance(sc, AbsWheelScenario) and isinstance(sc.tire, MagicFormulaCurve)
    assert sc.ecu is not None
    return sc


@pytest.mark.parametrize(("path", "road"), CASES)
def test_the_friction_read_is_the_curves(path: str, road: str) -> None:
    """Every trace row's friction coefficient is the TIR curve's mu at that row's slip (the
    kernel's piecewise cubic: within its certified 1e-5 of the exact formula)."""
    sc = _scenario(path, road)
    tr = sc.trace(sc.gains_array(None))
    slip, mu = tr.signals["slip"], tr.signals["mu"]
    assert slip.size > 100
    assert np.all((slip >= 0.0) & (slip <= 1.0))
    assert np.max(np.abs(mu[1:] - sc.tire.mu(slip[1:]))) <= 1e-5


@pytest.mark.parametrize(("path", "road"), CASES)
@pytest.mark.parametrize("controller", ["pid", "threshold", "fuzzy-pid"])
def test_no_stop_beats_the_bound(path: str, road: str, controller: str) -> None:
    """Registry defaults and 12 gain rows drawn in the tuning box: every stopped run is longer
    than the adhesion bound of the MF curve's peak (`AbsWheelScenario.bound_distance_m`)."""
    sc = _scenario(path, road, controller)
    box = np.array(sc.controller.bounds(), dtype=float).reshape(-1, 2)
    rows = np.random.default_rng(5).random((12, box.shape[0]))
    gains = np.vstack([sc.gains_array(None), box[:, 0] + rows * (box[:, 1] - box[:, 0])])
    m = sc.metrics(gains)
    stopped = m["status"] == "stopped"
    assert stopped[0], "the registry defaults stop"
    assert np.all(m["stop_distance_m"][stopped] > sc.bound_distance_m)


def test_a_batch_row_is_its_single_run() -> None:
    """Bit for bit, on one thread and on two."""
    sc = _scenario(CHRONO, TIRE_SURFACE)
    box = np.array(sc.controller.bounds(), dtype=float).reshape(-1, 2)
    rows = np.random.default_rng(9).random((40, box.shape[0]))
    gains = box[:, 0] + rows * (box[:, 1] - box[:, 0])
    batch = sc.raw(gains, workers=1)
    for i in (0, 17, 33, 39):
        assert sc.raw(gains[i : i + 1], workers=1).tobytes() == batch[i : i + 1].tobytes()
    assert sc.raw(gains, workers=2).tobytes() == batch.tobytes()
