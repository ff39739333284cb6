"""The yaw-moment build-up delay on the 7-DOF vehicle (`controllers.yaw_moment_delay`): the front
pressures stay within r_gma q_max t of each other at every step; on a road that brakes both
front wheels alike it never binds (the run equals the one without it, bit for bit), nor does
it with a rate that the pressures' own difference never reaches; on split-mu it lowers the peak
yaw rate of the first second; a bad choice is refused naming the field."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.controllers.yaw_moment_delay import RATE_GAIN
from chassistune.errors import InputError
from chassistune.scenarios.registry import get_plant

VEHICLE = get_plant("abs-vehicle")
ON = {"yaw_moment_delay": "on"}


def _pair(road: str, extra: dict[str, object]):  # type: ignore[no-untyped-def]
    off = VEHICLE.scenario(None, road, "pid", dict(extra), 0)
    on = VEHICLE.scenario(None, road, "pid", {**extra, **ON}, 0)
    return off, on, off.gains_array(None)


def test_on_a_uniform_road_it_never_binds() -> None:
    off, on, g = _pair("dry-concrete", {})
    assert on.gain_names == (*off.gain_names, RATE_GAIN.name)
    rows = np.stack([np.r_[g, r] for r in (RATE_GAIN.lo, 1.0, RATE_GAIN.hi)])
    expected = off.raw(g[None, :])
    for row in on.raw(rows):
        assert np.array_equal(row, expected[0], equal_nan=True)


@pytest.mark.parametrize("steering", ("driver", "fixed"))
def test_on_split_mu_the_front_pressures_stay_within_the_bound(steering: str) -> None:
    _, on, g = _pair("split-mu", {"steering": steering})
    rate = 0.5
    tr = on.trace(np.r_[g, rate]).signals
    p = on.plant_params
    kq_front = 2.0 * p.front_brake_share * p.brake_gain  # design.md: 2 s kq on a front wheel
    gap = np.abs(tr["brake_torque_fl_n_m"] - tr["brake_torque_fr_n_m"]) / kq_front
    bound = rate * p.q_max * tr["time_s"]
    assert np.all(gap <= bound + 1e-9 * p.q_max)
    assert np.any(gap >= 0.99 * bound) and gap.max() > 0.05 * p.q_max  # it binds, and matters


@pytest.mark.parametrize("steering", ("driver", "fixed"))
def test_on_split_mu_it_lowers_the_first_seconds_yaw_rate(steering: str) -> None:
    off, on, g = _pair("split-mu", {"steering": steering})
    yaw_off = off.metrics(g[None, :])["yaw_rate_peak_1s_rad_s"][0]
    m = on.metrics(np.stack([np.r_[g, 0.5], np.r_[g, RATE_GAIN.hi]]))
    assert m["yaw_rate_peak_1s_rad_s"][0] < 0.95 * yaw_off
    assert np.all(m["status"] == "stopped")
    assert m["yaw_rate_peak_1s_rad_s"][1] == pytest.approx(yaw_off, rel=0.05)


def test_the_scenario_says_so_and_a_bad_choice_is_refused() -> None:
    _, on, _ = _pair("split-mu", {})
    assert on.params()["yaw_moment_delay"] == "on"
    with pytest.raises(InputError) as err:
        VEHICLE.scenario(None, "split-mu", "pid", {"yaw_moment_delay": "yes"}, 0)
    assert err.value.field == "params.yaw_moment_delay"
