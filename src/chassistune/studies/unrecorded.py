"""Finished runs the store could not take in time (another process held its lock past the wait):
kept beside it, one JSON file each in DIR/unrecorded/, until the next `study run` records them.

So a lock never costs a finished run: the driver stops, and the rerun stores what it had.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

from chassistune._io import write_json
from chassistune.errors import InputError
from chassistune.studies.records import RunResult, RunStatus
from chassistune.studies.spec import RunSpec

FOLDER = "unrecorded"


def folder(study_dir: str | Path) -> Path:
    return Path(study_dir) / FOLDER


def keep(study_dir: str | Path, spec: RunSpec, result: RunResult) -> Path:
    """Write one finished run to DIR/unrecorded/<spec hash>.json (atomically)."""
    path = folder(study_dir) / f"{spec.spec_hash}.json"
    path.parent.mkdir(exist_ok=True)
    write_json(path, {"spec": json.loads(spec.model_dump_json()), **dataclasses.asdict(result)})
    return path


def kept(study_dir: str | Path) -> list[tuple[Path, RunSpec, RunResult]]:
    """Every run kept in DIR/unrecorded/, with the spec and result it holds."""
    out = []
    for path in sorted(folder(study_dir).glob("*.json")):
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
            spec = RunSpec.model_validate_json(json.dumps(doc.pop("spec")))
            doc["status"] = RunStatus(doc["status"])
            out.append((path, spec, RunResult(**doc)))
        except (OSError, ValueError, TypeError, KeyError) as exc:
            raise InputError(
                "out", f"{str(path)!r} is not a kept run ({type(exc).__name__}: {exc})"
            ) from None
    return out
