"""The setup of a study, as tables for the report: what was tuned (plant, preset, roads and every
parameter value, gain bounds, objective), by what (optimizer hyperparameters with defaults
filled in, budgets and the evaluations actually spent), with which seeds, when, and with which
versions; and the config itself as TOML."""

from __future__ import annotations

import datetime as dt
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from chassistune.reports.tables import StudyData
from chassistune.reports.toml_text import to_toml
from chassistune.studies.spec import RunSpec

_TOP_ORDER = ("study", "scenarios", "optimizers", "budget")
_FIRST_KEYS = ("name", "label", "plant", "preset", "controller", "objective", "roads")


def _first(d: Mapping[str, Any]) -> dict[str, Any]:
    keys = [k for k in _FIRST_KEYS if k in d] + [k for k in d if k not in _FIRST_KEYS]
    return {k: d[k] for k in keys}


def config_toml(config: Mapping[str, Any]) -> str:
    """The validated config as TOML, sections in reading order ([study] first)."""
    ordered: dict[str, Any] = {}
    for k in [*[k for k in _TOP_ORDER if k in config], *[k for k in config if k not in _TOP_ORDER]]:
        v = config[k]
        ordered[k] = (
            _first(v)
            if isinstance(v, Mapping)
            else [_first(x) for x in v]
            if isinstance(v, list)
            else v
        )
    return to_toml(ordered)


def _utc(seconds: float) -> str:
    return dt.datetime.fromtimestamp(seconds, dt.UTC).strftime("%Y-%m-%d %H:%M UTC")


def _span(seeds: list[int]) -> str:
    if seeds and seeds == list(range(seeds[0], seeds[0] + len(seeds))):
        return f"{seeds[0]}..{seeds[-1]}" if len(seeds) > 1 else str(seeds[0])
    return ", ".join(map(str, seeds))


REPORT_PACKAGES = ("chassistune", "numpy", "scipy", "pandas", "matplotlib", "jinja2", "plotly")


def report_versions() -> str:
    """Python and the versions of the packages that make the report (those installed)."""
    import platform
    from importlib.metadata import PackageNotFoundError, version

    out = [f"python {platform.python_version()}"]
    for pkg in REPORT_PACKAGES:
        try:
            out.append(f"{pkg} {version(pkg)}")
        except PackageNotFoundError:
            continue
    return ", ".join(out)


def study_table(data: StudyData, config: Mapping[str, Any], store_file: Path) -> pd.DataFrame:
    """Runs, seeds, dates and versions."""
    study = config.get("study", {})
    n_ok = sum(r.completed for r in data.records)
    written = [p.stat().st_mtime for p in (store_file, Path(f"{store_file}-wal")) if p.exists()]
    versions: dict[str, set[str]] = {}
    for r in data.records:
        for k, v in r.versions.items():
            versions.setdefault(k, set()).add(v)
    rows = [
        ("study", data.name),
        ("runs", f"{len(data.records)} finished: {n_ok} completed, {len(data.failed)} failed"),
        (
            "seeds",
            f"indices {_span(list(study.get('seeds', [])))} (root seed "
            f"{study.get('seed', 0)}; run i draws from SeedSequence(root, spawn_key=(i,)))",
        ),
        ("study store last written", _utc(max(written)) if written else "unknown"),
        ("report written", _utc(dt.datetime.now(dt.UTC).timestamp())),
        (
            "versions of the runs",
            ", ".join(f"{k} {' / '.join(sorted(v))}" for k, v in sorted(versions.items())),
        ),
        ("report made with", report_versions()),
    ]
    return pd.DataFrame(rows, columns=["item", "value"])


