"""A control law added in this one file, no other file edited: a saturated proportional slip law
u0 = amplitude clip(k_sat e, -1, 1) (e = S_target - S), sampled every ts_s and held (the
continuous PID's gains stay zero). Registered for this module's tests and removed after them, it
runs on the single wheel (ideal and realistic ECU) and on the vehicle, passes the conformance
check, tunes, and the C its module declares, printed by the export (also through `chassistune
export`), reproduces the ideal kernel's and the ECU's commands bit for bit."""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from helpers import CLaw, needs_cc, write_c
from numba import njit

from chassistune.controllers import laws
from chassistune.controllers.discrete import no_table
from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws.registry import DiscreteLaw
from chassistune.controllers.laws.shared import AMPLITUDE, SAMPLE_PERIOD, per_wheel
from chassistune.controllers.specs import ControllerSpec, GainSpec
from chassistune.export import c99, vectors
from chassistune.export.source import ExportedController
from chassistune.scenarios.abs_wheel import AbsWheelScenario
from chassistune.scenarios.base import PENALTY
from chassistune.scenarios.check import check_plant
from chassistune.scenarios.registry import get_plant
from chassistune.tuning.tune import tune

NAME = "saturated-p"
WHEEL = ControllerSpec(
    laws.ABS_WHEEL,
    NAME,
    "saturated proportional slip law u0 = amplitude clip(k_sat e, -1, 1), sampled every ts_s",
    gains=(GainSpec("k_sat", "1/(slip)", 50.0, 0.0, 1000.0, "slope of the linear zone"),),
    params=(AMPLITUDE, SAMPLE_PERIOD),
)
G_K = F.gains(WHEEL)["k_sat"]


@functools.cache
def compiled_forms() -> tuple[Any, Any]:
    """(tick, step): the saturated command at each sample of the ideal kernels, and the ECU's
    discrete step on (state, inputs (slip,), params (k_sat, amplitude, target_slip, ts_s))."""

    @njit(**F.FORM)
    def command(k_sat, e, amplitude):  # type: ignore[no-untyped-def]
        u = k_sat * e
        if u > 1.0:
            u = 1.0
        if u < -1.0:
            u = -1.0
        return amplitude * u

    @njit(**F.FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):  # type: ignore[no-untyped-def]
        u0 = command(g[g0 + G_K], sig[F.SIG_SLIP_ERROR], c[F.P_AMPLITUDE])
        return (u0, held[F.H_KP], held[F.H_KI], held[F.H_KD]), mem

    @njit(**F.FORM)
    def step(state, inputs, params, table, grid):  # type: ignore[no-untyped-def]
        state[0] = 1.0
        return command(params[0], params[2] - inputs[0], params[1])

    return tick, step


def kernel_forms() -> tuple[Any, Any]:
    """(start, tick): at rest at the start; the saturated command at each sample."""
    return None, compiled_forms()[0]


def ecu_step() -> Any:
    """The ECU's step: the same command of the ECU's slip (the discrete form the C prints)."""
    return compiled_forms()[1]


LAW = laws.Law(
    NAME,
    (WHEEL, per_wheel(WHEEL)),
    functools.cache(kernel_forms),
    discrete=DiscreteLaw(
        NAME,
        ("slip",),
        ("k_sat", "amplitude", "target_slip", "ts_s"),
        ("started",),
        0,
        "sampled saturated proportional law",
    ),
    ecu=laws.EcuForm(ecu_step),
    c=laws.CForm(
        ("u_k = amplitude clip(k_sat e_k, -1, 1)",),
        """\
double ct_step(ct_state *s, const double *in)
{
    double u = s->p.k_sat * (s->p.target_slip - in[CT_IN_SLIP]);
    if (u > 1.0) u = 1.0;
    if (u < -1.0) u = -1.0;
    s->started = 1.0;
    return s->p.amplitude * u;
}
""",
    ),
    source="a test law: a saturated proportional slip law, defined in this file",
)

NAME_PLANT = laws.ABS_WHEEL
SHORT = {NAME_PLANT: {"v0_m_s": 15.0}}
"""Shorter runs than the presets' (as tests/scenarios/test_check_plant.py)."""

pytestmark = pytest.mark.slow  # the kernels compile with the added law


@pytest.fixture(scope="module", autouse=True)
def registered() -> Iterator[None]:
    laws.register(LAW)
    yield
    laws.unregister(NAME)


