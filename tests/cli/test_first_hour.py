"""What went wrong in a new user's first hour: the tune's defaults and checks, `list params`,
output checks, units and `simulate --r13h`; one test (or more) per fault."""

from __future__ import annotations

import json


def test_tune_defaults_to_pid(cli):
    r = cli("tune", "abs-wheel", "--optimizer", "pso", "--pop", "4", "--iters", "1", "--json")
    assert r.code == 0, r.err
    assert json.loads(r.out)["controller"] == "pid"


def test_tune_checks_every_given_option_before_a_missing_one(cli):
    r = cli("tune", "abs-wheel", "--controller", "pidd")
    assert r.code == 2 and "--controller" in r.err and "pidd" in r.err, r.err
    r = cli("tune", "abs-wheel", "--controller", "pid")
    assert r.code == 2, r.err
    assert r.err.strip() == "chassistune: error: --optimizer: missing (chassistune list optimizers)"
