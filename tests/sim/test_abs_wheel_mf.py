"""The Magic Formula tire as a tire law of the ideal single-wheel kernel: its mu(S) against the
scalar force functions, the closed loop against scipy's solve_ivp, the adhesion bound, and a
batch row against its single run."""

from __future__ import annotations

import dataclasses
import re
import warnings
from importlib.resources import files
from pathlib import Path

import numba
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_abs_wheel_kernel import _has_avx

from chassistune._branchfree import stack_copy
from chassistune.controllers.laws.held_pid import HELD_PID
from chassistune.errors import InputError
from chassistune.perf.abs import pid_closed_loop
from chassistune.plants.magic_formula import longitudinal_force_pure_n, longitudinal_shape
from chassistune.plants.mf_curve import (
    POLY_SIZE,
    TIRE_SURFACE,
    MagicFormulaCurve,
    fit_gap,
    polynomial_mu,
)
from chassistune.plants.mf_peak import braking_friction_peak, scaled_to_road
from chassistune.plants.tir import TirWarning, read_tir
from chassistune.plants.tires import KIND_MAGIC_FORMULA
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario
from chassistune.sim import abs_wheel_kernel as K
from chassistune.sim.abs_wheel_tires import magic_formula_mu, table_tuples

TIRES = files("chassistune") / "data" / "tires"
CHRONO = str(TIRES / "chrono_185_80R14_pac2002.tir")
COMMONROAD = str(TIRES / "commonroad_pac2002.tir")
MF61 = str(Path(__file__).parents[1] / "plants" / "data" / "MagicFormula61_Parameters.tir")


def _tire(path: str):  # type: ignore[no-untyped-def]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TirWarning)
        return read_tir(path)


def _scenario(controller: str, road: str = TIRE_SURFACE, path: str = CHRONO) -> AbsWheelScenario:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TirWarning)
        sc = PLANT.scenario("paper-derlsp-ao", road, controller, {"tire": path})
    assert isinstance(sc, AbsWheelScenario) and isinstance(sc.tire, MagicFormulaCurve)
    return sc


@numba.njit
def _tire_law_many(s, c4, poly):  # type: ignore[no-untyped-def]
    out = np.empty(s.size)
    for i in range(s.size):
        out[i] = magic_formula_mu(s[i], c4[0], c4[1], c4[2], c4[3], poly)
    return out


@pytest.mark.parametrize("path", [CHRONO, COMMONROAD, MF61])
@pytest.mark.parametrize("fz_n", [900.0, 3000.0, 7500.0])
@pytest.mark.parametrize("road_mu", [None, 0.05])
def test_the_kernel_law_is_the_scalar_force_within_1e_5(
    path: str, fz_n: float, road_mu: float | None
) -> None:
    """The kernel's piecewise cubic against mu(S) = -F_x0(-S) / F_z of
    `magic_formula.longitudinal_force_pure_n` over a slip grid through the knot at S_Hx
    (measured: at most 9.4e-6, MF61 at 7500 N on a road of peak 0.05); within 1e-15 of
    `mf_curve.polynomial_mu` (numpy, without the kernel's fused multiply-adds)."""
    tire = _tire(path) if road_mu is None else scaled_to_road(_tire(path), road_mu, fz_n)
    curve = MagicFormulaCurve(tire, fz_n)
    kind, coef, poly, _ = curve.kernel_data()
    assert kind == KIND_MAGIC_FORMULA and poly.shape == (POLY_SIZE,)
    shx = longitudinal_shape(tire.kernel_array(), 0.0, fz_n)[4]
    s = np.concatenate([np.linspace(0.0, 1.0, 20_001), [shx, np.nextafter(shx, 1.0)]])
    s = s[(s >= 0.0) & (s <= 1.0)]
    ours = _tire_law_many(s, coef, poly)
    c = tire.kernel_array()
    ref = np.array([-longitudinal_force_pure_n(c, -x, fz_n) / fz_n for x in s])
    assert np.max(np.abs(ours - ref)) <= 1e-5
    assert np.max(np.abs(ours - polynomial_mu(coef, poly, s))) <= 1e-15
    assert np.array_equal(curve.mu(s), ref)
    assert fit_gap(curve) <= 1e-5


def test_a_nan_slip_gives_nan_and_reads_inside_the_table() -> None:
    curve = MagicFormulaCurve(_tire(CHRONO), 3000.0)
    _, coef, poly, _ = curve.kernel_data()
    assert np.isnan(_tire_law_many(np.array([np.nan]), coef, poly)[0])


def test_a_curve_the_polynomial_cannot_follow_is_refused() -> None:
    """A tire a thousand times as stiff (PKX1 x 1000: its peak at S = 1e-4, below the fine
    zone's smallest width) is refused in one line."""
    tire = dataclasses.replace(_tire(CHRONO), pkx1=1000.0 * _tire(CHRONO).pkx1)
    with pytest.raises(InputError, match="too steep for the kernels' piecewise polynomial"):
        MagicFormulaCurve(tire, 3000.0, "stiff.tir")


def test_the_curve_peak_is_the_closed_form_braking_peak() -> None:
    tire = _tire(MF61)
    curve = MagicFormulaCurve(tire, 2500.0)
    mu_peak, s_peak, target = curve.peak()
    assert mu_peak == braking_friction_peak(tire, 2500.0)
    assert target == s_peak and 0.05 < s_peak < 0.3
    grid = np.linspace(0.0, 1.0, 100_001)
    assert np.max(curve.mu(grid)) <= mu_peak * (1.0 + 1e-12)