@pytest.mark.parametrize("plant", [laws.ABS_WHEEL, laws.ABS_VEHICLE])
def test_the_added_law_is_a_controller_of_both_plants(plant: str) -> None:
    assert NAME in [s.name for s in get_plant(plant).controllers()]
    assert laws.kind(NAME) == len(laws.names()) - 1


@pytest.mark.parametrize("plant", [laws.ABS_WHEEL, laws.ABS_VEHICLE])
def test_the_added_law_passes_the_conformance_check(plant: str) -> None:
    check_plant(plant, SHORT.get(plant))


@pytest.mark.parametrize(("plant", "road"), [("abs-wheel", "ice"), ("abs-vehicle", "mu-jump")])
def test_the_added_law_stops_shorter_than_no_abs(plant: str, road: str) -> None:
    p = get_plant(plant)
    distance = {}
    for name in (NAME, "none"):
        sc = p.scenario(None, road, name, {}, 0)
        m = sc.metrics(sc.gains_array(None)[None, :])
        assert m["status"][0] == "stopped"
        distance[name] = float(m["stop_distance_m"][0])
    assert distance[NAME] < distance["none"]


def test_the_added_law_tunes() -> None:
    result = tune(
        "abs-wheel", NAME, "pso", pop_size=6, max_iter=2, seed=1, params=SHORT[NAME_PLANT]
    )
    assert set(result.best_gains) == {"k_sat"} and 0.0 <= result.best_gains["k_sat"] <= 1000.0
    assert np.isfinite(result.best_cost) and result.best_cost < PENALTY
    assert np.isfinite(result.default_cost) and result.default_cost < PENALTY


def _export(sc: AbsWheelScenario) -> ExportedController:
    """The added law's discrete form at the scenario's sample period and default gains."""
    table, grid = no_table()
    cp = sc.controller_params
    law = LAW.discrete
    assert law is not None
    values = {"k_sat": WHEEL.gains[0].default, "target_slip": sc.target_slip, **cp}
    return ExportedController(
        law=law,
        scenario=sc,
        gains={"k_sat": WHEEL.gains[0].default},
        params=np.array([float(values[n]) for n in law.params]),
        table=table,
        grid=grid,
        breakpoints=(),
        table_inputs=(),
        table_outputs=(),
        rulebase=None,
        source="test law",
    )


@needs_cc
def test_the_added_laws_c_reproduces_the_ideal_kernel_bit_for_bit(tmp_path: Path) -> None:
    sc = get_plant("abs-wheel").scenario(None, "ice", NAME, {"ts_s": 0.005}, 0)
    assert isinstance(sc, AbsWheelScenario)
    trace = sc.trace(sc.gains_array(None))
    steps = round(0.005 / sc.plant_params.dt_s)
    slip, u = trace.signals["slip"], trace.signals["command"]
    ticks = np.arange(0, len(u) - 1, steps)  # the sample instants: steps k, slip at their start
    inputs = slip[ticks][:, None]
    expected = u[ticks + 1]  # the command over step k (row k + 1 of the trace)
    assert len(ticks) > 100 and np.unique(expected).size > 10  # saturated and linear samples
    folder = write_c(_export(sc), tmp_path)
    assert "u_k = amplitude clip(k_sat e_k, -1, 1)" in c99.header(_export(sc))
    assert np.array_equal(CLaw(folder, c99.BITWISE_FLAGS).run(inputs), expected)


def test_the_added_law_runs_in_the_realistic_ecu() -> None:
    p = get_plant("abs-wheel")
    distance = {}
    for name in (NAME, "none"):
        sc = p.scenario(None, "ice", name, {"ecu": "realistic"}, 0)
        m = sc.metrics(sc.gains_array(None)[None, :])
        assert m["status"][0] == "stopped"
        distance[name] = float(m["stop_distance_m"][0])
    assert distance[NAME] < distance["none"]


@needs_cc
def test_the_cli_exports_the_added_law_and_its_c_replays_the_vectors_bit_for_bit(
    cli: Callable[..., Any], tmp_path: Path
) -> None:
    out = tmp_path / "c"
    res = cli("export", "--controller", NAME, "--format", "c", "--out", str(out))
    assert res.code == 0, res.err
    names, data = vectors.read_csv(str(out / "test_vectors.csv"))
    assert names == ("slip", "u")
    inputs, u = data[:, :-1], data[:, -1]
    assert len(u) > 100 and np.unique(u).size > 10  # saturated and linear samples
    assert np.array_equal(CLaw(out, c99.BITWISE_FLAGS).run(inputs), u)
