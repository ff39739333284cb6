"""Results loaded back into Python: a tune's folder (or an export's JSON) and a study's folder.

    load_tune("out/")            -> the tune.json document (plant, preset, roads, controller,
                                    best_gains, params, metrics, ...), checked
    simulate_tuned("out/", road="ice")
                                 -> a SimulationResult of the tuned controller (its plant,
                                    preset, parameters and gains; another road if given)
    load_study("st/")            -> StudyData: every stored run (spec, status, best gains,
                                    metrics); `runs_table(data.records)` as a DataFrame

What `simulate --from` reads is `load_tune`'s document. Bad input raises InputError naming
`field` (the CLI's `--from`, the API's `path`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from chassistune.reports.tables import StudyData
    from chassistune.simulate import SimulationResult


def load_tune(path: str | os.PathLike[str], field: str = "path") -> dict[str, Any]:
    """A tune's tune.json (or the folder holding it), or an export's JSON seen as one; checked
    (`tuning.saved.check_tune`: every gain of its controller present and a finite number)."""
    from chassistune.params import read_json
    from chassistune.tuning.saved import check_tune

    file = os.path.join(path, "tune.json") if os.path.isdir(path) else os.fspath(path)
    doc = read_json(file, field)
    if isinstance(doc, dict) and "schema" in doc:
        from chassistune.export.json_export import as_tune_result

        doc = as_tune_result(doc, field, file)
    return check_tune(doc, field, file)


def overrides(doc: Mapping[str, Any]) -> dict[str, object]:
    """The parameters a tune result set away from its scenario's defaults (its `params` echo
    minus what the preset, road and controller give anyway), and its TIR file (`tire`), which
    its road may need."""
    from chassistune.scenarios.registry import get_plant

    tire = {"tire": doc["params"]["tire"]} if "tire" in doc["params"] else {}
    plain = (
        get_plant(doc["plant"])
        .scenario(doc["preset"], doc["roads"][0], doc["controller"], tire, 0)
        .params()
    )
    changed = {k: v for k, v in doc["params"].items() if k != "seed" and plain.get(k) != v}
    return {**changed, **tire}


def simulate_tuned(
    path: str | os.PathLike[str],
    road: str | None = None,
    params: Mapping[str, object] | None = None,
) -> SimulationResult:
    """The tuned controller of a tune result simulated again: on its first road (or `road`),
    with its parameters (`params` overriding them) and its seed."""
    from chassistune.simulate import simulate

    doc = load_tune(path)
    values = {**overrides(doc), **(params or {})}
    return simulate(
        doc["plant"],
        doc["preset"],
        road or doc["roads"][0],
        doc["controller"],
        values,
        doc["best_gains"],
        int(doc["params"].get("seed", 0)),
    )


def load_study(study_dir: str | os.PathLike[str], field: str = "path") -> StudyData:
    """Every stored run of a study folder, in the config's order of scenarios and optimizers
    (the store is opened read-only for the call; a running study may add more later)."""
    from chassistune.reports.tables import load_study as read
    from chassistune.studies.store import open_study

    with open_study(Path(study_dir), field) as store:
        return read(store)
