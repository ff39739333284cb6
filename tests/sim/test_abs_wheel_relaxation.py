"""The tire's lagged slip on the ideal single wheel (relaxation length sigma, docs/tires.md):
zero is today's kernel bit for bit, the lag relaxes with the time constant sigma / v, the closed
loop agrees with scipy's solve_ivp and converges as dt halves, a batch row is its single run."""

from __future__ import annotations

import math
import sys
import warnings
from importlib.resources import files
from pathlib import Path
from typing import Any

import numba
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from chassistune._branchfree import stack_copy
from chassistune.controllers.laws.held_pid import HELD_PID
from chassistune.errors import InputError
from chassistune.perf.abs import pid_closed_loop
from chassistune.plants.mf_curve import TIRE_SURFACE, MagicFormulaCurve
from chassistune.plants.mf_relaxation import longitudinal_relaxation_length_m
from chassistune.plants.tir import TirWarning
from chassistune.plants.tires import KIND_BILINEAR
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario
from chassistune.sim import abs_wheel_kernel as K
from chassistune.sim import abs_wheel_layout as KL
from chassistune.sim.abs_wheel_tires import table_tuples

sys.path.insert(0, str(Path(__file__).parents[1] / "golden"))

import golden_cases
from golden_cases import PINNED

GOLDEN = __import__("json").loads(PINNED.read_text())
SIGMA_M = 0.3
CHRONO = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")
COMMONROAD = str(files("chassistune") / "data" / "tires" / "commonroad_pac2002.tir")


def _scenario(
    preset: str, road: str, controller: str, params: dict[str, Any] | None = None
) -> AbsWheelScenario:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TirWarning)
        sc = PLANT.scenario(preset, road, controller, params or {})
    assert isinstance(sc, AbsWheelScenario)
    return sc


def _population(sc: AbsWheelScenario, n: int, seed: int) -> np.ndarray:
    box = np.array(sc.controller.bounds(), dtype=float).reshape(-1, 2)
    rng = np.random.default_rng(seed)
    return box[:, 0] + rng.random((n, box.shape[0])) * (box[:, 1] - box[:, 0])


# (a) a zero length is today's kernel: the golden pins, with the length given explicitly

ZERO_CASES = [
    ("paper-derlsp-ao", "dry-concrete", "pid"),  # bilinear, RK3
    ("paper-derlsp-ao", "ice", "threshold"),  # bilinear, RK4 (a sampled law)
    ("paper-derlsp-ao", "burckhardt-wet-asphalt", "pid"),  # Burckhardt
    ("sldemo", "sldemo-table", "bang-bang"),  # table
    ("paper-fuzzy-immune", "asphalt-0.8", "fuzzy-immune-pid"),
]


@pytest.mark.parametrize("case", ZERO_CASES, ids=lambda c: "/".join(c))
def test_zero_length_reproduces_the_pinned_runs_bit_for_bit(case: tuple[str, str, str]) -> None:
    got = golden_cases.abs_case(*case, {"relaxation_length_m": 0.0})
    assert got == GOLDEN["abs"]["/".join(case)]


@pytest.mark.parametrize("controller", ["pid", "fuzzy-pid"])
def test_zero_length_reproduces_the_pinned_batch_costs(controller: str) -> None:
    sc = _scenario("paper-derlsp-ao", "dry-concrete", controller, {"relaxation_length_m": 0})
    pop = golden_cases._population([(g.lo, g.hi) for g in sc.controller.gains], 12, 7)
    got = {obj: golden_cases._digest(sc.cost(pop, obj)) for obj in ("itae", "distance", "time")}
    assert got == GOLDEN["abs_population"][controller]


def test_a_zero_length_on_the_magic_formula_tire_is_the_static_run() -> None:
    static = _scenario("paper-derlsp-ao", TIRE_SURFACE, "pid", {"tire": CHRONO})
    zero = _scenario(
        "paper-derlsp-ao", TIRE_SURFACE, "pid", {"tire": CHRONO, "relaxation_length_m": 0.0}
    )
    g = _population(static, K.LANES + 3, 2)
    assert zero.raw(g, workers=1).tobytes() == static.raw(g, workers=1).tobytes()


# (b) the wheel held at constant speeds: S' relaxes to S with the time constant sigma / v

SPEEDS_M_S = np.array([1.0, 3.0, 7.5, 15.0, 30.0, 45.0, 60.0, 70.0])
HELD_SLIP = 0.2
DT_S = 1e-3


