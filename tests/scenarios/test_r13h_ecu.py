"""r13h_epsilon with the realistic ECU: k_M from the ABS-off search (no ECU acts on a
constant pressure), z_AL from the ECU-realistic stop."""

from __future__ import annotations

import pytest

from chassistune.scenarios.r13h import adhesion_coefficient, r13h_epsilon

PRESET = "paper-derlsp-ao"
CONTROLLERS = ("threshold", "pid", "fuzzy-pid", "fuzzy-immune-pid")


def _epsilon(controller: str, road: str, vref: str) -> float:
    return r13h_epsilon(
        controller,
        PRESET,
        road,
        params={"ecu": "realistic", "vref": vref},
        adhesion=adhesion_coefficient(PRESET, road),
    ).epsilon


@pytest.mark.parametrize("road", ["dry-concrete", "wet-asphalt", "ice"])
def test_threshold_abs_passes_with_the_default_reference(road: str) -> None:
    """The default reference (accelerometer, re-anchored after 20 ms of agreement): measured
    0.846 on dry concrete, 0.864 on wet asphalt, 0.811 on ice (ideal ECU: 0.957, 0.962, 0.983;
    before the 20 ms rule the threshold ABS locked the wheel on ice, epsilon 0)."""
    assert 0.75 <= _epsilon("threshold", road, "accel") < 1.0


@pytest.mark.parametrize("road", ["dry-concrete", "wet-asphalt", "ice"])
def test_no_controller_exceeds_one_and_the_slew_reference_locks_the_wheel(road: str) -> None:
    """With the default reference no controller locks the wheel (epsilon > 0.5; the continuous
    slip controllers on ice score 0.61-0.72: the accelerometer bias lifts the reference over the
    45 s stop) nor exceeds 1; with the slew-limited reference every controller locks it (the
    reference drifts onto the wheel, docs/ecu.md)."""
    for controller in CONTROLLERS:
        assert 0.5 < _epsilon(controller, road, "accel") <= 1.0
        assert _epsilon(controller, road, "slew-limited") == 0.0
    assert 0.75 <= _epsilon("threshold", road, "true") <= 1.0
