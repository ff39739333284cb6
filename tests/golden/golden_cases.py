"""Golden numbers: results that a change of structure must leave bit for bit the same.

`compute()` runs every pinned case through the public API and returns plain JSON data (floats as
their exact `float.hex()` strings, time series as SHA-256 digests of their bytes). The pinned copy
is `golden.json` beside this file; `python tests/golden/golden_cases.py --write` re-records it
(only when a change of numerics is intended and stated).
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

PINNED = Path(__file__).with_name("golden.json")

ABS_CASES: list[tuple[str, str, str, dict[str, float]]] = [
    # (preset, road, controller, params)
    ("paper-derlsp-ao", "dry-concrete", "none", {}),
    ("paper-derlsp-ao", "dry-concrete", "pid", {}),
    ("paper-derlsp-ao", "wet-asphalt", "pid", {}),
    ("paper-derlsp-ao", "ice", "pid", {}),
    ("paper-derlsp-ao", "burckhardt-wet-asphalt", "pid", {}),
    ("paper-derlsp-ao", "dry-concrete", "bang-bang", {}),
    ("paper-derlsp-ao", "dry-concrete", "threshold", {}),
    ("paper-derlsp-ao", "ice", "threshold", {}),
    ("paper-derlsp-ao", "dry-concrete", "fuzzy-pid", {}),
    ("paper-derlsp-ao", "wet-asphalt", "fuzzy-pid", {}),
    ("paper-derlsp-ao", "dry-concrete", "fuzzy-immune-pid", {}),
    ("paper-fuzzy-immune", "asphalt-0.8", "fuzzy-immune-pid", {}),
    ("paper-fuzzy-immune", "dirt-0.2", "pid", {}),
    ("sldemo", "sldemo-table", "bang-bang", {}),
    ("sldemo", "sldemo-table", "none", {}),
    ("paper-derlsp-ao", "dry-concrete", "sliding-mode", {}),
    ("paper-derlsp-ao", "ice", "sliding-mode", {}),
    ("paper-derlsp-ao", "dry-concrete", "adrc", {}),
    ("paper-derlsp-ao", "ice", "adrc", {}),
    ("paper-derlsp-ao", "dry-concrete", "mixed-slip-deceleration", {}),
    ("paper-derlsp-ao", "burckhardt-snow", "mixed-slip-deceleration", {}),
    ("paper-derlsp-ao", "dry-concrete", "extremum-seeking", {}),
    ("paper-derlsp-ao", "burckhardt-snow", "extremum-seeking", {}),
    ("paper-derlsp-ao", "dry-concrete", "mpc", {}),
    ("paper-derlsp-ao", "ice", "mpc", {}),
]
QUARTER_CASES: list[tuple[str, str, str]] = [
    ("paper-iabc", "iso-b", "passive"),
    ("paper-iabc", "iso-b", "pid"),
    ("paper-iabc", "iso-c", "skyhook"),
    ("typical", "iso-b", "pid"),
]
OPTIMIZERS = [
    "ao",
    "derlsp-ao",
    "deffao",
    "abc",
    "iabc",
    "ga",
    "pso",
    "de",
    "gwo",
    "mfo",
    "poa",
    "dbo",
]


def _hex(x: Any) -> Any:
    """Exact JSON form of a metric: floats as float.hex, others as they are."""
    if isinstance(x, bool | np.bool_) or x is None or isinstance(x, str):
        return x if not isinstance(x, np.bool_) else bool(x)
    return float(x).hex()


def _digest(a: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(a, dtype=np.float64).tobytes()).hexdigest()[:24]


def _population(bounds: list[tuple[float, float]], n: int, seed: int) -> np.ndarray:
    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    return lo + (hi - lo) * np.random.default_rng(seed).random((n, len(bounds)))


def abs_case(preset: str, road: str, controller: str, params: dict[str, float]) -> dict[str, Any]:
    import chassistune

    res = chassistune.simulate("abs-wheel", preset, road, controller, params)
    out: dict[str, Any] = {"metrics": {k: _hex(v) for k, v in sorted(res.metrics.items())}}
    out["trace"] = {k: _digest(v) for k, v in sorted(res.trace.signals.items())}
    return out


def abs_population(controller: str) -> dict[str, str]:
    """Costs of 12 random candidates (wild ones included) in one batch call, per objective."""
    from golden_adapter import abs_scenario, gain_bounds

    sc = abs_scenario("paper-derlsp-ao", "dry-concrete", controller)
    pop = _population(gain_bounds(sc), 12, 7)
    return {obj: _digest(sc.cost(pop, obj)) for obj in ("itae", "distance", "time")}


def quarter_case(preset: str, road: str, controller: str) -> dict[str, Any]:
    import chassistune

    res = chassistune.simulate("quarter-car", preset, road, controller, {}, seed=3)
    return {
        "metrics": {k: _hex(v) for k, v in sorted(res.metrics.items())},
        "trace": {k: _digest(v) for k, v in sorted(res.trace.signals.items())},
    }


def optimizer_case(name: str) -> dict[str, Any]:
    import chassistune
    from chassistune import benchmarks

    f = benchmarks.get("F5")
    r = chassistune.minimize(
        f, [(-30.0, 30.0)] * 10, method=name, pop_size=20, max_iter=30, seed=11
    )
    return {
        "fun": _hex(r.fun),
        "x": _digest(np.asarray(r.x)),
        "nfev": int(r.nfev),
        "nit": int(r.nit),
        "history": _digest(np.asarray(r.history)),
        "history_nfev": [int(v) for v in r.history_nfev],
    }


def tune_case(plant: str, controller: str, optimizer: str, roads: list[str]) -> dict[str, Any]:
    import chassistune

    r = chassistune.tune(plant, controller, optimizer, roads=roads, pop_size=10, max_iter=8, seed=5)
    return {
        "best_gains": {k: _hex(v) for k, v in r.best_gains.items()},
        "best_cost": _hex(r.best_cost),
        "nfev": int(r.nfev),
        "history": _digest(np.asarray(r.history)),
    }


def compute() -> dict[str, Any]:
    out: dict[str, Any] = {
        "abs": {},
        "abs_population": {},
        "quarter": {},
        "optimizers": {},
        "tune": {},
    }
    for preset, road, ctrl, params in ABS_CASES:
        out["abs"][f"{preset}/{road}/{ctrl}"] = abs_case(preset, road, ctrl, params)
    for ctrl in ("pid", "fuzzy-pid", "fuzzy-immune-pid"):
        out["abs_population"][ctrl] = abs_population(ctrl)
    for preset, road, ctrl in QUARTER_CASES:
        out["quarter"][f"{preset}/{road}/{ctrl}"] = quarter_case(preset, road, ctrl)
    for name in OPTIMIZERS:
        out["optimizers"][name] = optimizer_case(name)
    out["tune"]["abs-wheel/pid/derlsp-ao"] = tune_case(
        "abs-wheel", "pid", "derlsp-ao", ["dry-concrete", "ice"]
    )
    out["tune"]["quarter-car/pid/iabc"] = tune_case("quarter-car", "pid", "iabc", ["iso-b"])
    return out


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).parent))
    if "--write" in sys.argv:
        PINNED.write_text(json.dumps(compute(), indent=1, sort_keys=True) + "\n")
        print(f"wrote {PINNED}")
    else:
        print(json.dumps(compute(), indent=1, sort_keys=True))
