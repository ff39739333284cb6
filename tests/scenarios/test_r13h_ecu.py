"""r13h_epsilon with the realistic ECU (issue 15): k_M from the ABS-off search (no ECU acts on a
constant pressure), z_AL from the ECU-realistic stop."""

from __future__ import annotations

import pytest

from chassistune.scenarios.r13h import adhesion_coefficient, r13h_epsilon

PRESET = "paper-derlsp-ao"
CONTROLLERS = ("threshold", "pid", "fuzzy-pid", "fuzzy-immune-pid")


def _epsilon(controller: str, road: str, vref: str) -> float:
    return r13h_epsilon(controller, PRESET, road, params={"ecu": "realistic", "vref": vref},
                        adhesion=adhesion_coefficient(PRESET, road)).epsilon


@pytest.mark.parametrize("road", ["dry-concrete", "wet-asphalt"])
def test_threshold_abs_passes_with_the_accelerometer_reference(road: str) -> None:
    """Measured 0.850 on dry concrete, 0.883 on wet asphalt (ideal ECU: 0.957, 0.962)."""
    assert 0.75 <= _epsilon("threshold", road, "accel") < 1.0


def test_no_controller_exceeds_one_and_the_slew_reference_locks_the_wheel() -> None:
    """On ice with the accelerometer reference the threshold ABS locks the wheel above 15 km/h
    (epsilon 0; 0.977 with the true speed); with the slew-limited reference every controller
    locks it on dry concrete (the reference drifts onto the wheel, docs/ecu.md)."""
    for controller in CONTROLLERS:
        assert _epsilon(controller, "dry-concrete", "accel") <= 1.0
        assert _epsilon(controller, "dry-concrete", "slew-limited") == 0.0
    assert _epsilon("threshold", "ice", "accel") == 0.0
    assert 0.75 <= _epsilon("threshold", "ice", "true") <= 1.0
