"""What one study run yields: its status word and the typed result the worker returns and the
store writes (one transaction per run)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from typing import Any


class RunStatus(StrEnum):
    """The status of a finished run: the only words the store's `status` column holds."""

    COMPLETED = "completed"
    FAILED = "failed"


@dataclass(frozen=True)
class RunResult:
    """One finished run, as the worker returns it (JSON-ready values: see `_io.jsonable`).

    A failed run carries its error text and no numbers; a completed one no error.
    """

    key: str
    spec_hash: str
    status: RunStatus
    wall_time_s: float
    versions: dict[str, str]
    error: str | None = None
    best_cost: float | None = None
    nfev: int | None = None
    nit: int | None = None
    best_gains: dict[str, float] | None = None
    metrics: dict[str, dict[str, Any]] | None = None
    test_costs: dict[str, float] | None = None
    history: list[float] | None = None
    history_nfev: list[int] | None = None
    diagnostics: dict[str, Any] | None = None  # what the optimizer reports (IABC's scouts)
    robust: dict[str, Any] | None = None
    """Robust runs: `uncertainty`, `training` (the winner's cost on each training scenario) and
    `validation` (`tuning.robust.run.summary_fields`)."""
    step_check: dict[str, Any] | None = None
    """The winner at a quarter of the step, by road (`scenarios.refine.StepCheck.as_dict`)."""

    @property
    def completed(self) -> bool:
        return self.status is RunStatus.COMPLETED
