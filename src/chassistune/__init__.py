"""chassistune: tune vehicle chassis controllers with swarm optimizers in closed-loop simulation.

Python API: `simulate(...)` one closed-loop run, `tune(...)` tune a controller's gains,
`minimize(fun, bounds, method=...)` any optimizer over a vectorized function,
`chassistune.benchmarks.get("F14")` the classic benchmark functions.
"""

__version__ = "0.1.0"

from chassistune.optimizers.minimize import minimize
from chassistune.simulate import simulate
from chassistune.tuning.tune import tune

__all__ = ["__version__", "minimize", "simulate", "tune"]
