"""The centre-bias test: `optimize --shift`, the loss table and the verdicts."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from chassistune.benchmarks.shifted import shifted
from chassistune.studies.centre_bias import GAP_FLOOR, LossRow, loss_table, markdown, verdict


def test_optimize_shift_moves_the_optimum_drawn_from_the_seed(cli) -> None:
    args = ["optimize", "F9", "--dim", "3", "--optimizer", "cma-es", "--evals", "1500", "--json"]
    plain = json.loads(cli(*args, "--seed", "4").out)
    moved = json.loads(cli(*args, "--seed", "4", "--shift").out)
    other = json.loads(cli(*args, "--seed", "5", "--shift").out)
    assert "optimum" not in plain and moved["function"] == "F9+shift"
    g = shifted("F9", 3, np.random.SeedSequence(4, spawn_key=(1,)))
    assert moved["optimum"] == g.minimizer().tolist()
    assert moved["optimum"] != other["optimum"]
    assert moved["best_f"] == pytest.approx(float(g(np.array(moved["best_x"]))), abs=0)
    assert moved["nfev"] == 1500


def test_loss_is_orders_of_magnitude_and_the_verdict_thresholds() -> None:
    row = LossRow("x", "F1", 1e-8, 1e-2)
    assert row.loss == pytest.approx(6.0)
    rows = [LossRow("a", f, 1e-8, 1e-6) for f in ("F1", "F9", "F10")] + [
        LossRow("b", f, 1.0, 2.0) for f in ("F1", "F9", "F10")
    ]
    rows.append(LossRow("b", "F8", 1.0, 1e9))  # not a centred function: no weight
    assert verdict(rows, "a") == (pytest.approx(2.0), "centre-biased")
    assert verdict(rows, "b")[1] == "no centre bias"
    assert verdict([LossRow("c", "F2", 1.0, 10**0.7)], "c")[1] == "mild"
    assert math.isnan(verdict(rows, "nope")[0])
    table = markdown(rows)
    assert "| a | +2.0 | +2.0 | +2.0 |" in table and "centre-biased" in table


def test_ao_loses_on_the_moved_optimum_and_cma_es_does_not() -> None:
    """A measured case: AO's eq. 13 scales Xbest by (1 - t/T), a pull towards 0 that finds the
    sphere's published optimum; CMA-ES is translation invariant, up to the bounds."""
    rows = loss_table(["ao", "cma-es"], ["F1", "F2"], seeds=2, evals=2000, dim=5)
    by = {(r.optimizer, r.function): r for r in rows}
    assert all(r.plain_gap >= GAP_FLOOR and r.shifted_gap >= GAP_FLOOR for r in rows)
    assert by[("ao", "F1")].loss > 3 and by[("ao", "F2")].loss > 1
    assert abs(by[("cma-es", "F1")].loss) < 1.5
    assert verdict(rows, "ao")[1] == "centre-biased"
    assert verdict(rows, "cma-es")[1] != "centre-biased"
