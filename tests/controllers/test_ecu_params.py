"""EcuParams: defaults with units and sources, validation naming the field, seeded draws."""

from __future__ import annotations

import math

import numpy as np
import pytest

from chassistune.controllers.ecu import edge_angle
from chassistune.controllers.ecu_params import (
    EcuParams,
    draw_noise,
    ecu_params,
    field_table,
    orifice_gains,
)
from chassistune.errors import InputError


def test_defaults_carry_unit_and_source() -> None:
    rows = field_table()
    assert {r["name"] for r in rows} >= {"ecu_ts_s", "sensor_teeth", "abs_cutout_m_s"}
    assert all(r["unit"] and r["source"] for r in rows)
    p = EcuParams()
    assert (
        p.ecu_ts_s,
        p.ecu_delay_samples,
        p.sensor_teeth,
        p.sensor_timer_s,
        p.abs_cutout_m_s,
    ) == (5e-3, 1, 48, 1e-6, 2.0)


def test_override_by_name() -> None:
    p, used = ecu_params({"sensor_teeth": "96", "vref": "accel", "other": "1"})
    assert p.sensor_teeth == 96 and p.vref == "accel"
    assert used == {"sensor_teeth", "vref"}


@pytest.mark.parametrize(
    ("values", "field"),
    [
        ({"sensor_teeth": "0"}, "params.sensor_teeth"),
        ({"sensor_teeth": "4.5"}, "params.sensor_teeth"),
        ({"ecu_ts_s": "-1"}, "params.ecu_ts_s"),
        ({"ecu_ts_s": "nan"}, "params.ecu_ts_s"),
        ({"ecu_delay_samples": "-1"}, "params.ecu_delay_samples"),
        ({"ecu_delay_samples": "9"}, "params.ecu_delay_samples"),
        ({"valves": "two-state"}, "params.valves"),
        ({"vref": "magic"}, "params.vref"),
        ({"sensor": "radar"}, "params.sensor"),
        ({"valve_dead_time_s": "0.005"}, "params.valve_dead_time_s"),
        ({"valve_min_on_s": "0.003"}, "params.valve_min_on_s"),
        ({"sensor_spacing_error": "0.3"}, "params.sensor_spacing_error"),
        ({"gain_schedule_floor": "2"}, "params.gain_schedule_floor"),
    ],
)
def test_bad_values_name_the_field(values: dict[str, str], field: str) -> None:
    with pytest.raises(InputError) as exc:
        ecu_params(values)
    assert exc.value.field == field


def test_orifice_gains_need_supply_above_return() -> None:
    kb, kd = orifice_gains(EcuParams(), 1500.0, 0.0)
    assert kb == pytest.approx(2.0 * math.sqrt(1500.0) / 0.15)
    assert kd == pytest.approx(2.0 * math.sqrt(1500.0) / 0.06)
    with pytest.raises(InputError):
        orifice_gains(EcuParams(), 0.0, 0.0)


def test_draws_are_seeded_and_keep_edges_in_order() -> None:
    p = EcuParams(sensor_spacing_error=0.2, sensor_jitter_s=1e-6)
    a, b, c = draw_noise(p, 7), draw_noise(p, 7), draw_noise(p, 8)
    assert np.array_equal(a.spacing_rad, b.spacing_rad)
    assert np.array_equal(a.jitter_s, b.jitter_s)
    assert np.array_equal(a.accel_noise_m_s2, b.accel_noise_m_s2)
    assert not np.array_equal(a.spacing_rad, c.spacing_rad)
    edges = np.array([edge_angle(k, p.sensor_teeth, a.spacing_rad) for k in range(-5, 200)])
    assert np.all(np.diff(edges) > 0.0)
    off = draw_noise(EcuParams(accel_noise_m_s2=0.0), 7)
    assert off.spacing_rad.tolist() == [0.0] and off.jitter_s.tolist() == [0.0]
    assert off.accel_noise_m_s2.tolist() == [0.0]


def test_docs_list_every_parameter() -> None:
    from pathlib import Path

    text = (Path(__file__).parents[2] / "docs" / "ecu.md").read_text()
    for row in field_table():
        assert f"| `{row['name']}` |" in text, row["name"]
