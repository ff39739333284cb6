"""Tables of a study, as pandas DataFrames: the run export and the report's statistics.

All statistics come from `chassistune.stats` (the one statistics module). Costs are minimized:
"best" is the lowest. Key metrics are the plant's lower-is-better figures (its PlantSpec's), so
their best and worst are their minimum and maximum too.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from chassistune import stats
from chassistune._io import atomic_path
from chassistune.errors import InputError
from chassistune.scenarios.registry import plant_names, plant_spec
from chassistune.studies.store import RunRecord, Store
from chassistune.units import si_unit


def key_metrics(plant: str) -> tuple[str, ...]:
    """The plant's lower-is-better metrics summarized in the report (its PlantSpec's)."""
    return plant_spec(plant).key_metrics if plant in plant_names() else ()


SUMMARY_COLUMNS = ("n", "mean", "std", "best", "worst", "median")


@dataclass(frozen=True)
class StudyData:
    """A study's finished runs, with scenarios and optimizers in the config's order."""

    name: str
    records: tuple[RunRecord, ...]
    scenarios: tuple[str, ...]
    optimizers: tuple[str, ...]

    def runs(
        self, scenario: str, optimizer: str | None = None, completed: bool = True
    ) -> list[RunRecord]:
        """Runs of `scenario` (and `optimizer`), completed ones only by default, by seed."""
        return [
            r
            for r in self.records
            if r.spec.scenario == scenario
            and (optimizer is None or r.spec.optimizer == optimizer)
            and (r.completed or not completed)
        ]

    def costs(self, scenario: str, optimizer: str) -> np.ndarray:
        return np.array([r.best_cost for r in self.runs(scenario, optimizer)], dtype=float)

    @property
    def failed(self) -> list[RunRecord]:
        return [r for r in self.records if not r.completed]


def _ordered(preferred: Iterable[str], present: Iterable[str]) -> tuple[str, ...]:
    present = list(dict.fromkeys(present))
    first = [p for p in preferred if p in present]
    return tuple(first + sorted(set(present) - set(first)))


def load_study(store: Store) -> StudyData:
    """Read every finished run of a store."""
    meta = store.meta()
    records = tuple(store.records())
    return StudyData(
        name=meta.get("study", ""),
        records=records,
        scenarios=_ordered(
            meta.get("scenarios", "").splitlines(), (r.spec.scenario for r in records)
        ),
        optimizers=_ordered(
            meta.get("optimizers", "").splitlines(), (r.spec.optimizer for r in records)
        ),
    )


# -- the export ----------------------------------------------------------------------------------


def _metric_columns(r: RunRecord) -> dict[str, Any]:
    out: dict[str, Any] = {}
    single = len(r.spec.roads) == 1
    for road, metrics in r.metrics.items():
        for name, value in metrics.items():
            out[f"metric_{name}" if single else f"metric_{name}@{road}"] = value
    return out


_SPEC_COLUMNS = (
    "scenario",
    "plant",
    "preset",
    "road",
    "controller",
    "objective",
    "aggregate",
    "optimizer",
    "optimizer_name",
    "seed",
    "root_seed",
)
"""The first columns of the run export: attributes of each run's spec, by name."""
_RECORD_COLUMNS = ("status", "best_cost", "nfev", "nit", "wall_time_s", "error")
"""The run export's columns after _SPEC_COLUMNS: attributes of each run's record, by name."""


def runs_table(records: Sequence[RunRecord]) -> pd.DataFrame:
    """One row per run: identity, status, cost, budget spent, one column per best gain
    (`gain_<name>`), metrics (`metric_<name>`; `metric_<name>@<road>` for multi-road runs),
    the cost of the best gains on each test road (`cost@<road>`), and versions (JSON)."""
    rows = []
    for r in records:
        s = r.spec
        row: dict[str, Any] = {c: getattr(s, c) for c in _SPEC_COLUMNS}
        row.update({c: getattr(r, c) for c in _RECORD_COLUMNS})
        for name in s.bounds:
            row[f"gain_{name}"] = r.best_gains.get(name, math.nan)
        row.update({f"cost@{road}": c for road, c in r.test_costs.items()})
        row.update(_metric_columns(r))
        row["versions"] = json.dumps(r.versions, sort_keys=True)
        rows.append(row)
    df = pd.DataFrame(rows)
    for col in ("nfev", "nit"):
        if col in df:
            df[col] = df[col].astype("Int64")
    return df


def write_table(df: pd.DataFrame, path: str, fmt: str = "csv") -> None:
    """Write CSV (floats exact: repr precision) or Parquet atomically."""
    if fmt not in ("csv", "parquet"):
        raise InputError("--format", f"unknown format {fmt!r} (known: csv, parquet)")
    with atomic_path(path) as tmp:
        if fmt == "csv":
            df.to_csv(tmp, index=False)
        else:
            df.to_parquet(tmp, index=False)