def test_a_road_scales_the_tire_to_its_peak() -> None:
    own = _scenario("pid")
    wet = _scenario("pid", "wet-asphalt")
    pp = own.plant_params
    fz_n = pp.load_fraction * pp.mass_kg * pp.g_m_s2
    assert own.mu_peak == braking_friction_peak(_tire(CHRONO), fz_n)
    assert wet.mu_peak == pytest.approx(0.78, rel=1e-4)  # S_Vx is scaled by lambda'_mu (4.E8)
    assert wet.bound_distance_m > own.bound_distance_m
    assert wet.params()["tire"] == CHRONO


def _reference(sc: AbsWheelScenario, kp: float, ki: float, kd: float) -> tuple[float, float]:
    """(stop time, stop distance) of the PID closed loop (`perf.abs.pid_closed_loop`) with the
    MF tire's scalar force, by scipy's RK45 at tight tolerances."""
    pp = sc.plant_params
    c = sc.tire.tire.kernel_array()
    fz = pp.load_fraction * pp.mass_kg * pp.g_m_s2
    rhs, y0, stopped = pid_closed_loop(
        sc, np.array([kp, ki, kd]), lambda s: -longitudinal_force_pure_n(c, -s, fz) / fz
    )
    sol = solve_ivp(
        rhs, (0.0, pp.t_max_s), y0, rtol=1e-10, atol=1e-10, max_step=1e-3, events=stopped
    )
    return float(sol.t_events[0][0]), float(sol.y_events[0][0][6])


GAINS = [(5000.0, 0.0, 230.0), (2000.0, 500.0, 50.0), (800.0, 0.0, 0.0)]


@pytest.mark.slow
@pytest.mark.parametrize("gains", GAINS)
def test_the_kernel_agrees_with_solve_ivp(gains: tuple[float, float, float]) -> None:
    sc = _scenario("pid")
    m = sc.metrics(np.array([gains]))
    assert m["status"][0] == "stopped"
    t_ref, x_ref = _reference(sc, *gains)
    assert abs(float(m["stop_time_s"][0]) - t_ref) <= 1e-5 * t_ref  # measured: 7.1e-7
    assert abs(float(m["stop_distance_m"][0]) - x_ref) <= 1e-5 * x_ref  # measured: 1.3e-6


@pytest.mark.parametrize("road", [TIRE_SURFACE, "ice", "burckhardt-snow"])
@pytest.mark.parametrize("controller", ["pid", "bang-bang", "none"])
def test_no_stop_beats_the_adhesion_bound(road: str, controller: str) -> None:
    sc = _scenario(controller, road, MF61)
    box = np.array(sc.controller.bounds(), dtype=float).reshape(-1, 2)
    rng = np.random.default_rng(5)
    g = box[:, 0] + rng.random((60, box.shape[0])) * (box[:, 1] - box[:, 0])
    m = sc.metrics(g)
    stopped = m["status"] == "stopped"
    assert np.all(m["stop_distance_m"][stopped] >= sc.bound_distance_m)


@pytest.mark.parametrize("controller", ["pid", "bang-bang"])
def test_batch_rows_equal_single_runs(controller: str) -> None:
    sc = _scenario(controller)
    box = np.array(sc.controller.bounds(), dtype=float).reshape(-1, 2)
    rng = np.random.default_rng(11)
    g = box[:, 0] + rng.random((K.LANES + 9, box.shape[0])) * (box[:, 1] - box[:, 0])
    batch = sc.raw(g, workers=1)
    for i in range(0, len(g), 5):
        assert sc.raw(g[i : i + 1], workers=1).tobytes() == batch[i : i + 1].tobytes()
    assert sc.raw(g, workers=2).tobytes() == batch.tobytes()


@pytest.mark.slow
@pytest.mark.skipif(not _has_avx(), reason="needs an x86 CPU with AVX2")
def test_the_magic_formula_loop_vectorizes() -> None:
    """Packed double arithmetic and gathers in the Magic Formula's vector loop."""
    steps = K._lane_steps_of(KIND_MAGIC_FORMULA, K.RK3, HELD_PID)

    @numba.njit(_nrt=False)  # type: ignore[misc]
    def run(st, c4, xc_tuple, xs_tuple, ys_tuple, poly, c):  # type: ignore[no-untyped-def]
        xc, xs, ys = stack_copy(xc_tuple), stack_copy(xs_tuple), stack_copy(ys_tuple)
        tire = (c4[0], c4[1], c4[2], c4[3], xc, xs, ys, poly)
        return steps(st, K.LANES, 1e-3, 5e-4, 1e-3 / 6.0, 100.0, 0.1, 0, tire, c)

    _p, _kind, coef, poly, _ys, _ck, c, _table = _scenario("pid")._kernel_args
    no_table = table_tuples(np.array([0.0, 1.0]), np.array([0.0, 0.0]))
    run(np.zeros(K.N_ROWS * K.LANES), coef, *no_table, poly, c)
    asm = steps.inspect_asm(steps.signatures[0])
    packed = re.findall(r"\bv(?:mul|add|sub|div|fmadd\w*)pd\s[^\n]*%[yz]mm", asm)
    assert len(packed) >= 150, "the Magic Formula's lane step no longer vectorizes"
    assert re.search(r"vgather\w*pd", asm), "the segments' coefficients are not gathered"
