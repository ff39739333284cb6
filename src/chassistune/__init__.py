"""chassistune: tune vehicle chassis controllers with swarm optimizers in closed-loop simulation.

Python API: `simulate(...)` one closed-loop run, `tune(...)` tune a controller's gains,
`minimize(fun, bounds, method=...)` any optimizer over a vectorized function,
`chassistune.benchmarks.get("F14")` the classic benchmark functions.
"""

__version__ = "0.1.0"

from chassistune._numba_cache import configure as _configure_numba_cache

_configure_numba_cache()

from chassistune.optimizers.minimize import minimize  # noqa: E402
from chassistune.simulate import simulate  # noqa: E402
from chassistune.tuning.tune import tune  # noqa: E402

__all__ = ["__version__", "minimize", "simulate", "tune"]
