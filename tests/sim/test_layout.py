"""Declared kernel layouts: names map to columns once, pack and decode by name."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.layout import Layout, Slot


def test_pack_and_decode_by_name() -> None:
    lay = Layout("t", (Slot("a", "m"), Slot("b", "s")))
    assert lay["b"] == 1 and len(lay) == 2 and "a" in lay
    assert lay.units == {"a": "m", "b": "s"}
    np.testing.assert_array_equal(lay.pack({"b": 2.0, "a": 1.0}), [1.0, 2.0])
    rows = np.array([[1.0, 2.0], [3.0, 4.0]])
    np.testing.assert_array_equal(lay.decode(rows)["b"], [2.0, 4.0])


def test_refuses_duplicates_and_incomplete_packs() -> None:
    with pytest.raises(ValueError, match="twice"):
        Layout("t", (Slot("a", "m"), Slot("a", "s")))
    lay = Layout("t", (Slot("a", "m"),))
    with pytest.raises(ValueError, match="missing"):
        lay.pack({})
    with pytest.raises(ValueError, match="unknown"):
        lay.pack({"a": 1.0, "z": 2.0})


def test_quarter_car_layouts_name_the_kernel_slots() -> None:
    from chassistune.plants import quarter_car as model
    from chassistune.sim import lyapunov
    from chassistune.sim import quarter_car_kernel as kernel

    assert kernel.PLANT["sprung_mass_kg"] == model.P_MS and len(kernel.PLANT) == model.N_PLANT
    assert kernel.OUTPUTS["force"] == model.OUT_FORCE and len(kernel.OUTPUTS) == model.N_OUT
    assert kernel.RESULT["diverged"] == kernel.R_DIVERGED == kernel.N_RESULT - 1
    assert lyapunov.EXACT["stable"] == lyapunov.E_STABLE == lyapunov.N_EXACT - 1
    assert kernel.RESULT.units["force_rms"] == "N" and kernel.OUTPUTS.units["body_acc"] == "m/s^2"
