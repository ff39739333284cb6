"""The bench's targets: `perf.targets` against docs/design.md 8's table, and the verdicts."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from chassistune.perf import targets as T

DESIGN = Path(__file__).resolve().parents[2] / "docs" / "design.md"


def _table_targets() -> dict[str, str]:
    """Figure -> its target text, from the rows of design.md 8 whose target is a bound."""
    section = DESIGN.read_text().split("## 8. Targets", 1)[1].split("\n## ", 1)[0]
    out = {}
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 3 or not cells[0].startswith("`"):
            continue
        names = re.findall(r"`([a-z0-9_]+)`", cells[0])
        bounds = re.findall(r"[<>]= [0-9][0-9.,e-]*[0-9]|[<>]= [0-9]", cells[2])
        if not bounds:
            assert cells[2] == "reported", line
            continue
        if cells[2].endswith(" each"):
            bounds = bounds * len(names)
        assert len(bounds) == len(names), line
        out.update(zip(names, bounds, strict=True))
    return out


def test_every_bound_of_the_design_table_is_a_target_and_no_other() -> None:
    table = _table_targets()
    assert len(table) >= 20
    assert {name: T.TARGETS[name].text() for name in table if name in T.TARGETS} == table
    assert set(T.TARGETS) == set(table)


@pytest.mark.parametrize(
    ("name", "value", "expected"),
    [
        ("abs_sims_per_s", 21_600.0, "(target >= 20,000: met)"),
        ("abs_sims_per_s", 10_580.0, "(target >= 20,000: NOT met)"),
        ("abs_sims_per_s", 20_000.0, "(target >= 20,000: met)"),
        ("abs_max_rel_err", 6.7e-4, "(target <= 1e-3: met)"),
        ("abs_max_rel_err", 2.7e-2, "(target <= 1e-3: NOT met)"),
        ("abs_ecu_ratio_to_ideal_cpu", 0.37, "(target >= 0.5: NOT met)"),
        ("tune_abs_wall_s", math.nan, "(target <= 2: NOT met)"),
        ("abs_mpc_sims_per_s", 6_368.0, ""),
    ],
)
def test_verdicts(name: str, value: float, expected: str) -> None:
    assert T.verdict(name, value) == expected


def test_bench_prints_each_figure_with_its_verdict(monkeypatch: pytest.MonkeyPatch) -> None:
    from chassistune.cli.main import cli
    from chassistune.perf import ecu

    figures = {"abs_ecu_ratio_to_ideal_cpu": 0.37, "abs_ecu_sims_per_s": 3_400.0}
    monkeypatch.setattr(ecu, "figures", lambda quick: figures)
    result = CliRunner().invoke(cli, ["bench", "--only", "ecu"])
    assert result.exit_code == 0, result.output
    lines = [line for line in result.output.splitlines() if line.startswith("abs_ecu")]
    assert lines[0] == "abs_ecu_ratio_to_ideal_cpu           0.37       (target >= 0.5: NOT met)"
    assert lines[1].split() == ["abs_ecu_sims_per_s", "3400"]
