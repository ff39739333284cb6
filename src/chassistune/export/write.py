"""Write an exported controller in one format into a folder: all files or none.

Every format carries test_vectors.csv (the reference the C, the FMU and any port must reproduce).
Files are built in memory, then written as one `_io.file_set`: every file goes to its temporary
twin in the target folder, and only once all are written do they replace their targets (one
rename each). On any error before that no target is touched, and a folder this call created is
removed again.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from chassistune._io import file_set
from chassistune.errors import InputError
from chassistune.export import c99, fmu, json_export, matlab, vectors
from chassistune.export.source import ExportedController

FORMATS = ("c", "fmu", "mat", "json")
VECTORS = "test_vectors.csv"


def check_folder(out_dir: str) -> None:
    """Refuse, before any work, a folder that cannot be created or written."""
    path = Path(out_dir).absolute()
    existing = path
    while not existing.exists():
        existing = existing.parent
    if path.exists() and not path.is_dir():
        raise InputError("out", f"{out_dir!r} exists and is not a folder")
    if not existing.is_dir():
        raise InputError("out", f"cannot create {out_dir!r}: {str(existing)!r} is not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise InputError("out", f"folder {str(existing)!r} is not writable")


def files(ec: ExportedController, fmt: str) -> dict[str, bytes]:
    """File name -> content of the format `fmt` (FORMATS)."""
    if fmt not in FORMATS:
        raise InputError("format", f"unknown format {fmt!r} (known: {', '.join(FORMATS)})")
    inputs, u = vectors.record(ec)
    if not (np.all(np.isfinite(inputs)) and np.all(np.isfinite(u))):
        raise InputError("gains", "the closed-loop stop diverged: no test vectors to export")
    out = {VECTORS: vectors.csv_text(ec.law.inputs, inputs, u).encode()}
    if fmt == "c":
        out[c99.HEADER] = c99.header(ec).encode()
        out[c99.SOURCE] = c99.source(ec).encode()
        out[c99.CHECK] = c99.CHECK_PROGRAM.encode()
    elif fmt == "fmu":
        out[f"{ec.model_name}.fmu"] = fmu.fmu_bytes(ec)
    elif fmt == "mat":
        out[f"{ec.model_name}.mat"] = matlab.mat_bytes(ec, inputs, u)
        out[f"{ec.model_name}.m"] = matlab.script(ec).encode()
    else:
        out[f"{ec.model_name}.json"] = json_export.json_text(ec, inputs, u).encode()
    return out


def write(ec: ExportedController, fmt: str, out_dir: str) -> list[str]:
    """Write the files of `fmt` into out_dir (created if needed), all or none; the paths."""
    check_folder(out_dir)
    contents = files(ec, fmt)
    target = Path(out_dir).absolute()
    with file_set(target) as staged:
        for name, data in contents.items():
            staged.write_bytes(target / name, data)
    return [str(target / name) for name in contents]
