"""A continuous control law added in this one file, no other file edited: a saturated
proportional-integral slip law with its own integrator state z,

    v = kp e + ki z,   u = clip(v, -amplitude, amplitude),   dz/dt = e while |v| < amplitude
    (0 while the command saturates: conditional integration),   e = S_target - S,

integrated with the plant by the ideal lane kernels of the single wheel and of the vehicle (one
law per wheel) through its continuous form (`ContinuousForm`, state ("z",)). Registered for this
module's tests and removed after them, on each plant it passes the conformance check, tunes, and
a batch row equals its single run bit for bit; on the single wheel it agrees with scipy's
solve_ivp on the same closed loop, on the vehicle (too heavy for solve_ivp) with the held PID
where the gains make the two laws one (ki = 0, an amplitude never reached: u = kp e)."""

from __future__ import annotations

import functools
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
from numba import njit
from scipy.integrate import solve_ivp

from chassistune._branchfree import clip, select
from chassistune.controllers import laws
from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws.dispatch import continuous_groups
from chassistune.controllers.laws.shared import AMPLITUDE, per_wheel
from chassistune.controllers.specs import ControllerSpec, GainSpec
from chassistune.scenarios import abs_vehicle
from chassistune.scenarios.abs_wheel import PLANT, AbsWheelScenario
from chassistune.scenarios.check import check_plant
from chassistune.sim import abs_vehicle_layout as VL
from chassistune.sim import abs_wheel_kernel as K
from chassistune.tuning.tune import tune

NAME = "saturated-pi"
WHEEL = ControllerSpec(
    laws.ABS_WHEEL,
    NAME,
    "continuous saturated PI on the slip error, conditional integration while saturated",
    gains=(
        GainSpec("kp", "1/(slip)", 5000.0, 0.0, 1e4, "proportional gain"),
        GainSpec("ki", "1/(slip s)", 2000.0, 0.0, 1e4, "integral gain"),
    ),
    params=(AMPLITUDE,),
)
VEHICLE = per_wheel(
    WHEEL,
    gains=(
        GainSpec("kp", "1/(slip)", 1200.0, 0.0, 5000.0, "proportional gain"),
        GainSpec("ki", "1/(slip s)", 500.0, 0.0, 5000.0, "integral gain"),
    ),
)
G_KP, G_KI = (F.gains(WHEEL)[n] for n in ("kp", "ki"))


@functools.cache
def kernel_forms() -> tuple[Any, Any]:
    """(start, tick): the gains held for the run in the held values' kp and ki; no tick."""

    @njit(**F.FORM)
    def start(g, g0, c):  # type: ignore[no-untyped-def]
        return 0.0, g[g0 + G_KP], g[g0 + G_KI], 0.0

    return start, None


@functools.cache
def continuous_forms() -> tuple[Any, Any]:
    """(initial, rate) of the saturated PI (module docstring), branch-free."""

    @njit(**F.FORM)
    def initial(target):  # type: ignore[no-untyped-def]
        return (0.0,)

    @njit(**F.FORM)
    def rate(e, x, held, c, n_filter, at_max, at_min):  # type: ignore[no-untyped-def]
        (z,) = x
        amplitude = c[F.P_AMPLITUDE]
        v = held[F.H_KP] * e + held[F.H_KI] * z
        u = clip(v, -amplitude, amplitude)
        return u, (select(v != u, 0.0, e),)

    return initial, rate


LAW = laws.Law(
    NAME,
    (WHEEL, VEHICLE),
    kernel_forms,
    continuous=laws.ContinuousForm(("z",), continuous_forms),
    source="a test law: a continuous law defined in this file",
)

pytestmark = pytest.mark.slow  # the kernel compiles with the added law

ROAD = ("paper-derlsp-ao", "burckhardt-wet-asphalt")


@pytest.fixture(scope="module", autouse=True)
def registered() -> Iterator[None]:
    laws.register(LAW)
    yield
    laws.unregister(NAME)


def _scenario() -> AbsWheelScenario:
    sc = PLANT.scenario(*ROAD, NAME)
    assert isinstance(sc, AbsWheelScenario)
    return sc


def _reference(sc: AbsWheelScenario, kp: float, ki: float) -> tuple[float, float]:
    """(stop time, stop distance) of the same closed loop by scipy's RK45 at tight tolerances."""
    pp = sc.plant_params
    amplitude = sc.controller_params["amplitude"]
    fz = pp.load_fraction * pp.mass_kg * pp.g_m_s2

    def rhs(t: float, y: np.ndarray) -> list[float]:
        v, w, q, r, z, _x = y
        s = min(max((v - w * pp.wheel_radius_m) / v, 0.0), 1.0)
        e = sc.target_slip - s
        fx = float(sc.tire.mu(s)) * fz
        dw = (pp.wheel_radius_m * fx - pp.brake_gain * q) / pp.wheel_inertia_kg_m2
        if w <= 0.0 and dw < 0.0:
            dw = 0.0
        cmd = kp * e + ki * z
        u = min(max(cmd, -amplitude), amplitude)
        dq = 0.0 if (q >= pp.q_max and r > 0) or (q <= 0 and r < 0) else r
        dr = (pp.actuator_gain * u - r) / pp.actuator_tau_s
        return [-fx / pp.mass_kg, dw, dq, dr, e if u == cmd else 0.0, v]

    def stopped(t: float, y: np.ndarray) -> float:
        return float(y[0] - pp.v_stop_m_s)

    stopped.terminal = True  # type: ignore[attr-defined]
    y0 = [pp.v0_m_s, pp.v0_m_s / pp.wheel_radius_m, 0.0, 0.0, 0.0, 0.0]
    sol = solve_ivp(
        rhs, (0.0, pp.t_max_s), y0, rtol=1e-10, atol=1e-10, max_step=1e-3, events=stopped
    )
    return float(sol.t_events[0][0]), float(sol.y_events[0][0][5])