# -- statistics ----------------------------------------------------------------------------------


def quantities(data: StudyData, scenario: str) -> list[str]:
    """best_cost, then the key metrics present in this scenario's runs (by road if several)."""
    runs = data.runs(scenario)
    out = ["best_cost", "nfev"]
    for r in runs[:1]:
        keys = key_metrics(r.spec.plant)
        for road in r.spec.roads:
            for k in keys:
                if k in r.metrics.get(road, {}):
                    out.append(k if len(r.spec.roads) == 1 else f"{k}@{road}")
    return out


def values(runs: Sequence[RunRecord], quantity: str) -> np.ndarray:
    if quantity == "best_cost":
        vals = [r.best_cost for r in runs]
    elif quantity == "nfev":
        vals = [r.nfev for r in runs]
    else:
        name, _, road = quantity.partition("@")
        vals = [r.metrics.get(road or r.spec.roads[0], {}).get(name) for r in runs]
    a = np.array([math.nan if v is None else float(v) for v in vals], dtype=float)
    return a[np.isfinite(a)]


def quantity_unit(runs: Sequence[RunRecord], quantity: str) -> str:
    """A quantity's SI unit with the plant's note on the metric (`PlantSpec.metric_unit`);
    empty for the cost and nfev."""
    if quantity in ("best_cost", "nfev"):
        return ""
    name = quantity.partition("@")[0]
    unit = si_unit(name)
    plant = runs[0].spec.plant if runs else ""
    return plant_spec(plant).metric_unit(name, unit) if plant in plant_names() else unit


def summary_table(data: StudyData) -> pd.DataFrame:
    """Per scenario, optimizer and quantity (final cost, key metrics): its SI unit (`unit`, empty
    for the cost and nfev), n, mean, std, best, worst, median over the completed runs; `failed`
    counts the failed runs of that cell."""
    rows = []
    for sc in data.scenarios:
        names = quantities(data, sc)
        for opt in data.optimizers:
            runs = data.runs(sc, opt)
            failed = len(data.runs(sc, opt, completed=False)) - len(runs)
            for q in names:
                v = values(runs, q)
                summ = stats.summary(v) if v.size else {c: math.nan for c in SUMMARY_COLUMNS}
                if not v.size:
                    summ["n"] = 0
                unit = quantity_unit(runs, q)
                rows.append(
                    {
                        "scenario": sc,
                        "optimizer": opt,
                        "quantity": q,
                        "unit": unit,
                        "failed": failed,
                        **{c: summ[c] for c in SUMMARY_COLUMNS},
                    }
                )
    return pd.DataFrame(
        rows, columns=["scenario", "optimizer", "quantity", "unit", "failed", *SUMMARY_COLUMNS]
    )


NFEV_TOLERANCE = 0.05
"""Optimizers whose median evaluation counts differ by more than this fraction are warned about:
their final costs were bought with unequal budgets."""


def median_nfev(data: StudyData, scenario: str, optimizer: str) -> float:
    """Median evaluations of the completed runs of one cell (NaN without any)."""
    v = values(data.runs(scenario, optimizer), "nfev")
    return float(np.median(v)) if v.size else math.nan


def budget_warnings(data: StudyData) -> list[str]:
    """One line per scenario whose optimizers spent evaluation counts more than
    NFEV_TOLERANCE apart (e.g. an `iterations` budget: ABC spends two evaluations per bee)."""
    out = []
    for sc in data.scenarios:
        n = {o: median_nfev(data, sc, o) for o in data.optimizers}
        seen = [v for v in n.values() if v == v]
        if len(seen) >= 2 and max(seen) > (1.0 + NFEV_TOLERANCE) * min(seen):
            counts = ", ".join(f"{o} {v:g}" for o, v in n.items() if v == v)
            out.append(
                f"{sc}: the optimizers spent unequal evaluations (median nfev {counts}); "
                "their costs are not a like-for-like comparison: give the study an "
                "`evaluations` budget"
            )
    return out


def check_reference(data: StudyData, reference: str | None) -> str:
    """The reference optimizer: the given label, else the config's first."""
    if reference is None:
        return data.optimizers[0]
    if reference not in data.optimizers:
        raise InputError(
            "--reference",
            f"unknown optimizer {reference!r} in this study (known: {', '.join(data.optimizers)})",
        )
    return reference


