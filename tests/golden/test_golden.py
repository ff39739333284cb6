"""Every pinned number (tests/golden/golden.json) is reproduced bit for bit."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

import golden_cases

from chassistune.controllers import laws

PINNED = json.loads(golden_cases.PINNED.read_text())


@pytest.mark.parametrize("law", laws.names())
def test_every_law_of_the_single_wheel_is_pinned(law: str) -> None:
    """A law of the single wheel without a pinned run could change unseen."""
    if laws.get(law).spec(laws.ABS_WHEEL) is None:
        pytest.skip(f"{law} does not run on the single wheel")
    assert law in {case[2] for case in golden_cases.ABS_CASES}


@pytest.mark.parametrize("case", golden_cases.ABS_CASES, ids=lambda c: "/".join(c[:3]))
def test_abs_wheel_runs(case: tuple) -> None:
    preset, road, ctrl, params = case
    assert (
        golden_cases.abs_case(preset, road, ctrl, params)
        == PINNED["abs"][f"{preset}/{road}/{ctrl}"]
    )


@pytest.mark.parametrize("ctrl", ["pid", "fuzzy-pid", "fuzzy-immune-pid"])
def test_abs_wheel_population_costs(ctrl: str) -> None:
    assert golden_cases.abs_population(ctrl) == PINNED["abs_population"][ctrl]


@pytest.mark.parametrize("case", golden_cases.QUARTER_CASES, ids=lambda c: "/".join(c))
def test_quarter_car_runs(case: tuple) -> None:
    assert golden_cases.quarter_case(*case) == PINNED["quarter"]["/".join(case)]


@pytest.mark.parametrize("name", golden_cases.OPTIMIZERS)
def test_optimizers_on_f5(name: str) -> None:
    assert golden_cases.optimizer_case(name) == PINNED["optimizers"][name]


def test_tune_abs_wheel() -> None:
    got = golden_cases.tune_case("abs-wheel", "pid", "derlsp-ao", ["dry-concrete", "ice"])
    assert got == PINNED["tune"]["abs-wheel/pid/derlsp-ao"]


def test_tune_quarter_car() -> None:
    got = golden_cases.tune_case("quarter-car", "pid", "iabc", ["iso-b"])
    assert got == PINNED["tune"]["quarter-car/pid/iabc"]
