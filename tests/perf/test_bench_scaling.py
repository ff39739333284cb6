"""`chassistune bench --plot` draws the scaling sweeps: with `--only` areas that leave them out it
is refused before anything is measured. The sweep measures every model at every population and
the tuning run at every population and iteration count asked for (shortened here; no speed is
asserted)."""

from __future__ import annotations

import importlib
import math

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


def test_the_sweep_measures_every_model_and_tuning_run(monkeypatch: pytest.MonkeyPatch) -> None:
    from chassistune.perf import scaling

    monkeypatch.setattr(scaling, "POPULATIONS", (1, 3))
    monkeypatch.setattr(scaling, "TUNE_POPULATIONS", (10,))
    monkeypatch.setattr(scaling, "TUNE_ITERATIONS", (2, 4))
    figures = scaling.figures()
    assert all(math.isfinite(v) and v > 0.0 for v in figures.values())
    per_step, tuning = scaling.curves(figures)
    assert set(per_step) == {model.replace("_", " ") for model in scaling.MODELS}
    assert {"vehicle split mu", "vehicle split mu driver"} <= set(per_step)
    assert all([n for n, _ in pts] == [1, 3] for pts in per_step.values())
    assert len(figures) == 2 * len(scaling.MODELS) + 2 * 3  # runs 10 x 100, 50 x 2, 50 x 4
    assert [n for n, _ in tuning["wall: iterations, N = 50"]] == [100, 200]
    assert [n for n, _ in tuning["cpu: population, 100 iterations"]] == [1000]