def rank_sum_table(data: StudyData, reference: str) -> pd.DataFrame:
    """Wilcoxon rank-sum of the reference against each other optimizer, per scenario.

    `sign` is read from the reference's side: "+" the reference is significantly better.
    """
    rows = []
    for sc in data.scenarios:
        ref = data.costs(sc, reference)
        for opt in data.optimizers:
            if opt == reference:
                continue
            other = data.costs(sc, opt)
            if ref.size and other.size:
                res = stats.rank_sum(ref, other)
                sign, p = res.sign, res.p_value
            else:
                sign, p = "n/a", math.nan
            rows.append(
                {
                    "scenario": sc,
                    "reference": reference,
                    "optimizer": opt,
                    "n_reference": ref.size,
                    "n": other.size,
                    "nfev_reference": median_nfev(data, sc, reference),
                    "nfev": median_nfev(data, sc, opt),
                    "p_value": p,
                    "sign": sign,
                }
            )
    return pd.DataFrame(
        rows,
        columns=[
            "scenario",
            "reference",
            "optimizer",
            "n_reference",
            "n",
            "nfev_reference",
            "nfev",
            "p_value",
            "sign",
        ],
    )


def rank_sum_counts_table(data: StudyData, reference: str) -> pd.DataFrame:
    """+/=/- counts over the scenarios, per optimizer (stats.rank_sum_counts)."""

    def by_scenario(opt: str) -> dict[str, np.ndarray]:
        return {sc: c for sc in data.scenarios if (c := data.costs(sc, opt)).size}

    ref = by_scenario(reference)
    rows = []
    for opt in data.optimizers:
        if opt != reference:
            counts = stats.rank_sum_counts(ref, by_scenario(opt))
            rows.append(
                {
                    "reference": reference,
                    "optimizer": opt,
                    **counts,
                    "nfev": _overall_nfev(data, opt),
                }
            )
    return pd.DataFrame(rows, columns=["reference", "optimizer", "+", "=", "-", "nfev"])


def _overall_nfev(data: StudyData, optimizer: str) -> float:
    """Median evaluations of an optimizer's completed runs over every scenario."""
    runs = [r for r in data.records if r.spec.optimizer == optimizer and r.completed]
    v = values(runs, "nfev")
    return float(np.median(v)) if v.size else math.nan


def score_matrix(data: StudyData) -> tuple[list[str], np.ndarray]:
    """Mean final cost (scenarios x optimizers) over the scenarios where every optimizer has a
    completed run; those scenarios."""
    kept, scores = [], []
    for sc in data.scenarios:
        means = [data.costs(sc, opt) for opt in data.optimizers]
        if all(m.size for m in means):
            kept.append(sc)
            scores.append([float(np.mean(m)) for m in means])
    return kept, np.array(scores, dtype=float).reshape(len(kept), len(data.optimizers))


def friedman_table(data: StudyData) -> tuple[pd.DataFrame, stats.Friedman | None]:
    """Friedman mean ranks (1 = best) of the optimizers across scenarios, by mean final cost."""
    kept, scores = score_matrix(data)
    if not kept:
        return pd.DataFrame(columns=["optimizer", "mean_rank", "scenarios"]), None
    res = stats.friedman(scores, data.optimizers)
    df = pd.DataFrame(
        {
            "optimizer": res.methods,
            "mean_rank": res.mean_ranks,
            "scenarios": res.n_problems,
            "nfev": [_overall_nfev(data, o) for o in res.methods],
        }
    )
    return df, res


def posthoc_table(data: StudyData, reference: str) -> pd.DataFrame:
    """Holm-corrected post-hoc tests of mean ranks against the reference (>= 2 scenarios)."""
    kept, scores = score_matrix(data)
    cols = ["reference", "optimizer", "rank_difference", "z", "p_value", "p_holm", "reject"]
    if len(kept) < 2 or len(data.optimizers) < 2:
        return pd.DataFrame(columns=cols)
    comps = stats.posthoc(scores, data.optimizers, control=reference)
    return pd.DataFrame(
        [
            {
                "reference": c.a,
                "optimizer": c.b,
                "rank_difference": c.rank_difference,
                "z": c.z,
                "p_value": c.p_value,
                "p_holm": c.p_holm,
                "reject": c.reject,
            }
            for c in comps
        ],
        columns=cols,
    )


def failures_table(data: StudyData) -> pd.DataFrame:
    """Failed runs and their errors."""
    return pd.DataFrame(
        [
            {
                "scenario": r.spec.scenario,
                "optimizer": r.spec.optimizer,
                "seed": r.spec.seed,
                "error": r.error,
            }
            for r in data.failed
        ],
        columns=["scenario", "optimizer", "seed", "error"],
    )


def best_run(data: StudyData, scenario: str) -> RunRecord | None:
    """The completed run of `scenario` with the lowest final cost (config order breaks ties)."""
    rank = {o: i for i, o in enumerate(data.optimizers)}
    runs = data.runs(scenario)
    if not runs:
        return None
    return min(runs, key=lambda r: (r.best_cost, rank[r.spec.optimizer], r.spec.seed))
