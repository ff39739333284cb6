"""The transfer study end to end (docs/transfer.md): read the sources' gains, run (or resume)
the re-tuning studies into OUT/retune/, score every cell, write the page."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

from chassistune._interrupt import on_interrupt
from chassistune.studies.executors import Executor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import StudyPlan
from chassistune.transfer.page import write_page
from chassistune.transfer.plan import Setting, plans, retuned, source_tunings
from chassistune.transfer.score import score_transfer

RETUNE = "retune"
"""The re-tuning studies' folder under the output folder, one store per source study."""


@dataclass(frozen=True)
class Outcome:
    """What a transfer run did: re-tuning runs planned, stored before and failed; score rows;
    the page (None when a run failed) and the wall time."""

    total: int
    skipped: int
    failed: int
    rows: int
    page: Path | None
    wall_time_s: float


def budget_text(by_study: dict[str, StudyPlan]) -> str:
    """The re-tuning budget of each study, one sentence."""
    parts = []
    for study, plan in by_study.items():
        b = plan.config.budget
        size = f"{b.evaluations} evaluations" if b.evaluations else f"{b.iterations} iterations"
        parts.append(
            f"{study} {len(plan.config.study.seeds)} seed(s), population {b.pop_size}, {size}"
        )
    return "Re-tuning budget per run: " + "; ".join(parts) + "."


def run_transfer(setting: Setting, from_dir: str | Path, out: Path, executor: Executor) -> Outcome:
    """Run the transfer study into `out` (resuming its stored re-tuning runs)."""
    start = time.perf_counter()
    paper = {s: source_tunings(from_dir, s) for s in setting.sources}
    by_study = plans(setting)
    forget = on_interrupt(
        lambda: f"the finished runs are stored in {out / RETUNE}; run the same command to resume"
    )
    total = skipped = failed = 0
    (out / RETUNE).mkdir(parents=True, exist_ok=True)
    for plan in by_study.values():
        outcome = run_study(plan, out / RETUNE / plan.config.study.name, executor)
        total, skipped, failed = (
            total + outcome.total,
            skipped + outcome.skipped,
            failed + outcome.failed,
        )
    forget()
    if failed:
        return Outcome(total, skipped, failed, 0, None, time.perf_counter() - start)
    again = retuned(out / RETUNE, by_study, setting)
    scores = score_transfer(setting, paper, again)
    tuning_s = sum(t.run_time_s for found in again.values() for t in found.values())
    page = write_page(
        out,
        setting,
        scores,
        budget_text(by_study),
        f"The re-tuning runs took {tuning_s:.0f} s together (each run's wall time, summed).",
    )
    return Outcome(total, skipped, failed, len(scores), page, time.perf_counter() - start)
