"""ISO 8608 road generation: class table, noise intensity, PSD of the generated profile."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.signal import welch

from chassistune.errors import InputError
from chassistune.plants import iso_roads as R
from chassistune.plants.roads import ISO_CLASSES, roughness_class


def test_class_table_is_iso_8608_geometric_means() -> None:
    expected = [16, 64, 256, 1024, 4096, 16384, 65536, 262144]
    assert list(ISO_CLASSES) == [f"iso-{c}" for c in "abcdefgh"]
    np.testing.assert_allclose(list(ISO_CLASSES.values()), np.array(expected) * 1e-6)


def test_unknown_road_is_one_line_input_error() -> None:
    with pytest.raises(InputError, match="unknown road 'iso-z'") as err:
        roughness_class("iso-z")
    assert "\n" not in str(err.value)


def test_noise_is_seeded_with_intensity_one_half() -> None:
    dt = 1e-3
    w = R.white_noise(7, 400_000, dt)
    np.testing.assert_array_equal(w, R.white_noise(7, 400_000, dt))
    assert not np.array_equal(w, R.white_noise(8, 400_000, dt))
    # discrete w_k ~ N(0, W/dt) with W = 1/2
    assert np.var(w) * dt == pytest.approx(0.5, rel=0.01)


def test_gain_of_the_road_filter() -> None:
    road = R.RoadParams(gq_m3=64e-6, speed_m_s=20.0)
    assert road.gain == pytest.approx(2 * np.pi * 0.1 * np.sqrt(64e-6 * 20.0))
    # stationary variance of eq. (2) with W = 1/2 equals the integral of the filter PSD
    var_exact = R.NOISE_INTENSITY * road.gain**2 / (2 * road.pole_rad_s)
    n = np.geomspace(1e-7, 1e4, 400_001)
    var_psd = np.trapezoid(R.filter_psd(n, road) * n, np.log(n))
    assert var_psd == pytest.approx(var_exact, rel=1e-4)


@pytest.mark.parametrize("road_name", ["iso-b", "iso-e"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_generated_psd_matches_iso_8608(road_name: str, seed: int) -> None:
    """Welch over 4000 s, 100 s segments, averaged over 7 log bands, 0.02-2.8 cycles/m, 20 m/s."""
    road = R.RoadParams(gq_m3=ISO_CLASSES[road_name], speed_m_s=20.0)
    dt = 1e-3
    z = R.road_profile(road, R.white_noise(seed, round(4000 / dt), dt), dt)
    f, g_t = welch(z, fs=1 / dt, nperseg=round(100 / dt))
    n = f / road.speed_m_s  # cycles/m
    g_n = g_t * road.speed_m_s  # one-sided spatial PSD, m^3
    edges = np.geomspace(0.02, 2.8, 8)
    for lo, hi in itertools.pairwise(edges):
        band = (n >= lo) & (n < hi)
        assert band.sum() >= 10
        iso = R.iso_psd(n[band], road.gq_m3).mean()
        own = R.filter_psd(n[band], road).mean()
        ratio = g_n[band].mean() / iso
        assert abs(ratio - 1) < 0.10, (lo, hi, ratio)
        assert abs(g_n[band].mean() / own - 1) < 0.06, (lo, hi)


def test_profile_starts_at_rest_and_has_stationary_variance() -> None:
    road = R.RoadParams(gq_m3=256e-6)
    dt = 2e-3
    z = R.road_profile(road, R.white_noise(3, round(3000 / dt), dt), dt)
    assert z[0] == 0.0
    var_exact = R.NOISE_INTENSITY * road.gain**2 / (2 * road.pole_rad_s)
    assert np.var(z[round(20 / dt) :]) == pytest.approx(var_exact, rel=0.1)
