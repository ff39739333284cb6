"""The transfer study's inputs and runs (docs/transfer.md, "Re-tuning"): each source's tuned
gains from a reproduction's stores (`--from DIR`), and one re-tuning study per source study:
every source re-tuned on each cell a kernel runs, with the source's own optimizer, objective,
roads and search box, at the reproduction's budget (its `[quick]` table in the quick setting)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from chassistune.errors import InputError
from chassistune.league.score import Tuned
from chassistune.papers.common import median_run
from chassistune.papers.reproduce import shipped_config
from chassistune.reports.tables import load_study
from chassistune.studies.spec import StudyConfig, StudyPlan, plan_study, quick_config
from chassistune.studies.store import open_study
from chassistune.transfer.cells import SOURCES, Cell, Source, cells, missing


@dataclass(frozen=True)
class Setting:
    """A transfer study: its sources, the cars, the re-tuning budget (quick: the reproduction's
    `[quick]` table) and overrides of its seeds, population and evaluations."""

    sources: tuple[Source, ...]
    cars: tuple[str, ...]
    quick: bool = False
    seeds: int | None = None
    pop_size: int | None = None
    evaluations: int | None = None

    def cells(self, source: Source) -> list[Cell]:
        """The source's cells on this setting's cars."""
        return cells(source, self.cars)


def source_folder(from_dir: str | Path, study: str) -> Path:
    """The reproduction's store of `study` under DIR/studies: the full one where it exists, else
    the quick one (InputError naming the field `reproduction` when neither does)."""
    for name in (study, f"{study}-quick"):
        folder = Path(from_dir) / "studies" / name
        if (folder / "study.sqlite").is_file():
            return folder
    raise InputError(
        "reproduction",
        f"{from_dir} holds no study {study} under studies/ (make one: chassistune reproduce "
        f"{study} --quick --out {from_dir})",
    )


Tunings = dict[tuple[str, ...], Tuned]
"""A controller's gains per set of roads it was tuned on (`Source.road_sets`)."""


def tunings(folder: Path, source: Source, group: str) -> Tunings:
    """The run of each road set that the tables show: the median run by final cost of the
    source's optimizer (`papers.common.median_run`); road sets without a finished run are
    left out."""
    with open_study(folder) as store:
        data = load_study(store)
    out: Tunings = {}
    for roads in source.road_sets:
        runs = data.runs(source.run_scenario(group, roads), source.optimizer)
        if runs:
            run = median_run(runs)
            out[roads] = Tuned(
                source.plant,
                source.controller,
                run.spec.seed,
                dict(run.best_gains),
                run.wall_time_s or 0.0,
            )
    return out


def source_folders(from_dir: str | Path, setting: Setting) -> list[Path]:
    """The reproduction's store of each source study (InputError naming `reproduction` for one
    missing), before any work."""
    return [source_folder(from_dir, s) for s in dict.fromkeys(s.study for s in setting.sources)]


def source_tunings(from_dir: str | Path, source: Source) -> Tunings:
    """The paper's tunings of the source, from the reproduction's store (InputError naming
    `reproduction` where a road set has no finished run)."""
    folder = source_folder(from_dir, source.study)
    out = tunings(folder, source, source.cell)
    if len(out) < len(source.road_sets):
        raise InputError(
            "reproduction",
            f"{folder} has no finished {source.optimizer} run of every road of {source.cell}",
        )
    return out


def retune_cells(setting: Setting, source: Source) -> list[Cell]:
    """The cells a source is re-tuned on: those a kernel runs, but its home plant."""
    return [c for c in setting.cells(source) if not c.is_home and missing(c) is None]


def study_name(study: str) -> str:
    """The re-tuning study of a source study (its folder under OUT/retune/)."""
    return f"transfer-{study}"


def retune_config(setting: Setting, study: str) -> StudyConfig:
    """The re-tuning study of the sources of `study`: the shipped config (its quick version in
    the quick setting) with a scenario per cell and the sources' optimizer only."""
    base = shipped_config(study)
    if setting.quick:
        base = quick_config(base)
    mine = [s for s in setting.sources if s.study == study]
    labels = {s.optimizer for s in mine}
    section = base.study.model_copy(
        update={
            "name": study_name(base.study.name),
            "description": f"the tuned controllers of {study} re-tuned on the real cars",
            **({"seeds": tuple(range(setting.seeds))} if setting.seeds else {}),
        }
    )
    budget = base.budget.model_copy(
        update={
            k: v
            for k, v in (("pop_size", setting.pop_size), ("evaluations", setting.evaluations))
            if v
        }
        | ({"iterations": None} if setting.evaluations else {})
    )
    scenarios = [
        s.scenario.model_copy(update={"name": c.name, "preset": c.target, "params": c.params()})
        for s in mine
        for c in retune_cells(setting, s)
    ]
    return base.model_copy(
        update={
            "study": section,
            "scenarios": scenarios,
            "optimizers": [o for o in base.optimizers if (o.label or o.name) in labels],
            "budget": budget,
            "quick": None,
        }
    )


OPTIONS = {"budget.pop_size": "pop_size", "budget.evaluations": "max_evals"}
"""The override behind a budget field (the command's `--pop` and `--evals`)."""


def plans(setting: Setting) -> dict[str, StudyPlan]:
    """The re-tuning study plan of each source study with a cell to re-tune, by study
    (InputError naming `pop_size` or `max_evals` for an override the optimizer refuses)."""
    studies = dict.fromkeys(s.study for s in setting.sources)
    out = {}
    for study in studies:
        config = retune_config(setting, study)
        if config.scenarios:
            try:
                out[study] = plan_study(config)
            except InputError as exc:
                raise InputError(OPTIONS.get(exc.field, exc.field), exc.problem) from None
    return out


def retuned(
    retune_dir: Path, plans_by_study: Mapping[str, StudyPlan], setting: Setting
) -> dict[Cell, Tunings]:
    """Each re-tuned cell's tunings, picked as the source's (`tunings`)."""
    out: dict[Cell, Tunings] = {}
    for study, plan in plans_by_study.items():
        for source in (s for s in setting.sources if s.study == study):
            for cell in retune_cells(setting, source):
                found = tunings(retune_dir / plan.config.study.name, source, cell.name)
                if found:
                    out[cell] = found
    return out


def check_sources(names: Sequence[str]) -> tuple[Source, ...]:
    """The sources named `study:cell` (all when none), InputError naming `sources` else."""
    if not names:
        return SOURCES
    by_key = {s.key: s for s in SOURCES}
    for n in names:
        if n not in by_key:
            raise InputError("sources", f"unknown source {n!r} (known: {', '.join(by_key)})")
    return tuple(by_key[n] for n in dict.fromkeys(names))