@numba.njit(_nrt=False)
def _run_held(steps, st, n, c4, xc_tuple, xs_tuple, ys_tuple, c, lags):  # type: ignore[no-untyped-def]
    xc, xs, ys = stack_copy(xc_tuple), stack_copy(xs_tuple), stack_copy(ys_tuple)
    tire = (c4[0], c4[1], c4[2], c4[3], xc, xs, ys, K._NO_POLY, KIND_BILINEAR)
    for k in range(n):
        steps(st, K.LANES, DT_S, 0.5 * DT_S, DT_S / 6.0, 1e9, 1e6, K.LANES, tire, c)
        for j in range(SPEEDS_M_S.size):
            lags[k, j] = st[K.R_LAG * K.LANES + j]


def _held_lanes(sigma_m: float, n: int) -> np.ndarray:
    """S'(t_k) in lanes of speeds SPEEDS_M_S, wheel speed (1 - HELD_SLIP) v / R, S'(0) = 0: the
    relaxed vector loop itself, with 1/M = 1/I = 0 (v, w held) and no brake torque."""
    sc = _scenario("paper-derlsp-ao", "dry-concrete", "pid")
    _p, _kind, coef, xs, ys, _ck, c, _table = sc._kernel_args
    c4 = np.zeros(4)
    c4[: len(coef)] = coef
    r_w = 0.5
    st = np.zeros(K.N_ROWS * K.LANES)
    rows = {
        K.R_V: SPEEDS_M_S,
        K.R_W: (1.0 - HELD_SLIP) * SPEEDS_M_S / r_w,
        K.R_RW: r_w,
        K.R_FZ: 981.0,
        K.R_INV_TAU: 100.0,
        K.R_QMAX: 1500.0,
        K.R_NF: 100.0,
        K.R_HOPELESS: math.inf,
        K.R_S1: HELD_SLIP,
        K.R_SIGMA: sigma_m,
        K.R_TARGET: 0.1,
    }
    for row, value in rows.items():  # every lane (the speeds repeated)
        st[row * K.LANES : (row + 1) * K.LANES] = np.resize(value, K.LANES)
    lags = np.zeros((n, SPEEDS_M_S.size))
    steps = K._relaxed_lane_steps_of(HELD_PID)
    _run_held(steps, st, n, c4, *table_tuples(xs, ys), c, lags)
    assert np.all(st[K.R_V * K.LANES : K.R_V * K.LANES + SPEEDS_M_S.size] == SPEEDS_M_S)
    return lags


def test_the_lagged_slip_relaxes_with_time_constant_sigma_over_speed() -> None:
    n = 3000
    lags = _held_lanes(SIGMA_M, n)
    t = DT_S * np.arange(1, n + 1)[:, None]
    tau = SIGMA_M / SPEEDS_M_S
    exact = HELD_SLIP * (1.0 - np.exp(-t / tau))
    # Kutta's RK3 on the linear lag: S' = S (1 - R(z)^k), R(z) = 1 + z + z^2/2 + z^3/6
    z = -DT_S / tau
    rk3 = HELD_SLIP * (1.0 - (1.0 + z + z * z / 2 + z**3 / 6) ** np.arange(1, n + 1)[:, None])
    np.testing.assert_allclose(lags, rk3, rtol=0, atol=1e-13)
    np.testing.assert_allclose(lags, exact, rtol=0, atol=5e-4 * HELD_SLIP)  # measured: 2.3e-4
    fast = tau < 0.1  # 30 time constants and more: there
    assert np.all(np.abs(lags[-1, fast] - HELD_SLIP) < 1e-12)  # tends to the kinematic slip
    # the time constant fitted from the decay of S - S' over the first two of them
    for j, tau_j in enumerate(tau):
        k = np.arange(n)[t[:, 0] <= 2 * tau_j]
        slope = np.polyfit(t[k, 0], np.log(HELD_SLIP - lags[k, j]), 1)[0]
        assert -1.0 / slope == pytest.approx(tau_j, rel=1e-3)


def test_a_shorter_relaxation_length_relaxes_faster() -> None:
    short, long_ = _held_lanes(0.1, 50), _held_lanes(0.6, 50)
    assert np.all(short[1:] > long_[1:])


# (c) the closed loop against scipy's solve_ivp of the same equations


