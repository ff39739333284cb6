"""chassistune: tune vehicle chassis controllers with swarm optimizers in closed-loop simulation."""

__version__ = "0.1.0"

from chassistune.optimizers.minimize import minimize

__all__ = ["__version__", "minimize"]
