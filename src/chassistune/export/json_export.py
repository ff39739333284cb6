"""JSON export: everything the other formats carry, as schema-versioned data.

`scenario` holds what `chassistune.simulate` needs to re-run the exported scenario (plant, preset,
road, controller, gains, params; the params include the export's ideal ECU, so the run is the
loop of the test vectors): `scenario_arguments` reads it back, `as_tune_result` gives it to
`simulate --from` as a tune result.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from chassistune._io import dumps
from chassistune._version import __version__
from chassistune.controllers import discrete
from chassistune.errors import InputError
from chassistune.export.source import ExportedController

SCHEMA = "chassistune.export"
SCHEMA_VERSION = 1


def document(ec: ExportedController, inputs: np.ndarray, u: np.ndarray) -> dict[str, Any]:
    """The JSON object (floats only finite; Python's repr keeps every double exact)."""
    sc = ec.scenario
    params = sc.params()
    params.pop("seed", None)
    table = None
    if ec.table_outputs:
        rows, cols = ec.table_inputs
        lo0, step0, lo1, step1 = ec.grid.tolist()
        table = {
            "rulebase": ec.rulebase,
            "inputs": list(ec.table_inputs),
            "outputs": list(ec.table_outputs),
            "orientation": f"values[output][i][j] at {rows} = breakpoints[{rows!r}][i], "
            f"{cols} = breakpoints[{cols!r}][j]",
            "grid": {"row_lo": lo0, "row_step": step0, "col_lo": lo1, "col_step": step1},
            "interpolation": "bilinear on the uniform grid, inputs clipped (controllers.discrete)",
            "breakpoints": {
                n: bp.tolist() for n, bp in zip(ec.table_inputs, ec.breakpoints, strict=True)
            },
            "values": {n: ec.table[k].tolist() for k, n in enumerate(ec.table_outputs)},
        }
    return {
        "schema": SCHEMA,
        "schema_version": SCHEMA_VERSION,
        "generator": f"chassistune {__version__}",
        "controller": ec.controller,
        "form": ec.law.form,
        "source": ec.source,
        "scenario": {
            "plant": sc.plant,
            "preset": sc.preset,
            "road": sc.road,
            "controller": ec.controller,
            "gains": dict(ec.gains),
            "params": params,
        },
        "sample_time_s": ec.ts_s,
        "inputs": [
            {"name": n, "description": discrete.INPUT_DESCRIPTIONS[n]} for n in ec.law.inputs
        ],
        "output": {"name": "u", "description": "command of the brake-pressure modulator"},
        "params": ec.param_dict(),
        "state": list(ec.law.state),
        "pid": ec.pid_form(),
        "table": table,
        "test_vectors": {
            "columns": [*ec.law.inputs, "u"],
            "rows": np.column_stack([inputs, u]).tolist(),
        },
    }


def json_text(ec: ExportedController, inputs: np.ndarray, u: np.ndarray) -> str:
    return dumps(document(ec, inputs, u), indent=1) + "\n"


def as_tune_result(doc: object, where: str, label: str) -> dict[str, Any]:
    """An exported JSON object seen as a tune result (plant, preset, roads, controller,
    best_gains, params): what `simulate --from` reads. Its params hold the export's ideal ECU,
    so the run is the closed loop the test vectors come from."""
    if not isinstance(doc, dict) or doc.get("schema") != SCHEMA:
        raise InputError(where, f"{label!r} is not a chassistune export")
    if doc.get("schema_version") != SCHEMA_VERSION:
        raise InputError(
            where, f"export schema version {doc.get('schema_version')!r} is not {SCHEMA_VERSION}"
        )
    sc = doc.get("scenario")
    need = ("plant", "preset", "road", "controller", "gains", "params")
    if not isinstance(sc, dict) or any(k not in sc for k in need):
        raise InputError(where, f"{label!r}: its scenario needs {', '.join(need)}")
    gains = sc["gains"]
    if not isinstance(gains, dict) or not all(
        isinstance(v, float) and math.isfinite(v) for v in gains.values()
    ):
        raise InputError(where, f"{label!r}: gains must be finite numbers")
    return {
        "plant": sc["plant"],
        "preset": sc["preset"],
        "roads": [sc["road"]],
        "controller": sc["controller"],
        "best_gains": dict(gains),
        "params": dict(sc["params"]),
    }


def scenario_arguments(path: str | Path) -> dict[str, Any]:
    """Keyword arguments of `chassistune.simulate` from an exported JSON file."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError("from", f"cannot read {str(path)!r}: {exc}") from None
    result = as_tune_result(doc, "from", str(path))
    return {
        "plant": result["plant"],
        "preset": result["preset"],
        "road": result["roads"][0],
        "controller": result["controller"],
        "gains": result["best_gains"],
        "params": result["params"],
    }
