"""The tuned parameter sets behind a paper's tables and figures: per study cell, the catalogue
defaults and each optimizer's median run (the run the tables and figures show), every parameter
with its search box; one table per controller (PID gains, fuzzy PID factors, fuzzy immune PID
parameters)."""

from __future__ import annotations

from collections.abc import Sequence

import pandas as pd

from chassistune.papers.common import Table, median_run
from chassistune.reports.gains import bound_flag
from chassistune.reports.tables import StudyData
from chassistune.scenarios.registry import get_plant
from chassistune.studies.spec import RunSpec

KIND = {
    "pid": "PID gains",
    "fuzzy-pid": "fuzzy PID factors",
    "fuzzy-immune-pid": "fuzzy immune PID parameters",
}
"""What a controller's tuned parameters are called in a table's title."""


def default_parameters(spec: RunSpec) -> dict[str, float]:
    """The catalogue defaults of the run's controller on its preset (the untuned rows)."""
    sc = get_plant(spec.plant).scenario(spec.preset, spec.roads[0], spec.controller, spec.params)
    return dict(zip(sc.gain_names, sc.gains_array(None).tolist(), strict=True))


def tuned_tables(key: str, data: StudyData, cells: Sequence[str] | None = None) -> list[Table]:
    """One table per controller over `cells` (default: every cell of the study)."""
    by_controller: dict[str, list[dict[str, object]]] = {}
    for cell in cells or data.scenarios:
        runs = data.runs(cell)
        if not runs:
            continue
        spec = runs[0].spec
        rows = by_controller.setdefault(spec.controller, [])
        rows.append(_row(cell, "defaults (untuned)", None, None, default_parameters(spec), spec))
        for opt in data.optimizers:
            mine = data.runs(cell, opt)
            if mine:
                rec = median_run(mine)
                rows.append(_row(cell, opt, rec.spec.seed, rec.best_cost, rec.best_gains, rec.spec))
    frames = {c: pd.DataFrame(rows).astype({"seed": "Int64"}) for c, rows in by_controller.items()}
    return [
        Table(
            f"tuned_{controller}",
            f"Tuned {KIND.get(controller, controller + ' parameters')} ({data.name}): the runs "
            "shown",
            frame,
            "Per cell: the catalogue defaults and each optimizer's median run by final cost "
            "(the run the tables and figures of this section draw); 'seed': its seed index; "
            "'near a bound': parameters within 1 % of their search box's edge. The defaults are "
            "not tuned, so they have no seed and no cost.",
            missing={"seed": "untuned", "final cost": "untuned"},
        )
        for controller, frame in frames.items()
    ]


def _row(
    cell: str,
    label: str,
    seed: int | None,
    cost: float | None,
    values: dict[str, float],
    spec: RunSpec,
) -> dict[str, object]:
    box = spec.bounds
    near = [f"{n} {bound_flag(values[n], *box[n])}" for n in box if bound_flag(values[n], *box[n])]
    return {
        "cell": cell,
        "run": label,
        "seed": seed,
        "objective": spec.objective,
        "final cost": cost,
        **{n: values[n] for n in box},
        "search box": ", ".join(f"{n} [{lo:g}, {hi:g}]" for n, (lo, hi) in box.items()),
        "near a bound": ", ".join(near) or "none",
    }