def test_the_added_law_is_a_continuous_controller_of_both_plants() -> None:
    assert NAME in [s.name for s in PLANT.controllers()]
    assert NAME in [s.name for s in abs_vehicle.PLANT.controllers()]
    groups = continuous_groups()
    assert (LAW.continuous, False, (laws.kind(NAME),)) in groups


@pytest.mark.parametrize(
    ("plant", "params"), [(laws.ABS_WHEEL, {"v0_m_s": 15.0}), (laws.ABS_VEHICLE, {})]
)
def test_the_added_law_passes_the_conformance_check(plant: str, params: dict[str, float]) -> None:
    check_plant(plant, params, plot=False)


@pytest.mark.parametrize(("plant", "road"), [(laws.ABS_WHEEL, None), (laws.ABS_VEHICLE, "ice")])
def test_the_added_law_tunes(plant: str, road: str | None) -> None:
    res = tune(plant, NAME, "pso", roads=road, pop_size=6, max_iter=2, seed=1)
    assert set(res.best_gains) == {"kp", "ki"} and np.isfinite(res.best_cost)
    assert np.all(np.diff(res.history) <= 0)


@pytest.mark.parametrize("gains", [(5000.0, 2000.0), (800.0, 0.0), (3000.0, 8000.0)])
def test_the_added_law_agrees_with_solve_ivp(gains: tuple[float, float]) -> None:
    sc = _scenario()
    m = sc.metrics(np.array([gains]))
    assert m["status"][0] == "stopped"
    t_ref, x_ref = _reference(sc, *gains)
    assert abs(float(m["stop_time_s"][0]) - t_ref) <= 1e-4 * t_ref
    assert abs(float(m["stop_distance_m"][0]) - x_ref) <= 1e-4 * x_ref


def test_the_added_law_integrates_its_own_state() -> None:
    """The integral gain acts (the state z is integrated), and saturation bounds the command."""
    sc = _scenario()
    g = np.array([[3000.0, 0.0], [3000.0, 8000.0]])
    d = sc.metrics(g)["stop_distance_m"]
    assert d[0] != d[1]
    trace = sc.trace(g[1])
    assert np.max(np.abs(trace.signals["command"])) <= sc.controller_params["amplitude"]


def test_batch_rows_equal_single_runs() -> None:
    sc = _scenario()
    rng = np.random.default_rng(7)
    g = rng.uniform(0.0, 1e4, (K.LANES + 9, 2))
    batch = sc.raw(g, workers=1)
    for i in range(0, len(g), 5):
        assert sc.raw(g[i : i + 1], workers=1).tobytes() == batch[i : i + 1].tobytes()


def _vehicle(road: str, controller: str, params: dict[str, str] | None = None) -> Any:
    return abs_vehicle.PLANT.scenario(None, road, controller, params or {})


@pytest.mark.parametrize("road", ["dry-concrete", "mu-jump", "split-mu"])
def test_on_the_vehicle_the_added_law_agrees_with_the_held_pid_where_they_are_one(
    road: str,
) -> None:
    """With ki = 0 and an amplitude the command never reaches, u = clip(kp e + 0 z) = kp e is
    the held PID's u = kp e + 0 z + 0 N (e - xf): the two laws' runs agree to rounding (the
    other state each integrates does not act)."""
    big = {"amplitude": "1e9"}
    for kp in (600.0, 1200.0, 3000.0):
        ours = _vehicle(road, NAME, big).metrics(np.array([[kp, 0.0]]))
        pid = _vehicle(road, "pid").metrics(np.array([[kp, 0.0, 0.0]]))
        assert ours["status"][0] == pid["status"][0] == "stopped"
        for key in ("stop_time_s", "stop_distance_m"):
            assert abs(float(ours[key][0]) - float(pid[key][0])) <= 1e-9 * float(pid[key][0])


def test_on_the_vehicle_the_integral_state_acts() -> None:
    sc = _vehicle("dry-concrete", NAME)
    d = sc.metrics(np.array([[1200.0, 0.0], [1200.0, 3000.0]]))["stop_distance_m"]
    assert d[0] != d[1]


@pytest.mark.parametrize(
    ("road", "params"), [("mu-jump", {}), ("split-mu", {"steering": "driver"})]
)
def test_on_the_vehicle_batch_rows_equal_single_runs(road: str, params: dict[str, str]) -> None:
    """The straight pass (mu-jump) and the general one (split-mu, the driver steering)."""
    sc = _vehicle(road, NAME, params)
    rng = np.random.default_rng(11)
    g = rng.uniform(0.0, 5000.0, (VL.LANES + 5, 2))
    batch = sc.raw(g, workers=1)
    for i in range(0, len(g), 7):
        assert sc.raw(g[i : i + 1], workers=1).tobytes() == batch[i : i + 1].tobytes()
