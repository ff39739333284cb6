"""paper_scripts/iabc_suspension_study.py on a tiny budget: outputs written, resume skips runs."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path
from types import ModuleType

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "paper_scripts" / "iabc_suspension_study.py"


@pytest.fixture(scope="module")
def study() -> ModuleType:
    spec = importlib.util.spec_from_file_location("iabc_suspension_study", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while decorating
    spec.loader.exec_module(module)
    return module


def _quiet(_: str) -> None:
    pass


def test_tiny_study_writes_outputs_and_resumes(study: ModuleType, tmp_path: Path) -> None:
    cfg = study.Config(out=tmp_path, seeds=2, pop=5, iters=3, realizations=2, checkpoints=(1, 3),
                       grid_points=11)
    res = study.run_study(cfg, _quiet)
    runs = sorted((tmp_path / "runs").rglob("seed_*.json"))
    assert res["new_runs"] == len(runs) == 2 * len(study.cells())
    for name in ("summary", "wilcoxon", "convergence", "optimum", "table2", "improvement"):
        assert (tmp_path / f"{name}.csv").stat().st_size > 0
    assert "Table 2, paper-iabc, paper box" in (tmp_path / "tables.md").read_text()
    assert len(list(tmp_path.glob("convergence_*.png"))) == 2 * len(study.exact_pairs()) + 1
    assert json.loads((tmp_path / "results.json").read_text())["seeds"] == 2

    one = json.loads(runs[0].read_text())
    assert one["nit"] == 3 and len(one["history"]) == 3 and one["scouts"] >= 0
    stamps = {p: p.stat().st_mtime_ns for p in runs}
    assert study.run_all(cfg, _quiet) == 0
    assert {p: p.stat().st_mtime_ns for p in runs} == stamps

    runs[0].unlink()
    assert study.run_all(cfg, _quiet) == 1
    again = json.loads(runs[0].read_text())
    again.pop("wall_time_s"), one.pop("wall_time_s")
    assert again == one  # the same seed redone gives the same run


def test_other_budget_in_same_folder_is_refused(study: ModuleType, tmp_path: Path) -> None:
    study.check_manifest(study.Config(out=tmp_path, pop=5, iters=3))
    with pytest.raises(SystemExit, match="--out"):
        study.check_manifest(study.Config(out=tmp_path, pop=6, iters=3))
