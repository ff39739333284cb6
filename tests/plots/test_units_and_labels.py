"""What a figure shows a new user: the quarter car's travel and tire deflection in mm
with units in its table, and no fuzzy-surface label cut by its axes."""

from __future__ import annotations

from itertools import pairwise

import pytest

from chassistune.units import shown_unit, si_unit


def _capture(monkeypatch, module):
    """Keep the figure a plot function saves (its texts and axes, before it is closed)."""
    seen = {}
    real = module.save

    def keep(fig, path):
        fig.canvas.draw()
        seen["fig"] = fig
        seen["labels"] = [ax.get_ylabel() for ax in fig.axes]
        seen["cells"] = [
            c.get_text().get_text()
            for ax in fig.axes
            for tab in ax.tables
            for c in tab.get_celld().values()
        ]
        real(fig, path)

    monkeypatch.setattr(module, "save", keep)
    return seen


def test_the_quarter_car_figure_shows_mm_and_units(monkeypatch, tmp_path):
    import chassistune.plots.quarter_car as qc
    from chassistune.simulate import simulate

    seen = _capture(monkeypatch, qc)
    result = simulate("quarter-car", controller="skyhook")
    result.plot(str(tmp_path / "qc.png"))
    assert {"suspension travel [mm]", "tire deflection [mm]", "body acceleration [m/s^2]"} <= set(
        seen["labels"]
    )
    cells = seen["cells"]
    assert {
        "travel RMS [mm]",
        "tire defl. RMS [mm]",
        "body acc. RMS [m/s^2]",
        "force RMS [N]",
    } <= set(cells)
    travel_mm = result.metrics["susp_travel_rms"] * 1e3
    assert f"{travel_mm:.4g}" in cells  # the value in mm, not m
    assert f"{result.metrics['susp_travel_rms']:.4g}" not in cells


def test_simulate_text_states_units_and_keeps_the_json_si(cli):
    import json

    doc = json.loads(cli("simulate", "quarter-car", "--json").out)
    assert 0.0005 < doc["metrics"]["susp_travel_rms"] < 0.05  # metres in the JSON (design.md 7)
    text = cli("simulate", "quarter-car").out
    row = next(line.split() for line in text.splitlines() if "susp_travel_rms" in line)
    assert row[:2] == ["susp_travel_rms", "[mm]"]
    assert float(row[2]) == pytest.approx(doc["metrics"]["susp_travel_rms"] * 1e3, rel=1e-3)
    assert any(line.split()[:2] == ["body_acc_rms", "[m/s^2]"] for line in text.splitlines())
    abs_text = cli("simulate", "abs-wheel").out
    assert any(line.split()[:2] == ["stop_distance_m", "[m]"] for line in abs_text.splitlines())


@pytest.mark.parametrize(
    ("name", "si", "shown"),
    [
        ("body_acc_rms", "m/s^2", ("m/s^2", 1.0)),
        ("passive_tire_defl_rms", "m", ("mm", 1e3)),
        ("travel_3sigma_m", "m", ("m", 1.0)),
        ("brake_torque_n_m", "N m", ("N m", 1.0)),
        ("vehicle_speed_m_s", "m/s", ("m/s", 1.0)),
        ("slip_itae", "s^2", ("s^2", 1.0)),
        ("stopped", "-", ("-", 1.0)),
    ],
)
def test_metric_units(name, si, shown):
    assert si_unit(name) == si and shown_unit(name) == shown


@pytest.mark.parametrize("name", ["deffao", "immune", "classic"])
def test_no_fuzzy_label_is_cut_by_its_axes(tmp_path, monkeypatch, name):
    import chassistune.plots.fuzzy as fz
    from chassistune.fuzzy.loader import load_rulebase

    figures = []
    real = fz._drop_clipped

    def keep(fig):
        real(fig)
        figures.append(fig)

    monkeypatch.setattr(fz, "_drop_clipped", keep)
    fz.plot_rulebase(load_rulebase(name), tmp_path / "rb.png")
    (fig,) = figures
    renderer = fig.canvas.get_renderer()
    labels = 0
    for ax in fig.axes:
        box = ax.bbox
        for t in ax.texts:
            if t.get_clip_on():
                ext = t.get_window_extent(renderer)
                labels += 1
                assert box.x0 <= ext.x0 and ext.x1 <= box.x1, t.get_text()
                assert box.y0 <= ext.y0 and ext.y1 <= box.y1, t.get_text()
        ticks = [t.get_window_extent(renderer) for t in ax.get_xticklabels() if t.get_text()]
        assert all(a.x1 < b.x0 for a, b in pairwise(ticks)), "tick labels overlap"
    assert labels > 10  # the contour labels are still there
