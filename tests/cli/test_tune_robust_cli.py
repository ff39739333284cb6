"""`tune --vary ...` through the real CLI: the validation object and the bad-input contract."""

from __future__ import annotations

import json

import pytest

TUNE = (
    "tune",
    "abs-wheel",
    "--controller",
    "pid",
    "--optimizer",
    "derlsp-ao",
    "--pop",
    "4",
    "--iters",
    "1",
)


def test_tune_json_gains_the_validation_object_and_the_certificate(cli):
    r = cli(
        *TUNE,
        "--vary",
        "mass_kg=80:120",
        "--vary",
        "mu_scale=0.85:1.15",
        "--scenarios",
        "4",
        "--aggregate",
        "cvar:0.5",
        "--validate",
        "8",
        "--objective",
        "distance_ratio",
        "--json",
    )
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["aggregate"] == "cvar:0.5" and doc["objective"] == "distance_ratio"
    assert doc["uncertainty"]["scenarios"] == 4 and doc["uncertainty"]["sampler"] == "sobol"
    assert doc["training"]["names"] == ["mass_kg", "mu_scale"]
    assert len(doc["training"]["values"]) == 4 and len(doc["training"]["costs"]) == 4
    v = doc["validation"]
    assert v["n"] == 8 and v["failures"] + round(v["pass_rate"] * 8) == 8
    if v["failures"] == 0:  # zero-failure bound eps = ln(1/beta) / N
        assert v["certificate"] == {
            "eps": pytest.approx(-__import__("math").log(0.05) / 8),
            "beta": 0.05,
        }
    else:
        assert v["certificate"] is None
    # the cvar of the winner's 4 training costs is the tuned cost: mean of the worst 2
    worst2 = sorted(doc["training"]["costs"])[2:]
    assert doc["best_cost"] == pytest.approx(sum(worst2) / 2, rel=1e-15)


def test_a_nominal_tune_has_no_validation_object(cli):
    r = cli(*TUNE, "--json")
    assert r.code == 0, r.err
    assert "validation" not in json.loads(r.out)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("--vary", "foo_kg=1:2"), "--vary foo_kg: unknown uncertain parameter 'foo_kg'"),
        (("--vary", "mass_kg=120:80"), "--vary mass_kg: need LO < HI, got 120:80"),
        (("--vary", "mass_kg=-10:80"), "--vary mass_kg: range [-10, 80] outside the valid range"),
        (("--vary", "mu_scale=0:1.1"), "--vary mu_scale: range [0, 1.1] outside the valid range"),
        (
            ("--vary", "mass_kg=80:120", "--scenarios", "6"),
            "--scenarios: must be a power of two for the sobol sampler, got 6",
        ),
        (("--vary", "mass_kg=normal:100:0"), "--vary mass_kg: the standard deviation must be"),
        (("--vary", "mass_kg=80:120", "--aggregate", "cvar:0"), "--aggregate: cvar ALPHA must be"),
        (("--vary", "mass_kg=80:120", "--beta", "1"), "--beta: must be in (0, 1)"),
        (("--vary", "mass_kg=80:120", "--validate", "-3"), "--validate: must be a non-negative"),
        (("--scenarios", "8"), "--scenarios: needs --vary"),
        (("--validate", "300"), "--validate: needs --vary"),
        (("--vary", "v0_m_s=0.1:0.4"), "--vary v0_m_s: a draw the plant refuses"),
    ],
)
def test_bad_robust_input_is_one_line_exit_2(cli, args, words):
    r = cli(*TUNE, *args)
    assert r.code == 2
    assert r.out == ""
    lines = r.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.err
    assert lines[0].startswith(f"chassistune: error: {words}"), lines[0]
