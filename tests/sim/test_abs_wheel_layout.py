"""The ABS kernel's declared layouts: every slot named once with a unit, decoded by name."""

from __future__ import annotations

import numpy as np

from chassistune.scenarios.abs_wheel import PLANT
from chassistune.sim import abs_wheel_layout as KL


def test_every_slot_has_a_unit() -> None:
    for layout in (KL.PLANT, KL.CONTROLLER, KL.METRICS, KL.TRACE):
        assert all(s.unit for s in layout.slots), layout.title


def test_metrics_and_trace_decode_by_name() -> None:
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    raw = sc.raw(np.array([[5000.0, 0.0, 230.0], [1.0, 0.0, 0.0]]), workers=1)
    m = KL.decode_metrics(raw)
    assert set(KL.RUN_METRICS) <= set(m) and list(m["status"]) == ["stopped", "hopeless"]
    assert list(m["stopped"]) == [True, False]  # kp = 1 builds no pressure: far too long
    tr = sc.trace(np.array([5000.0, 0.0, 230.0]))
    assert tuple(tr.signals) == KL.TRACE.names
    assert tr.units == {**KL.TRACE.units, "pressure": sc.pressure_unit}  # the preset's unit
    assert tr.signals["time_s"][-1] == tr.metrics["stop_time_s"]
    assert tr.signals["vehicle_speed_m_s"][-1] == sc.plant_params.v_stop_m_s


def test_controller_vector_defaults_to_zero() -> None:
    c = KL.pack_controller({"amplitude": 2.0, "rulebase": "deffao"})
    assert c[KL.CONTROLLER["amplitude"]] == 2.0 and np.count_nonzero(c) == 1
