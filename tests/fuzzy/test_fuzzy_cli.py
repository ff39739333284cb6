"""`chassistune fuzzy show|eval`, in process: output contracts and one-line errors with exit 2."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from test_fuzzy_schema import SMALL_TOML

from chassistune.fuzzy import evaluate, load_rulebase, rulebase_from_dict


@pytest.mark.parametrize("name", ["deffao", "classic", "immune"])
def test_show_json_is_the_description(cli: Callable[..., Any], name: str) -> None:
    r = cli("fuzzy", "show", name, "--json")
    assert r.code == 0 and r.err == ""
    description = json.loads(r.out)
    assert set(description) == {"inputs", "outputs", "rules", "operators"}
    assert description["operators"] == {"and": "min", "aggregate": "max", "defuzzify": "centroid"}
    assert rulebase_from_dict(description, name) == load_rulebase(name)


def test_show_human_prints_the_table(cli: Callable[..., Any]) -> None:
    r = cli("fuzzy", "show", "immune")
    assert r.code == 0
    assert "e \\ ec  NB  NS  ZE  PS  PB" in r.out
    assert "  NS      NB  NB  NS  PB  NB" in r.out


def test_eval_json(cli: Callable[..., Any]) -> None:
    r = cli("fuzzy", "eval", "deffao", "--input", "e=0.7", "--input", "ec=-1.3", "--json")
    assert r.code == 0 and r.err == ""
    outputs = json.loads(r.out)["outputs"]
    expected = evaluate(load_rulebase("deffao"), [0.7, -1.3])[0]
    assert list(outputs) == ["kp", "ki", "kd"]
    assert [outputs[k] for k in ("kp", "ki", "kd")] == pytest.approx(expected, abs=1e-12)


def test_eval_human_notes_clipping(cli: Callable[..., Any]) -> None:
    r = cli("fuzzy", "eval", "immune", "--input", "ec=0", "--input", "e=7")
    assert r.code == 0
    assert "e = 7  (clipped to 1)" in r.out and r.out.strip().splitlines()[-1].startswith("f = ")


def test_user_file(cli: Callable[..., Any], tmp_path: Path) -> None:
    path = tmp_path / "mine.toml"
    path.write_text(SMALL_TOML)
    r = cli("fuzzy", "eval", str(path), "--input", "x=0.2", "--input", "y=1", "--json")
    assert r.code == 0 and set(json.loads(r.out)["outputs"]) == {"z"}


def test_plot(cli: Callable[..., Any], tmp_path: Path) -> None:
    path = tmp_path / "immune.png"
    r = cli("fuzzy", "show", "immune", "--json", "--plot", str(path))
    assert r.code == 0 and json.loads(r.out)["rules"]
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 20_000


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["eval", "classic", "--input", "e=0", "--input", "speed=3"],
            "--input: unknown input 'speed'",
        ),
        (
            ["eval", "classic", "--input", "e=zero", "--input", "ec=0"],
            "--input: e: not a number: 'zero'",
        ),
        (["eval", "classic", "--input", "e=nan", "--input", "ec=0"], "not a finite number"),
        (["eval", "classic", "--input", "e", "--input", "ec=0"], "expected NAME=VALUE"),
        (["eval", "classic", "--input", "e=1", "--input", "e=2"], "given twice"),
        (["eval", "classic", "--input", "e=1"], "missing a value for input 'ec'"),
        (["show", "fancy"], "rulebase: unknown rule base 'fancy'"),
        (["show", "missing.toml"], "rulebase: file not found"),
        (["show", "immune", "--plot", "surface.jpg"], "--plot: expected a file ending in .png"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(
    cli: Callable[..., Any], args: list[str], message: str
) -> None:
    r = cli("fuzzy", *args)
    assert r.code == 2 and r.out == ""
    assert r.err.count("\n") == 1 and message in r.err, r.err


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("this is not toml", "is not valid TOML"),
        (
            SMALL_TOML.replace('["P", "P", "HI"]', '["P", "P", "TOP"]'),
            "rules[3][2]: unknown set 'TOP'",
        ),
        (SMALL_TOML.replace("universe = [0.0, 2.0]", "universe = [2.0, 0.0]"), "lo must be < hi"),
        (
            SMALL_TOML.replace(
                'shape = "gauss", params = [0.0, 0.6]', 'shape = "bell", params = [0.0, 0.6]'
            ),
            "unknown shape 'bell'",
        ),
        (SMALL_TOML.replace('  ["P", "P", "HI"],\n', ""), "complete 2 x 2 table of 4 rules, got 3"),
    ],
)
def test_bad_rulebase_file_is_one_line_and_exit_2(
    cli: Callable[..., Any], tmp_path: Path, text: str, message: str
) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    r = cli("fuzzy", "show", str(path))
    assert r.code == 2 and r.out == ""
    assert r.err.count("\n") == 1 and message in r.err and "bad.toml" in r.err, r.err
