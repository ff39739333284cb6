"""Tuned on road X, tested on road Y: the cost of each run's best gains on every test road of its
scenario (stored by the run), beside the plant's generalization metrics (stop distance over its
bound and locked time for the ABS), re-simulated here from the stored gains and scenario seed;
and robust versus nominal tuning: training and validation figures of the runs with an
`[uncertainty]` table."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd

from chassistune.reports.plant_view import plant_view
from chassistune.reports.tables import StudyData
from chassistune.studies.store import RunRecord

COLUMNS = ["group", "optimizer", "tuned_on", "tested_on", "n", "median_cost", "mean_cost"]


def _test_metrics(run: RunRecord, road: str, names: list[str]) -> dict[str, float]:
    """The named metrics of the run's best gains on `road` (same preset, params and seed)."""
    from chassistune.scenarios.registry import get_plant

    s = run.spec
    sc = get_plant(s.plant).scenario(s.preset, road, s.controller, s.params, s.scenario_seed)
    gains = np.array([[run.best_gains[g] for g in sc.gain_names]], dtype=float)
    m = sc.metrics(gains)
    return {k: float(m[k][0]) for k in names}


def _median(v: list[float]) -> float:
    a = np.asarray(v, dtype=float)
    a = a[np.isfinite(a)]
    return float(np.median(a)) if a.size else math.nan


def generalization_table(data: StudyData) -> pd.DataFrame:
    """One row per (group, optimizer, tuned on, tested on) for scenario groups with two or more
    test roads: n, median and mean cost over seeds, and `median_<metric>` per generalization
    metric of the plant."""
    rows = []
    rank = {sc: i for i, sc in enumerate(data.scenarios)}
    records = sorted(data.records, key=lambda r: rank[r.spec.scenario])  # config order
    groups = dict.fromkeys(r.spec.group for r in records if len(r.spec.test_roads) > 1)
    metric_names: list[str] = []
    for group in groups:
        runs = [r for r in records if r.spec.group == group and r.completed]
        names = (
            [m for m, _ in plant_view(runs[0].spec.plant).generalization_metrics] if runs else []
        )
        metric_names += [m for m in names if m not in metric_names]
        for opt in data.optimizers:
            mine = [r for r in runs if r.spec.optimizer == opt]
            for tuned in dict.fromkeys(r.spec.road for r in mine):
                cell = [r for r in mine if r.spec.road == tuned]
                for road in cell[0].spec.test_roads:
                    v = np.array([r.test_costs.get(road, math.nan) for r in cell], dtype=float)
                    v = v[np.isfinite(v)]
                    tested = [_test_metrics(r, road, names) for r in cell]
                    rows.append(
                        {
                            "group": group,
                            "optimizer": opt,
                            "tuned_on": tuned,
                            "tested_on": road,
                            "n": v.size,
                            "median_cost": float(np.median(v)) if v.size else math.nan,
                            "mean_cost": float(np.mean(v)) if v.size else math.nan,
                            **{f"median_{k}": _median([t[k] for t in tested]) for k in names},
                        }
                    )
    return pd.DataFrame(rows, columns=[*COLUMNS, *(f"median_{k}" for k in metric_names)])


def matrix(cell: pd.DataFrame, labels: list[tuple[str, str]]) -> pd.DataFrame:
    """One (group, optimizer)'s rows as a wide table: a row per road tuned on and, per road
    tested on, one column per (column, label) of `labels` (two-level columns: road, label)."""
    tuned = list(dict.fromkeys(cell["tuned_on"]))
    columns: dict[tuple[str, str], object] = {("", "tuned on"): tuned}
    for road in dict.fromkeys(cell["tested_on"]):
        part = cell[cell["tested_on"] == road].set_index("tuned_on").reindex(tuned)
        for col, label in labels:
            columns[(f"tested on {road}", label)] = part[col].to_numpy()
    out = pd.DataFrame(columns)
    out.columns = pd.MultiIndex.from_tuples(list(columns))
    return out


ROBUST_COLUMNS = [
    "group",
    "optimizer",
    "tuned_on",
    "tuning",
    "n",
    "training_worst_cost",
    "validation_draws",
    "validation_failures",
    "pass_rate",
    "validation_worst",
    "validation_mean",
    "certificate",
]


def _arm(robust: dict[str, Any]) -> str:
    """'nominal' (K = 0: tuned on the nominal plant, validated on the uncertainty) or
    'robust K=16 max'."""
    u = robust["uncertainty"]
    return "nominal" if u["scenarios"] == 0 else f"robust K={u['scenarios']} {u['aggregate']}"


def robustness_table(data: StudyData) -> pd.DataFrame:
    """Robust versus nominal: one row per (group, optimizer, tuned on, tuning arm) of
    the runs with an `[uncertainty]` table: medians over seeds of the winner's worst training
    cost and of its worst and mean validation figure (the distance ratio when the plant has one,
    else the cost), the validation draws and failures summed over seeds, and the certificate
    (failure probability <= eps at confidence 1 - beta) when no draw of any seed failed."""
    rows = []
    runs = [r for r in data.records if r.completed and r.robust is not None]
    keys = dict.fromkeys(
        (r.spec.group, r.spec.optimizer, r.spec.road, _arm(r.robust))
        for r in runs
        if r.robust is not None
    )
    for group, opt, road, arm in keys:
        cell = [
            r.robust
            for r in runs
            if r.robust is not None
            and _arm(r.robust) == arm
            and (r.spec.group, r.spec.optimizer, r.spec.road) == (group, opt, road)
        ]
        vals = [c["validation"] for c in cell if c["validation"] is not None]
        kind = "distance_ratio" if vals and "worst_distance_ratio" in vals[0] else "cost"
        n_draws = sum(v["n"] for v in vals)
        fails = sum(v["failures"] for v in vals)
        certs = [v["certificate"] for v in vals]
        cert = (
            f"p_fail <= {max(c['eps'] for c in certs):.3%} at {1 - certs[0]['beta']:.0%}"
            if certs and all(certs)
            else ""
        )
        rows.append(
            {
                "group": group,
                "optimizer": opt,
                "tuned_on": road,
                "tuning": arm,
                "n": len(cell),
                "training_worst_cost": _median([max(c["training"]["costs"]) for c in cell]),
                "validation_draws": n_draws,
                "validation_failures": fails,
                "pass_rate": 1.0 - fails / n_draws if n_draws else math.nan,
                "validation_worst": _median([v[f"worst_{kind}"] for v in vals]),
                "validation_mean": _median([v[f"mean_{kind}"] for v in vals]),
                "certificate": cert,
            }
        )
    return pd.DataFrame(rows, columns=ROBUST_COLUMNS)
