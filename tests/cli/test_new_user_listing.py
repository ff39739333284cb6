"""What a new user looks for before the first run (issue 10): the roads' friction curves
(`list roads --plot`) and the valid choices in `--help`."""

from __future__ import annotations

import os

import pytest


def test_list_roads_plot_draws_every_friction_road_labelled_with_units(cli, tmp_path,
                                                                       monkeypatch):
    import chassistune.plots.roads as roads_plot
    from chassistune.plants.roads import friction_roads

    seen = {}

    def keep(fig, path):
        seen["labels"] = [t.get_text() for ax in fig.axes for t in ax.get_legend().get_texts()]
        seen["axes"] = [(ax.get_xlabel(), ax.get_ylabel()) for ax in fig.axes]
        real_save(fig, path)

    real_save = roads_plot.save
    monkeypatch.setattr(roads_plot, "save", keep)
    png = tmp_path / "roads.png"
    r = cli("list", "roads", "--plot", str(png))
    assert r.code == 0, r.err
    assert png.stat().st_size > 10_000 and f"wrote {png}" in r.out
    assert [label.split(" (peak")[0] for label in seen["labels"]] == list(friction_roads())
    assert "dry-concrete (peak 0.9 at S = 0.2)" in seen["labels"]
    assert seen["axes"][0] == ("longitudinal slip S = (v - w R) / v [-]",
                               "friction coefficient mu [-]")


@pytest.mark.parametrize("args", [["list", "plants", "--plot", "x.png"],
                                  ["list", "roads", "--plot", "x.svg"],
                                  ["list", "roads", "--plot", "/proc/x.png"],
                                  ["list", "roads", "--plot", "missing/x.png"]])
def test_list_plot_refuses_before_drawing(cli, tmp_path, monkeypatch, args):
    monkeypatch.chdir(tmp_path)
    r = cli(*args)
    assert r.code == 2 and r.err.count("\n") == 1
    assert r.err.startswith("chassistune: error: --plot: ") and r.out == ""
    assert os.listdir(tmp_path) == []
