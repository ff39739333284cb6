"""The fuzzy control laws' step functions against exact inference and their equations."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.controllers.fuzzy_pid import fuzzy_pid_gains
from chassistune.controllers.immune_pid import immune_gain, immune_pid_step, incremental_pid_du
from chassistune.fuzzy import compiled, evaluate, load_rulebase, surface_lookup, surface_value

TOLERANCE = 1e-3  # of the output range


@pytest.mark.parametrize("name", ["deffao", "classic"])
def test_fuzzy_pid_gain_schedule(name: str) -> None:
    rb = load_rulebase(name)
    cs = compiled(rb)
    rng = np.random.default_rng(5)
    e, de = rng.uniform(-0.3, 0.3, 200), rng.uniform(-30.0, 30.0, 200)
    ke, kec, ku, k0 = 10.0, 0.1, np.array([500.0, 20.0, 50.0]), np.array([3000.0, 5.0, 200.0])
    gains = np.empty((e.size, 3))
    out = np.empty(3)
    for p in range(e.size):  # compiled step functions are callable from Python too
        gains[p] = fuzzy_pid_gains(cs.table, e[p], de[p], ke, kec, *ku, *k0)
        surface_lookup(cs.table, ke * e[p], kec * de[p], out)
        assert np.array_equal(gains[p], k0 + ku * out)  # the inlined lookup, bit for bit
    exact = k0 + ku * evaluate(rb, np.stack([ke * e, kec * de], 1))
    np.testing.assert_allclose(gains, exact, atol=float(np.max(ku * cs.output_spans)) * TOLERANCE)
    assert all(np.isnan(fuzzy_pid_gains(cs.table, np.nan, 0.0, ke, kec, *ku, *k0)))


def test_immune_gain_and_incremental_law() -> None:
    rb = load_rulebase("immune")
    cs = compiled(rb)
    k_immune, eta, ke, kec = 800.0, 0.6, 5.0, 0.02
    for e, ec in [(0.0, 0.0), (0.1, -20.0), (-0.15, 30.0), (0.3, 80.0)]:
        f = evaluate(rb, [ke * e, kec * ec])[0, 0]
        expected = k_immune * (1.0 - eta * f)
        assert immune_gain(cs.table, e, ec, ke, kec, k_immune, eta) == pytest.approx(
            expected, abs=k_immune * eta * 2.0 * TOLERANCE
        )
    ts = 1e-3
    assert incremental_pid_du(2.0, 3.0, 4.0, ts, 0.1, 0.05, 0.0) == pytest.approx(
        2.0 * 0.05 + 3.0 * ts * 0.1 + 4.0 * (0.1 - 0.1 + 0.0) / ts
    )
    assert incremental_pid_du(0.0, 0.0, 1.0, 0.5, 1.0, 0.0, 1.0) == pytest.approx(4.0)


def test_immune_step_starts_from_rest_without_kick() -> None:
    cs = compiled(load_rulebase("immune"))
    g = (800.0, 0.6, 30.0, 40.0, 5.0, 0.02)  # k_immune, eta, ki, kd, ke, kec
    ts, e = 1e-3, 0.12
    kp1 = 800.0 * (1.0 - 0.6 * surface_value(cs.table, 0, 5.0 * e, 0.0))
    first = immune_pid_step(cs.table, e, 0.3, -0.2, 1.5, ts, True, *g)
    assert first == 1.5 + (kp1 * e + 30.0 * ts * e + 0.0 * e / ts)
    e1, e2 = 0.1, 0.05
    kp1 = 800.0 * (1.0 - 0.6 * surface_value(cs.table, 0, 5.0 * e, 0.02 * (e - e1) / ts))
    later = immune_pid_step(cs.table, e, e1, e2, 1.5, ts, False, *g)
    assert later == 1.5 + incremental_pid_du(kp1, 30.0, 40.0, ts, e, e1, e2)
