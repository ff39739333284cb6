"""`chassistune reproduce`: run the papers' shipped studies and write one report.

Each paper names its studies (package data `data/studies/<name>.toml`, a user can copy one and
change it); each study runs through the study machinery into OUT/studies/<study name>/ (SQLite
store: a killed reproduction resumes where it stopped, and every executor gives the same
numbers). `--quick` runs each config's `[quick]` version (study `<name>-quick`). Then every
paper builds its section from the stores and the report is written (`papers.report`).
"""

from __future__ import annotations

import time
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from types import ModuleType

from chassistune.papers import (
    deffao_vehicle_abs,
    derlsp_ao_abs,
    fuzzy_immune_abs,
    iabc_suspension,
)
from chassistune.papers.common import Context, PaperSection
from chassistune.papers.report import ReportFiles, write_report
from chassistune.reports.tables import StudyData, load_study
from chassistune.studies.executors import Executor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import StudyConfig, parse_config, plan_study, quick_config
from chassistune.studies.store import open_study

PAPERS: dict[str, ModuleType] = {
    derlsp_ao_abs.KEY: derlsp_ao_abs,
    iabc_suspension.KEY: iabc_suspension,
    deffao_vehicle_abs.KEY: deffao_vehicle_abs,
    fuzzy_immune_abs.KEY: fuzzy_immune_abs,
}
Progress = Callable[[str], None]


def shipped_config(name: str) -> StudyConfig:
    """The study config `name` shipped as package data."""
    text = resources.files("chassistune").joinpath(f"data/studies/{name}.toml").read_text(
        "utf-8")
    return parse_config(tomllib.loads(text))


def paper_keys(which: str) -> list[str]:
    """`all` or one paper key, as a list."""
    return list(PAPERS) if which == "all" else [which]


def study_names(keys: Sequence[str]) -> list[str]:
    """The studies the papers `keys` need, in order (available ones only: paper 003's vehicle
    study needs the abs-vehicle plant)."""
    return [n for k in keys for n in PAPERS[k].studies()]


@dataclass(frozen=True)
class Outcome:
    """What a reproduction did and wrote."""

    files: ReportFiles
    sections: list[PaperSection]
    wall_time_s: float


def run_studies(names: Sequence[str], quick: bool, out: Path, executor: Executor,
                progress: Progress | None = None
                ) -> tuple[dict[str, StudyData], dict[str, tuple[StudyConfig, StudyConfig]]]:
    """Run (or resume) each study into OUT/studies/; the stores' data and (full, quick) configs."""
    data: dict[str, StudyData] = {}
    configs: dict[str, tuple[StudyConfig, StudyConfig]] = {}
    plans = []
    for name in names:
        full = shipped_config(name)
        configs[name] = (full, quick_config(full))
        plans.append((name, plan_study(configs[name][1] if quick else full)))
    (out / "studies").mkdir(parents=True, exist_ok=True)
    for name, plan in plans:
        folder = out / "studies" / plan.config.study.name
        outcome = run_study(plan, folder, executor)
        if progress is not None:
            progress(f"{plan.config.study.name}: {outcome.completed} run(s) now, "
                     f"{outcome.skipped} done before, {outcome.failed} failed "
                     f"({outcome.wall_time_s:.1f} s)")
        with open_study(folder) as store:
            data[name] = load_study(store)
    return data, configs


def reproduce(which: str, quick: bool, out: str | Path, executor: Executor,
              progress: Progress | None = None) -> Outcome:
    """Run the studies of paper `which` (or `all`) and write the report into `out`."""
    t0 = time.perf_counter()
    out = Path(out)
    keys = paper_keys(which)
    data, configs = run_studies(study_names(keys), quick, out, executor, progress)
    ctx = Context(out / "figures", data, configs, quick)
    sections = [PAPERS[k].build(ctx) for k in keys]
    wall = time.perf_counter() - t0
    files = write_report(out, sections, quick, wall)
    return Outcome(files, sections, wall)
