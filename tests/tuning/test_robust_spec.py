"""Uncertain-parameter specs: `--vary`, `--aggregate` and the `[uncertainty]` table."""

from __future__ import annotations

import math

import pytest

from chassistune.errors import InputError
from chassistune.tuning.robust.aggregate import Aggregate, parse_aggregate
from chassistune.tuning.robust.spec import (
    ParamRange,
    PassCriterion,
    check_sampler,
    parse_table,
    parse_vary,
    spec_from_options,
)

KNOWN = {
    "mass_kg": ParamRange(0.0, math.inf, lo_open=True),
    "mu_scale": ParamRange(0.0, math.inf, lo_open=True),
    "lock_ratio": ParamRange(0.0, 1.0),
}


def test_uniform_and_normal_specs_parse_in_order():
    a, b, c = parse_vary(
        ["mass_kg=80:120", "mu_scale = normal:1.0:0.1", "lock_ratio=uniform:0:0.5"], KNOWN
    )
    assert (a.name, a.dist, a.lo, a.hi) == ("mass_kg", "uniform", 80.0, 120.0)
    assert (b.name, b.dist, b.mean, b.sd) == ("mu_scale", "normal", 1.0, 0.1)
    assert b.valid == KNOWN["mu_scale"]
    assert (c.lo, c.hi) == (0.0, 0.5)  # a closed end may be reached


@pytest.mark.parametrize(
    ("item", "field", "words"),
    [
        ("mass=80:120", "vary.mass", "unknown uncertain parameter 'mass'"),
        ("mass_kg=120:80", "vary.mass_kg", "LO < HI"),
        ("mass_kg=80:80", "vary.mass_kg", "LO < HI"),
        ("mass_kg=0:120", "vary.mass_kg", "outside the valid range (0, inf)"),
        ("lock_ratio=0.5:1.5", "vary.lock_ratio", "outside the valid range [0, 1]"),
        ("mu_scale=normal:-1:0.1", "vary.mu_scale", "mean -1 outside the valid range"),
        ("mu_scale=normal:1:0", "vary.mu_scale", "standard deviation must be positive"),
        ("mass_kg=80", "vary.mass_kg", "expected LO:HI"),
        ("mass_kg=a:b", "vary.mass_kg", "not a number"),
        ("mass_kg=80:nan", "vary.mass_kg", "must be finite"),
        ("mass_kg", "vary", "expected NAME=LO:HI"),
    ],
)
def test_bad_vary_specs_name_the_field_on_one_line(item, field, words):
    with pytest.raises(InputError) as exc:
        parse_vary([item], KNOWN)
    assert exc.value.field == field
    assert words in str(exc.value)
    assert "\n" not in str(exc.value)


def test_a_parameter_varied_twice_is_refused():
    with pytest.raises(InputError, match=r"^vary\.mass_kg: listed twice"):
        parse_vary(["mass_kg=80:120", "mass_kg=90:110"], KNOWN)


def test_sobol_needs_a_power_of_two_and_lhs_does_not():
    for k in (1, 2, 16, 1024):
        check_sampler("sobol", k)
    check_sampler("lhs", 12)
    with pytest.raises(InputError, match=r"^scenarios: must be a power of two"):
        check_sampler("sobol", 12)
    with pytest.raises(InputError, match=r"^sampler: must be sobol or lhs"):
        check_sampler("halton", 16)
    with pytest.raises(InputError, match=r"scenarios: must be an integer >= 1, got 0"):
        check_sampler("lhs", 0)
    check_sampler("sobol", 0, minimum=0)  # a training set of none: the nominal plant


