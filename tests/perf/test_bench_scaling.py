"""`chassistune bench --plot` draws the scaling sweeps: without `--only scaling` it is refused
before anything is measured."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from chassistune.cli import bench


def test_plot_without_the_scaling_sweeps_is_refused_before_measuring(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    def measured(name: str) -> None:
        raise AssertionError(f"{name} was imported to be measured")

    monkeypatch.setattr(bench.importlib, "import_module", measured)
    result = CliRunner().invoke(bench.bench_command, ["--only", "abs", "--plot", "curves.png"])
    assert result.exit_code == 2, result.output
    assert "--plot draws the scaling curves: add --only scaling" in result.output
