"""The built-in rule bases hold the papers' tables.

deffao-vehicle-abs Table 3 (deffao), shared/fuzzy_tables.md (classic), fuzzy-immune-abs Table 1
(immune).
"""

from __future__ import annotations

import pytest

from chassistune.fuzzy import RuleBase, builtin_names, load_rulebase, rulebase_from_dict

# Tian, Huang et al. 2025 (deffao-vehicle-abs), Table 3 exactly as the paper's text prints it: each
# row is its E label followed by seven "kp,ki,kd" cells (columns EC = NB..PB) run together.
SEED_003_TABLE_3 = """\
NBB,Z,SB,Z,MB,Z,BB,Z,BZ,Z,MZ,Z,MZ,Z,S
NMB,S,MM,S,MM,Z,BS,Z,BZ,S,MZ,S,MZ,S,M
NSM,M,ZM,B,SS,M,SZ,B,SS,M,SS,M,SS,M,Z
ZM,B,ZS,B,ZZ,B,SZ,B,ZS,B,ZS,B,ZM,B,Z
PSS,M,ZS,B,SS,M,SZ,B,SM,M,SM,M,SM,M,Z
PMS,S,MZ,S,MS,Z,BS,Z,BM,S,MM,S,MB,S,M
PBZ,Z,SZ,Z,MB,Z,BB,Z,BB,Z,MB,Z,MB,Z,S
"""
LEVELS_7 = ("NB", "NM", "NS", "Z", "PS", "PM", "PB")


def parse_seed_table(text: str) -> dict[tuple[str, str], tuple[str, str, str]]:
    """{(E, EC): (kp, ki, kd)} from the run-together rows of the seed text."""
    table = {}
    for line in text.splitlines():
        label = line[:2] if line[0] in "NP" else line[0]
        letters = line[len(label) :].replace(",", "")
        assert len(letters) == 21 and set(letters) <= set("ZSMB"), line
        for j, ec in enumerate(LEVELS_7):
            kp, ki, kd = letters[3 * j : 3 * j + 3]
            table[(label, ec)] = (kp, ki, kd)
    return table


def cells(rb: RuleBase) -> dict[tuple[str, ...], tuple[str, ...]]:
    n = len(rb.inputs)
    return {tuple(r[:n]): tuple(r[n:]) for r in rb.rules}


def test_builtin_names() -> None:
    assert set(builtin_names()) >= {"deffao", "classic", "immune"}


def test_deffao_is_seed_003_table_3() -> None:
    parsed = parse_seed_table(SEED_003_TABLE_3)
    assert len(parsed) == 49
    assert cells(load_rulebase("deffao")) == parsed


@pytest.mark.parametrize(
    ("e", "ec", "gains"),
    [  # read by eye from the seed text
        ("NB", "NB", ("B", "Z", "S")),
        ("NB", "PB", ("Z", "Z", "S")),
        ("NM", "NS", ("M", "Z", "B")),
        ("NS", "NM", ("M", "B", "S")),
        ("Z", "Z", ("Z", "B", "Z")),
        ("Z", "PB", ("M", "B", "Z")),
        ("PS", "PS", ("M", "M", "S")),
        ("PM", "PB", ("B", "S", "M")),
        ("PB", "NB", ("Z", "Z", "S")),
        ("PB", "Z", ("B", "Z", "B")),
    ],
)
def test_deffao_cells_read_by_eye(e: str, ec: str, gains: tuple[str, str, str]) -> None:
    assert cells(load_rulebase("deffao"))[(e, ec)] == gains


def test_deffao_variables() -> None:
    rb = load_rulebase("deffao")
    assert rb.input_names == ("e", "ec") and rb.output_names == ("kp", "ki", "kd")
    assert all(v.universe == (-3.0, 3.0) and v.set_names == LEVELS_7 for v in rb.inputs)
    assert all(v.universe == (0.0, 1.0) and v.set_names == ("Z", "S", "M", "B") for v in rb.outputs)


@pytest.mark.parametrize(
    ("e", "ec", "deltas"),
    [  # fuzzy_tables.md, rows E, columns EC: (delta-kp, delta-ki, delta-kd)
        ("NB", "NB", ("PB", "NB", "PS")),
        ("NB", "PB", ("ZO", "ZO", "PS")),
        ("NM", "PB", ("NS", "ZO", "ZO")),
        ("ZO", "ZO", ("ZO", "ZO", "NS")),
        ("PS", "NB", ("PS", "NM", "ZO")),
        ("PM", "NM", ("ZO", "ZO", "NS")),
        ("PB", "NM", ("ZO", "ZO", "PM")),
        ("PB", "PB", ("NB", "PB", "PB")),
    ],
)
def test_classic_cells(e: str, ec: str, deltas: tuple[str, str, str]) -> None:
    rb = load_rulebase("classic")
    assert rb.output_names == ("dkp", "dki", "dkd")
    assert cells(rb)[(e, ec)] == deltas


def test_immune_is_seed_004_table_1() -> None:
    rows = {  # Table 1 as printed: rows x = e, columns x' = ec, both NB NS ZE PS PB
        "NB": ("NS", "NB", "PS", "PB", "PB"),
        "NS": ("NB", "NB", "NS", "PB", "NB"),
        "ZE": ("NB", "NS", "NS", "PM", "ZE"),
        "PS": ("ZE", "PM", "ZE", "PM", "ZE"),
        "PB": ("PS", "PB", "ZE", "PB", "PB"),
    }
    levels = ("NB", "NS", "ZE", "PS", "PB")
    expected = {(e, ec): (rows[e][j],) for e in levels for j, ec in enumerate(levels)}
    rb = load_rulebase("immune")
    assert cells(rb) == expected
    assert rb.outputs[0].set_names == ("NB", "NS", "ZE", "PS", "PM", "PB")
    assert all(v.universe == (-1.0, 1.0) for v in rb.inputs + rb.outputs)


def test_description_round_trips(builtin: RuleBase) -> None:
    again = rulebase_from_dict(builtin.as_dict(), builtin.name)
    assert again == builtin
    assert set(builtin.as_dict()) == {"inputs", "outputs", "rules", "operators"}