def optimizer_table(data: StudyData) -> pd.DataFrame:
    """Per optimizer: algorithm, every hyperparameter (defaults filled in), budget asked and the
    evaluations and iterations actually spent (min, median, max over its completed runs)."""
    from chassistune.optimizers.peers import PEERS
    from chassistune.optimizers.registry import hyperparameters

    rows = []
    for opt in data.optimizers:
        runs = [r for r in data.records if r.spec.optimizer == opt]
        spec = runs[0].spec
        if spec.optimizer_name in PEERS:
            hyper_text = "the peer's settings (chassistune.optimizers.peers)"
        else:
            hyper = hyperparameters(spec.optimizer_name, **spec.hyperparameters).as_dict()
            hyper_text = ", ".join(f"{k} = {v}" for k, v in hyper.items()) or "none"
        done = [r for r in runs if r.completed]
        rows.append(
            {
                "optimizer": opt,
                "algorithm": spec.optimizer_name,
                "hyperparameters": hyper_text,
                "population": spec.pop_size,
                "iterations asked": spec.max_iter if spec.max_iter is not None else "",
                "evaluations asked": spec.max_evals if spec.max_evals is not None else "",
                "evaluations spent": _range([r.nfev for r in done]),
                "iterations done": _range([r.nit for r in done]),
            }
        )
    return pd.DataFrame(rows)


def _range(values: list[int | None]) -> str:
    v = [x for x in values if x is not None]
    if not v:
        return ""
    lo, mid, hi = min(v), float(np.median(v)), max(v)
    return f"{lo}" if lo == hi else f"{lo} / {mid:g} / {hi} (min / median / max)"


def scenario_specs(data: StudyData) -> dict[str, RunSpec]:
    """One run spec per config scenario (group), in config order."""
    out: dict[str, RunSpec] = {}
    for sc in data.scenarios:
        runs = data.runs(sc, completed=False)
        if runs and runs[0].spec.group not in out:
            out[runs[0].spec.group] = runs[0].spec
    return out


def scenario_table(data: StudyData, group: str) -> pd.DataFrame:
    """What a config scenario tunes: plant, preset, controller, objective, roads, bounds."""
    cells = [
        sc
        for sc in data.scenarios
        if (runs := data.runs(sc, completed=False)) and runs[0].spec.group == group
    ]
    spec = data.runs(cells[0], completed=False)[0].spec
    bounds = ", ".join(f"{g} in [{lo:g}, {hi:g}]" for g, (lo, hi) in spec.bounds.items())
    rows = [
        ("plant", spec.plant),
        ("preset", spec.preset),
        ("controller", spec.controller),
        ("objective", spec.objective),
        (
            "tuned on",
            "; ".join(", ".join(data.runs(c, completed=False)[0].spec.roads) for c in cells),
        ),
        ("several roads scored by", spec.aggregate),
        ("tested on", ", ".join(spec.test_roads)),
        ("gain bounds", bounds or "none (no gains)"),
        ("parameter overrides", ", ".join(f"{k} = {v}" for k, v in spec.params.items()) or "none"),
    ]
    return pd.DataFrame(rows, columns=["item", "value"])


def parameter_table(spec: RunSpec) -> pd.DataFrame:
    """Every parameter value of the scenario, one column per road (test roads included)."""
    from chassistune.scenarios.registry import get_plant

    plant = get_plant(spec.plant)
    roads = list(dict.fromkeys([*spec.roads, *spec.test_roads]))
    by_road = {
        road: plant.scenario(
            spec.preset, road, spec.controller, spec.params, spec.scenario_seed
        ).params()
        for road in roads
    }
    names = list(dict.fromkeys(k for p in by_road.values() for k in p if k != "seed"))
    rows = [
        {"parameter": k, **{road: _show(by_road[road].get(k, "")) for road in roads}} for k in names
    ]
    return pd.DataFrame(rows)


def _show(v: Any) -> str:
    """Exact text of a parameter value (floats by repr, sequences joined)."""
    if isinstance(v, list | tuple):
        return ", ".join(_show(x) for x in v)
    return repr(v) if isinstance(v, float) else str(v)
