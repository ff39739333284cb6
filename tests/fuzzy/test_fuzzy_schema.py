"""Rule-base descriptions are validated with one clear message naming the field."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import pytest

from chassistune.errors import InputError
from chassistune.fuzzy import load_rulebase, rulebase_from_dict

SMALL_TOML = """\
# a 2 x 2 rule base with trapezoids and Gaussians
description = "test"
operators = { and = "min", aggregate = "max", defuzzify = "centroid" }
rules = [
  ["N", "N", "LO"],
  ["N", "P", "MID"],
  ["P", "N", "MID"],
  ["P", "P", "HI"],
]

[[inputs]]
name = "x"
universe = [-1.0, 1.0]
sets = [
  { name = "N", shape = "trap", params = [-1.0, -1.0, -0.5, 0.5] },
  { name = "P", shape = "trap", params = [-0.5, 0.5, 1.0, 1.0] },
]

[[inputs]]
name = "y"
universe = [0.0, 2.0]
sets = [
  { name = "N", shape = "gauss", params = [0.0, 0.6] },
  { name = "P", shape = "gauss", params = [2.0, 0.6] },
]

[[outputs]]
name = "z"
universe = [0.0, 10.0]
sets = [
  { name = "LO", shape = "tri", params = [0.0, 0.0, 5.0] },
  { name = "MID", shape = "gauss", params = [5.0, 1.5] },
  { name = "HI", shape = "trap", params = [5.0, 8.0, 10.0, 10.0] },
]
"""


def small_description() -> dict[str, Any]:
    import tomllib

    return tomllib.loads(SMALL_TOML)


def test_small_file_loads(tmp_path: Path) -> None:
    path = tmp_path / "small.toml"
    path.write_text(SMALL_TOML)
    rb = load_rulebase(str(path))
    assert rb.name == "small" and rb.input_names == ("x", "y") and rb.output_names == ("z",)
    assert rb.description == "test"
    assert load_rulebase(path) is rb  # cached per file and modification time


def _break(description: dict[str, Any], path: str, value: Any) -> dict[str, Any]:
    """Set (or delete, for value ...) the item at a dotted path like 'inputs.0.sets.1.params'."""
    out = copy.deepcopy(description)
    *parents, last = path.split(".")
    node: Any = out
    for key in parents:
        node = node[int(key)] if isinstance(node, list) else node[key]
    key: Any = int(last) if isinstance(node, list) else last
    if value is ...:
        del node[key]
    else:
        node[key] = value
    return out


@pytest.mark.parametrize(
    ("path", "value", "field", "words"),
    [
        ("rules.1.1", "Q", "rules[1][1]", "unknown set 'Q' of input 'y'"),
        ("rules.2.2", "TOP", "rules[2][2]", "unknown set 'TOP' of output 'z'"),
        ("rules.3", ["P", "P"], "rules[3]", "expected 3 set names"),
        ("rules.3", ["P", "N", "HI"], "rules[3]", "repeats the antecedent"),
        ("rules.3", ..., "rules", "complete 2 x 2 table of 4 rules, got 3"),
        ("rules", [], "rules", "must not be empty"),
        ("inputs.0.universe", [1.0, -1.0], "inputs[0].universe", "lo must be < hi"),
        ("inputs.1.universe", [0.0, 0.0], "inputs[1].universe", "lo must be < hi"),
        ("outputs.0.universe", [0.0], "outputs[0].universe", "expected [lo, hi]"),
        ("outputs.0.universe", [0.0, "ten"], "outputs[0].universe[1]", "finite number"),
        ("inputs.0.sets.1.shape", "bell", "inputs[0].sets[1].shape", "unknown shape 'bell'"),
        ("inputs.0.sets.0.params", [-1.0, 0.0], "inputs[0].sets[0].params", "takes 4 parameters"),
        ("outputs.0.sets.1.params", [5.0, -1.0], "outputs[0].sets[1].params", "sigma"),
        ("outputs.0.sets.0.params", [0.0, 6.0, 5.0], "outputs[0].sets[0].params", "non-decreasing"),
        (
            "outputs.0.sets.2.params",
            [20.0, 21.0, 22.0, 23.0],
            "outputs[0].sets[2].params",
            "outside",
        ),
        ("outputs.0.sets.2.name", "LO", "outputs[0].sets[2].name", "duplicate set name 'LO'"),
        ("outputs.0.name", "x", "outputs", "duplicate variable name 'x'"),
        ("inputs.0.sets.0.colour", "red", "inputs[0].sets[0]", "unknown key 'colour'"),
        ("inputs.1.sets", ..., "inputs[1]", "missing key 'sets'"),
        ("operators.and", "prod", "operators.and", "only 'min' is supported"),
        ("operators.defuzzify", "bisector", "operators.defuzzify", "only 'centroid'"),
        ("outputs", ..., "", "missing key 'outputs'"),
        ("rule", [], "", "unknown key 'rule'"),
        ("inputs", {"name": "x"}, "inputs", "expected an array"),
    ],
)
def test_bad_description_names_the_field(path: str, value: Any, field: str, words: str) -> None:
    bad = _break(small_description(), path, value)
    with pytest.raises(InputError) as info:
        rulebase_from_dict(bad, "small", where="rulebase small.toml")
    expected_field = f"rulebase small.toml: {field}" if field else "rulebase small.toml"
    assert info.value.field == expected_field
    assert words in info.value.problem
    assert "\n" not in str(info.value)


def test_missing_file_and_unknown_name(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="file not found"):
        load_rulebase(str(tmp_path / "nope.toml"))
    with pytest.raises(InputError, match=r"unknown rule base 'fancy'.*deffao"):
        load_rulebase("fancy")
    with pytest.raises(InputError, match="not a file"):
        load_rulebase(str(tmp_path) + "/")


def test_not_toml(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text('rules = [["NB", \n')
    with pytest.raises(InputError, match="is not valid TOML") as info:
        load_rulebase(str(path))
    assert info.value.field == "rulebase"
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\xff\xfe\x00rules")
    with pytest.raises(InputError, match="not a UTF-8 text file"):
        load_rulebase(str(binary))


def test_file_errors_name_the_file(tmp_path: Path) -> None:
    path = tmp_path / "typo.toml"
    path.write_text(SMALL_TOML.replace('["P", "P", "HI"]', '["P", "PP", "HI"]'))
    with pytest.raises(InputError) as info:
        load_rulebase(str(path))
    assert str(info.value).startswith("rulebase typo.toml: rules[3][1]: unknown set 'PP'")


def test_edited_file_is_reloaded(tmp_path: Path) -> None:
    path = tmp_path / "small.toml"
    path.write_text(SMALL_TOML)
    first = load_rulebase(str(path))
    path.write_text(SMALL_TOML.replace('description = "test"', 'description = "edited!"'))
    assert load_rulebase(str(path)).description == "edited!" != first.description
