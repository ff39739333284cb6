"""`chassistune bench --plot` draws the scaling sweeps: without `--only scaling` it is refused
before anything is measured."""

from __future__ import annotations

import importlib

import pytest
from click.testing import CliRunner

from chassistune.cli import bench


def test_plot_without_the_scaling_sweeps_is_refused_before_measuring(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    real = importlib.import_module

    def measured(name: str, *args: object) -> object:
        if name.startswith("chassistune.perf."):
            raise AssertionError(f"{name} was imported to be measured")
        return real(name, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(bench.importlib, "import_module", measured)
    result = CliRunner().invoke(bench.bench_command, ["--only", "abs", "--plot", "curves.png"])
    assert result.exit_code == 2, result.output
    assert "--plot draws the scaling curves: add --only scaling" in result.output


def test_the_sweeps_figures_become_curves_and_an_image(tmp_path) -> None:
    from chassistune.perf.scaling import curves
    from chassistune.plots.bench_scaling import plot_scaling

    figures = {
        "scaling_abs_wheel_ns_per_candidate_step_pop_50": 12.0,
        "scaling_abs_wheel_ns_per_candidate_step_pop_1": 150.0,
        "scaling_quarter_car_ns_per_candidate_step_pop_10": 40.0,
        "scaling_tune_wall_s_pop_10_iter_100": 0.3,
        "scaling_tune_wall_s_pop_50_iter_500": 3.2,
        "scaling_tune_cpu_s_pop_50_iter_500": 2.8,
    }
    per_step, tuning = curves(figures)
    assert per_step["abs wheel"] == [(1, 150.0), (50, 12.0)]
    assert per_step["quarter car"] == [(10, 40.0)] and per_step["vehicle straight"] == []
    assert tuning["wall: population, 100 iterations"] == [(1000, 0.3)]
    assert tuning["wall: iterations, N = 50"] == [(25000, 3.2)]
    assert tuning["cpu: iterations, N = 50"] == [(25000, 2.8)]
    path = tmp_path / "curves.png"
    plot_scaling(per_step, tuning, str(path))
    assert path.read_bytes().startswith(b"\x89PNG")