def _reference(sc: AbsWheelScenario, gains: tuple[float, float, float]) -> tuple[float, float]:
    """(stop time, stop distance) of the PID closed loop (`perf.abs.pid_closed_loop`) with the
    tire read at the lagged slip, sigma dS'/dt = (v - w R) - v S', by solve_ivp (RK45, tight)."""
    pp = sc.plant_params
    lag_now = [0.0]

    def odd_mu(_s: float) -> float:  # the tire at the lagged slip, odd, capped at 1
        return math.copysign(float(sc.tire.mu(min(abs(lag_now[0]), 1.0))), lag_now[0])

    rhs, y0, stopped = pid_closed_loop(sc, np.array(gains), odd_mu)

    def relaxed(t: float, y: np.ndarray) -> list[float]:
        v, w, lag = y[0], y[1], y[8]
        lag_now[0] = lag
        slip_speed = v - w * pp.wheel_radius_m
        return [*rhs(t, y[:8]), (slip_speed - v * lag) / pp.relaxation_length_m]

    sol = solve_ivp(
        relaxed,
        (0.0, pp.t_max_s),
        [*y0, 0.0],
        rtol=1e-10,
        atol=1e-10,
        max_step=1e-3,
        events=stopped,
    )
    return float(sol.t_events[0][0]), float(sol.y_events[0][0][6])


@pytest.mark.slow
@pytest.mark.parametrize("gains", [(5000.0, 0.0, 230.0), (2000.0, 500.0, 50.0)])
def test_the_relaxed_closed_loop_agrees_with_solve_ivp(gains: tuple[float, float, float]) -> None:
    sc = _scenario("paper-derlsp-ao", "dry-concrete", "pid", {"relaxation_length_m": SIGMA_M})
    m = sc.metrics(np.array([gains]))
    assert m["status"][0] == "stopped"
    t_ref, x_ref = _reference(sc, gains)
    assert abs(float(m["stop_time_s"][0]) - t_ref) <= 1e-5 * t_ref  # measured: 1.4e-6
    assert abs(float(m["stop_distance_m"][0]) - x_ref) <= 1e-5 * x_ref  # measured: 2.5e-6


# (d) convergence as dt halves


@pytest.mark.parametrize("controller", ["pid", "threshold"])
def test_the_relaxed_run_converges_as_dt_halves(controller: str) -> None:
    """The sampled law's period held at 1 ms (ts_s), so that only the step changes."""
    steps = (1e-3, 5e-4, 2.5e-4, 1.25e-4)
    runs = []
    for dt in steps:
        params = {"relaxation_length_m": SIGMA_M, "dt_s": dt}
        if controller != "pid":
            params["ts_s"] = 1e-3
        sc = _scenario("paper-derlsp-ao", "wet-asphalt", controller, params)
        m = sc.metrics(np.array([list(sc.controller.default_gains().values())]))
        assert m["status"][0] == "stopped"
        runs.append(float(m["stop_distance_m"][0]))
    errors = np.abs(np.array(runs[:-1]) - runs[-1])
    print(controller, runs, errors)
    assert np.all(np.diff(errors) < 0)  # each halving closer to the finest step
    assert errors[-1] <= 1e-3 * runs[-1]


# (e) a batch row is its single run; every lane of a run takes the same branch


@pytest.mark.parametrize(
    "case",
    [
        ("paper-derlsp-ao", "dry-concrete", "pid", {}),
        ("paper-derlsp-ao", "burckhardt-snow", "fuzzy-immune-pid", {}),
        ("sldemo", "sldemo-table", "bang-bang", {}),
        ("paper-derlsp-ao", TIRE_SURFACE, "threshold", {"tire": CHRONO}),
    ],
    ids=lambda c: "/".join(c[:3]),
)
def test_relaxed_batch_rows_equal_single_runs(case: tuple[str, str, str, dict[str, str]]) -> None:
    preset, road, controller, params = case
    sc = _scenario(preset, road, controller, {**params, "relaxation_length_m": SIGMA_M})
    static = _scenario(preset, road, controller, params)
    g = _population(sc, K.LANES + 9, 8)
    batch = sc.raw(g, workers=1)
    for i in range(0, len(g), 5):
        assert sc.raw(g[i : i + 1], workers=1).tobytes() == batch[i : i + 1].tobytes()
    assert sc.raw(g, workers=2).tobytes() == batch.tobytes()
    assert not np.array_equal(batch, static.raw(g, workers=1))  # the lag changes the runs


