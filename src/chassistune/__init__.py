"""chassistune: tune vehicle chassis controllers with swarm optimizers in closed-loop simulation.

Python API: `simulate(...)` one closed-loop run, `tune(...)` tune a controller's gains,
`minimize(fun, bounds, method=...)` any optimizer over a vectorized function,
`chassistune.benchmarks.get("F14")` the classic benchmark functions; `load_tune`,
`simulate_tuned` and `load_study` read results back (`chassistune.results`). Their heavy parts
(numpy, numba, the plants) are imported on first use, so that importing the package and starting
the CLI stay fast.
"""

from __future__ import annotations

import importlib
import os as _os
import sys as _sys
from typing import TYPE_CHECKING, Any

if _os.path.basename(_sys.argv[0]) == "chassistune":  # the console script: Ctrl-C policy first
    from chassistune._interrupt import install as _install_ctrl_c

    _install_ctrl_c()

from chassistune._numba_cache import configure as _configure_numba_cache
from chassistune._version import __version__

_configure_numba_cache()

# `simulate` is bound now (its module is light): the function must shadow the submodule of the
# same name before anything imports that submodule.
from chassistune.simulate import simulate  # noqa: E402

if TYPE_CHECKING:
    from chassistune.optimizers.minimize import minimize
    from chassistune.results import load_study, load_tune, simulate_tuned
    from chassistune.simulate import compare
    from chassistune.tuning.tune import tune

_LAZY = {
    "minimize": "chassistune.optimizers.minimize",
    "tune": "chassistune.tuning.tune",
    "compare": "chassistune.simulate",
    "load_tune": "chassistune.results",
    "simulate_tuned": "chassistune.results",
    "load_study": "chassistune.results",
}


def __getattr__(name: str) -> Any:
    """`chassistune.minimize`, `tune`, `compare` and the loaders of `chassistune.results`,
    imported on first access."""
    if name not in _LAZY:
        raise AttributeError(f"module 'chassistune' has no attribute {name!r}")
    value = getattr(importlib.import_module(_LAZY[name]), name)
    globals()[name] = value
    return value


__all__ = [
    "__version__",
    "compare",
    "load_study",
    "load_tune",
    "minimize",
    "simulate",
    "simulate_tuned",
    "tune",
]
