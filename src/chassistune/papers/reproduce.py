"""`chassistune reproduce`: run the papers' shipped studies and write one report.

Each paper names its studies (package data `data/studies/<name>.toml`, a user can copy one and
change it); each study runs through the study machinery into OUT/studies/<study name>/ (SQLite
store: a killed reproduction resumes where it stopped, and every executor gives the same
numbers). `--quick` runs each config's `[quick]` version (study `<name>-quick`). Then every
paper builds its section from the stores and the report is written (`papers.report`; with
`--interactive` also the plotly page).
"""

from __future__ import annotations

import time
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from types import ModuleType

from chassistune.papers import (
    deffao_vehicle_abs,
    derlsp_ao_abs,
    fuzzy_immune_abs,
    iabc_suspension,
    standard,
)
from chassistune.papers.common import Context, PaperSection
from chassistune.papers.report import (
    ReportFiles,
    timing_text,
    write_interactive,
    write_report,
)
from chassistune.papers.supplement import supplement
from chassistune.reports.tables import StudyData, load_study
from chassistune.studies.executors import Executor
from chassistune.studies.progress import with_progress
from chassistune.studies.runner import StudyOutcome, check_out_dir, pending_runs, run_study
from chassistune.studies.spec import (
    StudyConfig,
    StudyPlan,
    parse_config,
    plan_study,
    quick_config,
)
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
    text = resources.files("chassistune").joinpath(f"data/studies/{name}.toml").read_text("utf-8")
    return parse_config(tomllib.loads(text))


def paper_keys(which: str) -> list[str]:
    """`all` or one paper key, as a list."""
    return list(PAPERS) if which == "all" else [which]


def study_names(keys: Sequence[str]) -> list[str]:
    """The studies the papers `keys` need, in order (available ones only: the vehicle study of
    deffao-vehicle-abs needs the abs-vehicle plant)."""
    return [n for k in keys for n in PAPERS[k].studies()]


@dataclass(frozen=True)
class Outcome:
    """What a reproduction did and wrote."""

    files: ReportFiles
    sections: list[PaperSection]
    wall_time_s: float


@dataclass(frozen=True)
class StudyRun:
    """One study of a reproduction: its name, (full, quick) configs and the plan to run."""

    name: str
    configs: tuple[StudyConfig, StudyConfig]
    plan: StudyPlan

    def folder(self, out: Path) -> Path:
        return out / "studies" / self.plan.config.study.name


def plan_reproduction(which: str, quick: bool) -> list[StudyRun]:
    """The studies of paper `which` (or `all`), validated and planned."""
    runs = []
    for name in study_names(paper_keys(which)):
        full = shipped_config(name)
        configs = (full, quick_config(full))
        runs.append(StudyRun(name, configs, plan_study(configs[1] if quick else full)))
    return runs


def check_reproduction(which: str, quick: bool, out: str | Path) -> list[StudyRun]:
    """Refuse, before anything is written, an output folder that cannot take the reproduction
    (not a folder, or holding runs of other configs); the planned studies."""
    out = Path(out)
    check_out_dir(out)
    runs = plan_reproduction(which, quick)
    for r in runs:
        if r.folder(out).exists():
            check_out_dir(r.folder(out))
            pending_runs(r.plan, r.folder(out))
    return runs


def run_studies(
    runs: Sequence[StudyRun], out: Path, executor: Executor, progress: Progress | None = None
) -> dict[str, StudyData]:
    """Run (or resume) each study into OUT/studies/; the stores' data by study name. With
    `progress`: a line per finished study, and the runs done so far every 30 s (off a terminal;
    a bar on one)."""
    data: dict[str, StudyData] = {}
    (out / "studies").mkdir(parents=True, exist_ok=True)
    for r in runs:
        if progress is None:
            outcome = run_study(r.plan, r.folder(out), executor)
        else:
            outcome = _run_with_progress(r.plan, r.folder(out), executor, progress)
            progress(
                f"{r.plan.config.study.name}: {outcome.completed} run(s) now, "
                f"{outcome.skipped} done before, {outcome.failed} failed "
                f"({outcome.wall_time_s:.1f} s)"
            )
        with open_study(r.folder(out)) as store:
            data[r.name] = load_study(store)
    return data


def _run_with_progress(
    plan: StudyPlan, folder: Path, executor: Executor, say: Progress
) -> StudyOutcome:
    return with_progress(
        lambda bar: run_study(plan, folder, executor, progress=bar, notice=say),
        plan.config.study.name,
        say,
    )


def reproduce(
    which: str,
    quick: bool,
    out: str | Path,
    executor: Executor,
    progress: Progress | None = None,
    interactive: bool = False,
) -> Outcome:
    """Run the studies of paper `which` (or `all`) and write the report into `out` (and, with
    `interactive`, report_interactive.html beside it)."""
    t0 = time.perf_counter()
    out = Path(out)
    runs = check_reproduction(which, quick, out)
    data = run_studies(runs, out, executor, progress)
    ctx = Context(out / "figures", data, {r.name: r.configs for r in runs}, quick)
    keys = paper_keys(which)
    sections = [supplement(PAPERS[k].build(ctx), ctx) for k in keys]
    if any(k in standard.PROPOSED for k in keys):
        sections.append(standard.build(papers=keys))
    wall = time.perf_counter() - t0
    timing = timing_text(wall, data)
    files = write_report(out, sections, quick, timing)
    if interactive:
        by_paper = {k: [(n, data[n]) for n in PAPERS[k].studies() if n in data] for k in keys}
        files = replace(
            files, interactive=write_interactive(out, sections, by_paper, quick, timing)
        )
    return Outcome(files, sections, wall)
