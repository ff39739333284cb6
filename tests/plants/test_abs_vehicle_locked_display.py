"""The 7-DOF vehicle's locked wheels as shown: slip 1 on a wheel that stands still while the car
moves (the trace keeps the ECU's slip), and a lock time that says it is summed over the four
wheels."""

from __future__ import annotations

import numpy as np

from chassistune.scenarios.abs_vehicle import PLANT
from chassistune.scenarios.registry import plant_spec
from chassistune.sim import abs_vehicle_layout as VL

WHEELS = ("fl", "fr", "rl", "rr")


def trace(road: str, controller: str):
    sc = PLANT.scenario(None, road, controller, {"steering": "fixed"})
    return sc.trace(sc.gains_array(None))


def test_a_locked_wheel_is_shown_with_slip_1_and_the_record_is_kept() -> None:
    """Split-mu with fixed steering and no ABS: the car spins with all four wheels locked; the
    ECU's slip, (u - w R)/|V| clipped to [0, 1], reads 0 while a wheel slides backwards, the
    shown slip reads 1 wherever the wheel stands still and the car moves."""
    tr = trace("split-mu", "none")
    rec, shown = tr.signals, tr.shown
    moving = rec["speed_m_s"] > 0.0
    for w in WHEELS:
        locked = (rec[f"wheel_speed_{w}_m_s"] == 0.0) & moving
        assert locked.sum() > 1000
        assert np.any(rec[f"slip_{w}"][locked] == 0.0)  # the recorded slip of a sliding wheel
        assert np.all(shown[f"slip_{w}"][locked] == 1.0)
        assert np.array_equal(shown[f"slip_{w}"][~locked], rec[f"slip_{w}"][~locked])
    assert all(np.array_equal(shown[k], v) for k, v in rec.items() if not k.startswith("slip_"))


def test_an_abs_run_without_locking_is_shown_as_recorded() -> None:
    tr = trace("dry-concrete", "pid")
    assert tr.metrics["locked_time_s"] == 0.0
    assert all(np.array_equal(tr.shown[k], v) for k, v in tr.signals.items())


def test_the_lock_time_says_it_is_a_sum_over_the_four_wheels(cli) -> None:
    """The metric is each wheel's locked time added up: a spinning car with four locked wheels
    gathers more of it than the run lasts; its label says so, the single wheel's does not."""
    m = trace("split-mu", "none").metrics
    assert m["stop_time_s"] < m["locked_time_s"] <= 4 * m["stop_time_s"]
    vehicle, wheel = plant_spec("abs-vehicle"), plant_spec("abs-wheel")
    assert vehicle.metric_unit("locked_time_s", "s") == "s, summed over the four wheels"
    assert wheel.metric_unit("locked_time_s", "s") == "s"
    assert (
        "summed over the four wheels" in dict(vehicle.view.generalization_metrics)["locked_time_s"]
    )
    slot = VL.METRIC_LAYOUT.slots[VL.M_LOCKED]
    assert slot.name == "locked_time_s" and "summed over the four wheels" in slot.description
    r = cli("simulate", "abs-vehicle", "--road", "split-mu", "--param", "steering=fixed")
    assert r.code == 0, r.err
    assert "locked_time_s [s, summed over the four wheels]" in r.out


def test_the_csv_and_the_plot_show_the_locked_slip(cli, tmp_path) -> None:
    csv_path, png = tmp_path / "trace.csv", tmp_path / "trace.png"
    r = cli("simulate", "abs-vehicle", "--road", "split-mu", "--controller", "none",
            "--param", "steering=fixed", "--csv", str(csv_path), "--plot", str(png))  # fmt: skip
    assert r.code == 0, r.err
    header = csv_path.read_text().splitlines()[0].split(",")
    rows = np.loadtxt(csv_path, delimiter=",", skiprows=1)
    col = {name.split(" [")[0]: i for i, name in enumerate(header)}
    shown = trace("split-mu", "none").shown
    for w in WHEELS:
        np.testing.assert_array_equal(rows[:, col[f"slip_{w}"]], shown[f"slip_{w}"])
    assert png.stat().st_size > 0
