"""Every metric and trace signal of every plant has its unit read from its name by the one
table (`units`), and that unit is the one the kernel's layout declares."""

from __future__ import annotations

import pytest

from chassistune.units import PRESSURE, si_unit, with_pressure

RUNS = {
    "abs-wheel": {},
    "abs-wheel ecu": {"ecu": "realistic"},
    "abs-vehicle": {},
    "quarter-car": {},
}


@pytest.fixture(scope="module", params=list(RUNS))
def trace_of(request):
    """(scenario, trace) of the pid controller with default gains on each plant's defaults."""
    from chassistune.scenarios.registry import get_plant

    sc = get_plant(request.param.split()[0]).scenario(None, None, "pid", RUNS[request.param])
    return sc, sc.trace(sc.gains_array(None))


def test_every_metric_name_gives_a_unit(trace_of):
    _, trace = trace_of
    missing = [name for name in trace.metrics if not si_unit(name)]
    assert missing == []


def test_every_signal_name_gives_its_declared_unit(trace_of):
    sc, trace = trace_of
    wrong = {
        name: (with_pressure(si_unit(name), sc.pressure_unit), declared)
        for name, declared in trace.units.items()
        if with_pressure(si_unit(name), sc.pressure_unit) != declared
    }
    assert wrong == {}


def test_declared_metric_units_match_the_names():
    from chassistune.sim import abs_vehicle_layout, abs_wheel_ecu_layout, abs_wheel_layout

    for layout in (
        abs_wheel_layout.METRICS,
        abs_wheel_ecu_layout.METRICS,
        abs_vehicle_layout.METRIC_LAYOUT,
    ):
        for slot in layout.slots:
            assert si_unit(slot.name) == slot.unit, (layout.title, slot.name)


@pytest.mark.parametrize(
    ("name", "unit"),
    [
        ("yaw_rate_peak_1s_rad_s", "rad/s"),
        ("peak_yaw_rate_rad_s", "rad/s"),
        ("spring_n_m", "N/m"),
        ("brake_torque_fl_n_m", "N m"),
        ("damper_n_s_m", "N s/m"),
        ("travel_3sigma_m", "m"),
        ("pressure_max", PRESSURE),
    ],
)
def test_names_that_misled_the_parser(name, unit):
    assert si_unit(name) == unit


def test_a_pressure_is_shown_in_the_presets_unit(cli, tmp_path):
    path = tmp_path / "run.csv"
    r = cli("simulate", "abs-wheel", "--preset", "paper-fuzzy-immune", "--csv", str(path))
    assert r.code == 0, r.err
    assert "pressure [kPa]" in path.read_text().splitlines()[0]
    assert PRESSURE not in cli("list", "params", "abs-wheel", "--preset", "sldemo").out


def test_the_three_sigma_travel_is_shown_in_the_unit_its_name_says(cli):
    r = cli("simulate", "quarter-car")
    line = next(x for x in r.out.splitlines() if "travel_3sigma_m" in x)
    assert "travel_3sigma_m [m]" in line, line
