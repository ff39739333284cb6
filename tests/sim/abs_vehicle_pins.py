"""Pinned abs-vehicle results: a change of the kernel's structure must leave them bit for bit.

`compute()` runs every case through the scenario API and returns plain JSON data: each metrics
row and each trace signal as the SHA-256 digest of its float64 bytes. The pinned copy is
`tests/golden/abs_vehicle.json`; `python tests/sim/abs_vehicle_pins.py --write` re-records it (only
when a change of numerics is intended and stated). `arrays()` returns the same results as arrays
(to compare against a saved copy while developing).
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

PINNED = Path(__file__).parents[1] / "golden" / "abs_vehicle.json"

CONTROLLERS = (
    "none",
    "pid",
    "threshold",
    "fuzzy-pid",
    "sliding-mode",
    "mixed-slip-deceleration",
    "adrc",
    "extremum-seeking",
    "mpc",
)
ROADS = ("dry-concrete", "ice", "mu-jump", "split-mu")

SINGLE_CASES: list[tuple[str, str, dict[str, str]]] = [
    *((road, ctrl, {}) for ctrl in CONTROLLERS for road in ROADS),
    ("split-mu", "pid", {"rear": "select-low"}),
    ("split-mu", "pid", {"steering": "driver"}),
    ("split-mu", "threshold", {"split_by": "road", "steering": "driver"}),
    ("mu-jump", "pid", {"axle_gains": "per-axle", "steering": "driver"}),
    ("mu-jump", "fuzzy-pid", {"first_surface": "dry-concrete", "second_surface": "ice"}),
    ("dry-concrete", "none", {"cg_height_m": "0"}),
]
"""(road, controller, params): one run at the default gains, traced."""

POPULATION_CASES: list[tuple[str, str, dict[str, str]]] = [
    ("dry-concrete", "pid", {}),
    ("ice", "fuzzy-pid", {}),
    ("dry-concrete", "fuzzy-pid", {}),
    ("mu-jump", "pid", {}),
    ("split-mu", "fuzzy-pid", {"rear": "select-low"}),
    ("split-mu", "pid", {"steering": "driver"}),
    ("dry-concrete", "sliding-mode", {}),
    ("mu-jump", "mixed-slip-deceleration", {}),
    ("dry-concrete", "adrc", {}),
    ("mu-jump", "extremum-seeking", {}),
    ("dry-concrete", "mpc", {}),
]
"""(road, controller, params): 12 candidates uniform in the tuning box and 4 wild ones."""


def _digest(a: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(a, dtype=np.float64).tobytes()).hexdigest()[:24]


def _key(road: str, ctrl: str, params: dict[str, str]) -> str:
    return "/".join([road, ctrl, *(f"{k}={v}" for k, v in sorted(params.items()))])


def _pinned(params: dict[str, str]) -> dict[str, str]:
    """The case's parameters with the steering the pins were recorded with: fixed where the
    case does not name one (split-mu's default is the driver)."""
    return {"steering": "fixed", **params}


def population(bounds: list[tuple[float, float]], seed: int = 7) -> np.ndarray:
    """12 candidates uniform in the box, then unstable and degenerate ones: every gain at 20x
    its upper bound, at minus its upper bound, at 0, and a NaN."""
    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    box = lo + (hi - lo) * np.random.default_rng(seed).random((12, len(bounds)))
    wild = np.stack([20.0 * hi, -hi, 0.0 * hi, np.where(np.arange(len(hi)) == 0, np.nan, hi)])
    return np.concatenate([box, wild])


def arrays() -> dict[str, dict[str, np.ndarray]]:
    """Every case's arrays: `raw` (the kernel's metrics rows) and, for single runs, the trace."""
    from chassistune.scenarios.abs_vehicle import PLANT

    out: dict[str, dict[str, np.ndarray]] = {}
    for road, ctrl, params in SINGLE_CASES:
        sc = PLANT.scenario(None, road, ctrl, _pinned(params))
        g = sc.gains_array(None)
        case = {"raw": sc.raw(g[None, :], workers=1)}
        case.update({f"trace.{k}": v for k, v in sc.trace(g).signals.items()})
        out[_key(road, ctrl, params)] = case
    for road, ctrl, params in POPULATION_CASES:
        sc = PLANT.scenario(None, road, ctrl, _pinned(params))
        out["population/" + _key(road, ctrl, params)] = {
            "raw": sc.raw(population(sc.controller.bounds()), workers=1)
        }
    return out


def compute() -> dict[str, Any]:
    """The pinned form of `arrays()`: a digest per metrics row and per trace signal."""
    out: dict[str, Any] = {}
    for key, case in arrays().items():
        pins: dict[str, Any] = {"raw": [_digest(row) for row in case["raw"]]}
        pins.update({k: _digest(v) for k, v in sorted(case.items()) if k != "raw"})
        out[key] = pins
    return out


if __name__ == "__main__":
    if "--write" in sys.argv:
        PINNED.write_text(json.dumps(compute(), indent=1, sort_keys=True) + "\n")
        print(f"wrote {PINNED}")
    elif "--save" in sys.argv:  # arrays for development: --save FILE.npz
        target = sys.argv[sys.argv.index("--save") + 1]
        np.savez(target, **{f"{k}|{n}": a for k, case in arrays().items() for n, a in case.items()})
    else:
        print(json.dumps(compute(), indent=1, sort_keys=True))