def test_aggregate_parsing():
    assert parse_aggregate("mean") == Aggregate("mean")
    assert parse_aggregate("MAX") == Aggregate("max")
    assert parse_aggregate("cvar:0.2") == Aggregate("cvar", 0.2)
    assert str(parse_aggregate("cvar:0.25")) == "cvar:0.25"
    for bad, words in (
        ("median", "must be mean, max or cvar:ALPHA"),
        ("cvar", "must be mean, max or cvar:ALPHA"),
        ("max:0.2", "must be mean, max or cvar:ALPHA"),
        ("cvar:0", "ALPHA must be in (0, 1]"),
        ("cvar:1.5", "ALPHA must be in (0, 1]"),
        ("cvar:x", "not a number"),
    ):
        with pytest.raises(InputError, match=r"^aggregate: ") as exc:
            parse_aggregate(bad)
        assert words in str(exc.value)


def test_the_study_table_parses_into_a_spec():
    spec = parse_table(
        {
            "vary": {"mass_kg": [80, 120], "mu_scale": "normal:1:0.05"},
            "scenarios": 32,
            "sampler": "sobol",
            "aggregate": "cvar:0.25",
            "validate": 300,
            "beta": 0.01,
            "pass": {"max_distance_ratio": 1.2, "allow_lock": True},
        },
        KNOWN,
    )
    assert spec.names == ("mass_kg", "mu_scale")
    assert (spec.scenarios, spec.sampler, spec.validate, spec.beta) == (32, "sobol", 300, 0.01)
    assert spec.aggregate == Aggregate("cvar", 0.25)
    assert spec.criterion == PassCriterion(
        require_stop=True, allow_lock=True, max_distance_ratio=1.2
    )


@pytest.mark.parametrize(
    ("table", "field"),
    [
        ({"vary": {"mass": "80:120"}}, "vary.mass"),
        ({"vary": {"mass_kg": "120:80"}}, "vary.mass_kg"),
        ({"vary": {}}, "vary"),
        ({"vary": {"mass_kg": "80:120"}, "scenarios": 10}, "scenarios"),
        ({"vary": {"mass_kg": "80:120"}, "sampler": "grid"}, "sampler"),
        ({"vary": {"mass_kg": "80:120"}, "aggregate": "cvar:2"}, "aggregate"),
        ({"vary": {"mass_kg": "80:120"}, "validate": -1}, "validate"),
        ({"vary": {"mass_kg": "80:120"}, "beta": 1.0}, "beta"),
        ({"vary": {"mass_kg": "80:120"}, "seeds": 3}, "seeds"),
        (
            {"vary": {"mass_kg": "80:120"}, "pass": {"max_distance_ratio": 0.9}},
            "pass.max_distance_ratio",
        ),
        ({"vary": {"mass_kg": "80:120"}, "pass": {"allow_lock": "yes"}}, "pass.allow_lock"),
        ({"vary": {"mass_kg": "80:120"}, "pass": {"stop": True}}, "pass.stop"),
    ],
)
def test_bad_tables_name_the_field_inside_the_table(table, field):
    with pytest.raises(InputError) as exc:
        parse_table(table, KNOWN)
    assert exc.value.field == field


def test_the_cli_options_build_a_spec_and_errors_name_the_domain_field():
    spec = spec_from_options(KNOWN, ["mass_kg=80:120"], 8, "lhs", "cvar:0.5", 300, 0.1)
    assert (spec.names, spec.scenarios, spec.sampler, spec.validate, spec.beta) == (
        ("mass_kg",),
        8,
        "lhs",
        300,
        0.1,
    )
    assert spec.aggregate == Aggregate("cvar", 0.5)
    for kwargs, field in (
        ({"vary": ["m=1:2"]}, "vary.m"),
        ({"scenarios": 12}, "scenarios"),
        ({"sampler": "grid"}, "sampler"),
        ({"aggregate": "worst"}, "aggregate"),
        ({"validate": -3}, "validate"),
        ({"beta": 0.0}, "beta"),
    ):
        args = {"vary": ["mass_kg=80:120"], **kwargs}
        with pytest.raises(InputError) as exc:
            spec_from_options(KNOWN, **args)
        assert exc.value.field == field
