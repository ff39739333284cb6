"""The combined-slip tire and the vehicle ABS load/force loop (design.md 3.3) as properties."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from chassistune.plants.abs_vehicle import (
    N_WORK,
    SF_MU_PEAK,
    WK_CS,
    WK_FXB,
    WK_FYB,
    WK_FZ,
    WK_SN,
    WK_SX,
    WK_VR,
    bilinear_mu,
    geometry,
    load_coefficients,
    solve_loads,
    straight_force_per_load,
    surface_row,
    tire_force,
)
from chassistune.plants.abs_vehicle_params import VehicleParams
from chassistune.plants.roads import BILINEAR_ROADS
from chassistune.plants.tires import BilinearTire
from tire_oracle import tire_mu

SURFACES = {
    name: surface_row(s, h, g, 60_000.0)[None, :] for name, (s, h, g, _) in BILINEAR_ROADS.items()
}
"""One-row surface tables by name (the tire reads row 0)."""
surface_names = st.sampled_from(sorted(SURFACES))
speeds = st.floats(-40.0, 40.0, allow_nan=False)
wheel_speeds = st.floats(0.0, 40.0, allow_nan=False)
loads = st.floats(1.0, 8000.0, allow_nan=False)
MIN_SPEED = 0.1


def force(
    u: float, v: float, wr: float, fz: float, surf: np.ndarray
) -> tuple[float, float, float, float]:
    """The tire force for contact-centre velocity (u, v) and wheel circumferential speed wr."""
    vabs = max(math.hypot(u, v), MIN_SPEED)
    return tire_force((u - wr) / vabs, v / vabs, fz, surf, 0)


@settings(max_examples=400, deadline=None)
@given(u=speeds, v=speeds, wr=wheel_speeds, fz=loads, name=surface_names)
def test_force_within_peak_friction_and_never_does_positive_work(u, v, wr, fz, name):
    surf = SURFACES[name]
    fx, fy, _, _ = force(u, v, wr, fz, surf)
    assert math.hypot(fx, fy) <= surf[0, SF_MU_PEAK] * fz * (1 + 1e-12)
    # power of the tire force on the slip velocity (u - w R, v): never positive
    assert fx * (u - wr) + fy * v <= 1e-9 * fz


@settings(max_examples=400, deadline=None)
@given(u=st.floats(0.2, 40.0), slip=st.floats(0.0, 1.0), fz=loads, name=surface_names)
def test_without_lateral_velocity_the_force_is_the_bilinear_curve_exactly(u, slip, fz, name):
    surf = SURFACES[name]
    wr = u * (1.0 - slip)
    sx = (u - wr) / u
    fx, fy, _, _ = tire_force(sx, 0.0, fz, surf, 0)
    s, h, g, _ = BILINEAR_ROADS[name]
    _, coef, xs, ys = BilinearTire(s, h, g).kernel_data()
    assert fy == 0.0
    assert fx == -(fz * tire_mu(2, coef, xs, ys, sx))  # bit for bit, the single wheel's curve
    assert bilinear_mu(sx, surf, 0) == tire_mu(2, coef, xs, ys, sx)
    assert straight_force_per_load(sx, surf, 0) * fz == fx


@settings(max_examples=400, deadline=None)
@given(u=speeds, v=speeds, fz=loads, name=surface_names)
@example(u=-5e-324, v=1.0, fz=1000.0, name="dry-concrete")  # found by hypothesis: fx underflows
def test_a_locked_wheel_slides_against_its_contact_velocity_in_every_direction(u, v, fz, name):
    fx, fy, _, _ = force(u, v, 0.0, fz, SURFACES[name])
    assert fx * u <= 0.0 and fy * v <= 0.0
    if math.hypot(u, v) > 1e-6:
        assert fx * u + fy * v < 0.0
        if u < -1e-9:  # sliding backwards: the force points forwards (at |u| ~ 1e-324 its
            assert fx > 0.0  # component fz mu u/|V| underflows to 0, which the line above allows)


@settings(max_examples=200, deadline=None)
@given(
    u=st.floats(1.0, 40.0),
    v=st.floats(-5.0, 5.0),
    wr=wheel_speeds,
    fz=st.floats(100.0, 8000.0),
    name=surface_names,
)
def test_load_derivative_matches_finite_differences(u, v, wr, fz, name):
    surf = SURFACES[name]
    _, _, dfx, dfy = force(u, v, wr, fz, surf)
    h = 1e-4 * fz
    fxp, fyp, _, _ = force(u, v, wr, fz + h, surf)
    fxm, fym, _, _ = force(u, v, wr, fz - h, surf)
    # away from the curve's kink the central difference is second-order accurate
    if abs(fxp - 2 * force(u, v, wr, fz, surf)[0] + fxm) < 1e-6 * fz:
        assert dfx == pytest.approx((fxp - fxm) / (2 * h), rel=1e-4, abs=1e-6)
        assert dfy == pytest.approx((fyp - fym) / (2 * h), rel=1e-4, abs=1e-6)


def test_pure_cornering_gives_the_cornering_stiffness_up_to_the_peak():
    surf = SURFACES["dry-concrete"]
    alpha = 0.01  # rad
    u, v = 30.0, -30.0 * math.tan(alpha)
    _, fy, _, _ = force(u, v, u, 4000.0, surf)
    assert fy == pytest.approx(60_000.0 * math.sin(alpha), rel=1e-12)
    _, fy_big, _, _ = force(u, -30.0, u, 4000.0, surf)
    assert abs(fy_big) <= 0.9 * 4000.0


def solve(
    sx, vr, delta: float, h: float, sidx, surfs
) -> tuple[float, float, int, np.ndarray, VehicleParams]:
    pp = VehicleParams(cg_height_m=h)
    wk = np.zeros((N_WORK, 4))
    wk[WK_SX], wk[WK_VR] = sx, vr
    wk[WK_CS] = [math.cos(delta)] * 2 + [1.0] * 2
    wk[WK_SN] = [math.sin(delta)] * 2 + [0.0] * 2
    ax, ay, it = solve_loads(
        wk, surfs, np.asarray(sidx).reshape(4, 1), 0, geometry(pp), pp.mass_kg, 0.0, 0.0
    )
    return ax, ay, it, wk, pp


@settings(max_examples=100, deadline=None)
@given(
    sx=st.lists(st.floats(-0.5, 1.0), min_size=4, max_size=4),
    vr=st.lists(st.floats(-0.3, 0.3), min_size=4, max_size=4),
    delta=st.floats(-0.1, 0.1),
    h=st.floats(0.0, 0.8),
)
def test_load_force_loop_is_solved_exactly(sx, vr, delta, h):
    surfs = np.concatenate([SURFACES["dry-concrete"], SURFACES["ice"]])
    ax, ay, it, wk, pp = solve(sx, vr, delta, h, [0, 1, 0, 1], surfs)
    assert it < 20
    # the loads are those of the accelerations the forces produce, and they sum to m g
    fz0, a, b = load_coefficients(pp)
    expected = np.maximum(fz0 + a * ax + b * ay, 0.0)
    np.testing.assert_allclose(wk[WK_FZ], expected, rtol=0, atol=1e-7)
    assert ax == pytest.approx(wk[WK_FXB].sum() / pp.mass_kg, abs=1e-12)
    assert ay == pytest.approx(wk[WK_FYB].sum() / pp.mass_kg, abs=1e-12)
    if np.all(wk[WK_FZ] > 0):
        assert wk[WK_FZ].sum() == pytest.approx(pp.mass_kg * pp.g_m_s2, rel=1e-12)


def test_straight_line_loop_has_the_closed_form():
    surf = SURFACES["dry-concrete"]
    # every wheel at the peak: ax = -0.9 g
    ax, ay, it, wk, pp = solve(
        np.full(4, 0.2), np.zeros(4), 0.0, 0.5, [0, 0, 0, 0], np.concatenate([surf, surf])
    )
    assert it == 0 and ay == 0.0
    assert ax == pytest.approx(-0.9 * pp.g_m_s2, rel=1e-14)
    assert wk[WK_FZ, 0] == pytest.approx(4204.8, abs=0.05)
    assert wk[WK_FZ, 2] == pytest.approx(1234.2, abs=0.05)