def test_no_relaxed_stop_beats_the_adhesion_bound() -> None:
    for road in ("dry-concrete", "ice"):
        sc = _scenario("paper-derlsp-ao", road, "pid", {"relaxation_length_m": 0.5})
        m = sc.metrics(_population(sc, 60, 5))
        stopped = m["status"] == "stopped"
        assert stopped.any()
        assert np.all(m["stop_distance_m"][stopped] >= sc.bound_distance_m)


def test_the_lag_vanishes_as_the_length_shrinks() -> None:
    """sigma -> 0 tends to the static tire: the stop distance's departure shrinks with sigma."""
    g = np.array([[5000.0, 0.0, 230.0]])
    base = float(
        _scenario("paper-derlsp-ao", "wet-asphalt", "pid").metrics(g)["stop_distance_m"][0]
    )
    gaps = [
        abs(
            float(
                _scenario(
                    "paper-derlsp-ao", "wet-asphalt", "pid", {"relaxation_length_m": sigma}
                ).metrics(g)["stop_distance_m"][0]
            )
            - base
        )
        for sigma in (0.4, 0.2, 0.1, 0.05)
    ]
    print(gaps)
    assert np.all(np.diff(gaps) < 0) and gaps[-1] > 0.0


# bad input


def test_a_length_the_step_cannot_resolve_is_refused() -> None:
    with pytest.raises(InputError, match=r"relaxation_length_m.*v0_m_s dt_s = 0\.03 m"):
        _scenario("paper-derlsp-ao", "dry-concrete", "pid", {"relaxation_length_m": 0.01})
    with pytest.raises(InputError, match="relaxation_length_m"):
        _scenario("paper-derlsp-ao", "dry-concrete", "pid", {"relaxation_length_m": -0.3})


def test_plant_rows_mixing_zero_and_positive_lengths_are_refused() -> None:
    sc = _scenario("paper-derlsp-ao", "dry-concrete", "pid")
    p, kind, coef, xs, ys, ckind, c, table = sc._kernel_args
    rows = np.repeat(p[None, :], 2, axis=0)
    rows[1, KL.PLANT["relaxation_length_m"]] = SIGMA_M
    out = np.zeros((2, len(KL.METRICS)))
    with pytest.raises(ValueError, match="relaxation_length_m"):
        K.simulate_abs_wheel(
            np.zeros((2, 3)), rows, kind, coef, xs, ys, ckind, c, table, np.zeros((0, 10)), out
        )


# the length from a TIR file

MF61 = str(Path(__file__).parents[1] / "plants" / "data" / "MagicFormula61_Parameters.tir")


@pytest.mark.parametrize("path", [MF61, CHRONO], ids=["mf61-carcass-stiffness", "mf52-ptx"])
def test_the_tir_files_length_at_the_wheels_load(path: str) -> None:
    """`relaxation_length_m=tire` takes the file's length at the wheel's load: MF 6.1's from its
    carcass stiffness (MFeval's sample), MF 5.2's from PTX1-3 (Chrono's PAC2002 file, which has
    no LONGITUDINAL_STIFFNESS); echoed as a number, which replays the run bit for bit."""
    sc = _scenario(
        "paper-derlsp-ao", TIRE_SURFACE, "pid", {"tire": path, "relaxation_length_m": "tire"}
    )
    assert isinstance(sc.tire, MagicFormulaCurve)
    sigma = longitudinal_relaxation_length_m(sc.tire.tire.kernel_array(), sc.tire.fz_n)
    assert sc.plant_params.relaxation_length_m == sigma > 0.0
    assert sc.params()["relaxation_length_m"] == sigma  # echoed as a number: replayable
    given = _scenario(
        "paper-derlsp-ao", TIRE_SURFACE, "pid", {"tire": path, "relaxation_length_m": sigma}
    )
    g = _population(sc, 3, 1)
    assert sc.raw(g, workers=1).tobytes() == given.raw(g, workers=1).tobytes()


def test_a_tir_file_without_the_length_or_no_tir_file_is_refused() -> None:
    with pytest.raises(InputError, match=r"neither LONGITUDINAL_STIFFNESS .* nor a positive PTX1"):
        _scenario(
            "paper-derlsp-ao",
            TIRE_SURFACE,
            "pid",
            {"tire": COMMONROAD, "relaxation_length_m": "tire"},
        )
    with pytest.raises(InputError, match="needs --tire"):
        _scenario("paper-derlsp-ao", "dry-concrete", "pid", {"relaxation_length_m": "tire"})
