"""One small study shared by the report tests (session scope), both of its report pages, and
the system chromium for pytest-playwright (no browser download: `executable_path`)."""

from __future__ import annotations

import json
import shutil
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from chassistune.reports.tables import StudyData, load_study
from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import parse_config, plan_study
from chassistune.studies.store import open_study

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "studies" / "abs-roads.toml"
SEEDS = 4  # four runs a side: the smallest sample where a rank-sum can be significant
BUDGET = {"pop_size": 6, "iterations": 4}

CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
SHOTS = pytest.StashKey[list[tuple[str, Path, tuple[int, int]]]]()
"""(page, PNG path, (width, height)) of every screenshot taken, listed after the tests."""


@dataclass(frozen=True)
class Reported:
    """The shared study: its folder, runs, config, and both pages."""

    dir: Path
    data: StudyData
    config: dict[str, Any]
    static: Path
    interactive: Path


@pytest.fixture(scope="session")
def reported(tmp_path_factory: pytest.TempPathFactory) -> Reported:
    """examples/studies/abs-roads.toml on a small budget, reported with `--interactive`."""
    from chassistune.cli.main import main

    config = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    config["study"]["seeds"] = SEEDS
    config["budget"] = BUDGET
    out = tmp_path_factory.mktemp("abs-roads") / "study"
    run_study(plan_study(parse_config(config)), out, SerialExecutor())
    with pytest.raises(SystemExit) as exc:
        main(["study", "report", str(out), "--interactive"])
    assert exc.value.code == 0
    with open_study(out) as store:
        data = load_study(store)
        stored = json.loads(store.meta()["config"])
    return Reported(out, data, stored, out / "report.html", out / "report_interactive.html")


@pytest.fixture(scope="session")
def browser_type_launch_args(browser_type_launch_args: dict[str, Any]) -> dict[str, Any]:
    """pytest-playwright launches Debian's chromium; skipped (one line) where it is missing."""
    exe = next((shutil.which(b) for b in ("chromium", "chromium-browser") if shutil.which(b)), None)
    if exe is None:
        pytest.skip("no chromium on this machine (.ci/run installs it with apt-get where it can)")
    return {**browser_type_launch_args, "executable_path": exe, "args": CHROMIUM_FLAGS}


@pytest.fixture(scope="session")
def screenshot(
    tmp_path_factory: pytest.TempPathFactory, pytestconfig: pytest.Config
) -> Callable[[Any, str], np.ndarray]:
    """Takes a full-page PNG of a playwright page, lists it for the summary, returns its grey
    levels (rows x columns)."""
    folder = tmp_path_factory.mktemp("screenshots")
    shots = pytestconfig.stash.setdefault(SHOTS, [])

    def take(page: Any, name: str) -> np.ndarray:
        from PIL import Image

        path = folder / f"{name}.png"
        # a page of 100,000+ px takes 15-21 s to capture on 2 idle cores: playwright's default
        # 30 s is too short on a loaded machine
        page.screenshot(path=str(path), full_page=True, timeout=180_000)
        # our own screenshot, not an untrusted file: PIL's decompression-bomb guard (about 179
        # million pixels) would refuse a full page taller than about 140,000 px at 1280 px wide
        Image.MAX_IMAGE_PIXELS = None
        with Image.open(path) as img:
            shots.append((name, path, img.size))
            return np.asarray(img.convert("L"), dtype=float)

    return take


def pytest_terminal_summary(terminalreporter: Any, config: pytest.Config) -> None:
    shots = config.stash.get(SHOTS, [])
    if shots:
        terminalreporter.section("report screenshots (headless chromium)")
        for page, path, (w, h) in shots:
            terminalreporter.write_line(
                f"{page}: {path} ({w} x {h} px, {path.stat().st_size // 1024} KiB)"
            )
