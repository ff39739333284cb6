"""What a new user looks for before the first run: the roads' friction curves
(`list roads --plot`) and the valid choices in `--help`."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest


def test_list_roads_plot_draws_every_friction_road_labelled_with_units(cli, tmp_path, monkeypatch):
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
    assert seen["axes"][0] == (
        "longitudinal slip S = (v - w R) / v [-]",
        "friction coefficient mu [-]",
    )


@pytest.mark.parametrize(
    "args",
    [
        ["list", "plants", "--plot", "x.png"],
        ["list", "roads", "--plot", "x.svg"],
        ["list", "roads", "--plot", "/proc/x.png"],
        ["list", "roads", "--plot", "missing/x.png"],
    ],
)
def test_list_plot_refuses_before_drawing(cli, tmp_path, monkeypatch, args):
    monkeypatch.chdir(tmp_path)
    r = cli(*args)
    assert r.code == 2 and r.err.count("\n") == 1
    assert r.err.startswith("chassistune: error: --plot: ") and r.out == ""
    assert os.listdir(tmp_path) == []


HELP_PROBE = """
import sys
from chassistune.cli import main
try:
    main(["tune", "--help"])
except SystemExit as exc:
    assert exc.code == 0
print("NUMBA", "numba" in sys.modules, file=sys.stderr)
"""


@pytest.fixture
def private_cache(tmp_path, monkeypatch):
    """The choices file in a private cache folder (and none of this process cached)."""
    from chassistune.cli import choices

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    choices.choices.cache_clear()
    yield tmp_path / "cache" / "chassistune"
    choices.choices.cache_clear()


def test_help_lists_the_choices_of_the_registries(cli, private_cache):
    from chassistune.cli.choices import collect

    truth = collect()
    text = cli("tune", "--help").out
    section = text[text.index("\nChoices:\n") :]
    lines = [line.strip() for line in section.splitlines()]
    for plant, info in truth["plants"].items():
        presets = ", ".join(
            f"{p} (default)" if p == info["default_preset"] else p for p in info["presets"]
        )
        assert f"{plant}: {presets}" in " ".join(lines)  # may wrap, as the objectives
        objectives = ", ".join(
            f"{o} (default)" if o == info["default_objective"] else o for o in info["objectives"]
        )
        assert f"{plant}: {objectives}" in " ".join(lines)
        for road in info["roads"]:  # every road, never broken at its hyphens
            assert any(road in line.replace(",", " ").split() for line in lines), road
        assert ", ".join(info["controllers"]) in " ".join(lines)
    assert ", ".join(truth["optimizers"]) in " ".join(lines)  # may wrap
    assert "--road, --test-road:" in lines and "PLANT:" in lines
    assert "or FILE.csv (abs-wheel: a measured mu-slip table, columns slip and mu)" in lines
    show = cli("fuzzy", "eval", "--help").out
    for name, rb in truth["rulebases"].items():
        assert f"{name}: inputs {', '.join(rb['inputs'])}; outputs" in show
    assert "RULEBASE:" in show
    assert list(private_cache.glob("cli-choices-*.json"))  # kept for the next --help


def test_help_reads_the_stored_choices_and_imports_no_numba(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path)

    def probe() -> str:
        done = subprocess.run(
            [sys.executable, "-c", HELP_PROBE], env=env, capture_output=True, text=True, check=True
        )
        assert "Choices:" in done.stdout and "burckhardt-snow" in done.stdout
        return done.stderr.strip().splitlines()[-1]

    assert probe() == "NUMBA True"  # a new version of the sources: collected and stored
    assert probe() == "NUMBA False"  # then read from the file
    (stored,) = (tmp_path / "chassistune").glob("cli-choices-*.json")
    stored.write_text("{not json")  # a damaged file is collected again, not an error
    assert probe() == "NUMBA True"
