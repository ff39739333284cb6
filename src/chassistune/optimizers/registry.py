"""Optimizers by name. Modules are imported on first use so that the CLI starts fast."""

from __future__ import annotations

import dataclasses
from typing import Any

from numpy.typing import ArrayLike

from chassistune._registry import Registry
from chassistune._rng import SeedLike
from chassistune.errors import InputError
from chassistune.optimizers.base import Optimizer, Repair

OPTIMIZERS: Registry[type[Optimizer]] = Registry("optimizer", key=str.lower)
for _name, _path in (
    ("ao", "aquila:AO"),
    ("derlsp-ao", "aquila:DERLSPAO"),
    ("deffao", "aquila:DEFFAO"),
    ("abc", "bee_colony:ABC"),
    ("iabc", "bee_colony:IABC"),
    ("ga", "ga:GA"),
    ("pso", "pso:PSO"),
    ("de", "de:DE"),
    ("gwo", "gwo:GWO"),
    ("mfo", "mfo:MFO"),
    ("poa", "poa:POA"),
    ("dbo", "dbo:DBO"),
    ("cma-es", "cma_es:CMAES"),
    ("random-search", "random_search:RandomSearch"),
):
    OPTIMIZERS.register(_name, f"chassistune.optimizers.{_path}")


def register(name: str, cls: type[Optimizer] | str) -> None:
    """Add an optimizer class (or a lazy "module:attr" path) under `name` (lower case)."""
    OPTIMIZERS.register(name.lower(), cls)


def names() -> list[str]:
    """The registered optimizer names."""
    return OPTIMIZERS.names()


def get(name: str) -> type[Optimizer]:
    """The optimizer class `name` (case-insensitive), or InputError listing the known ones."""
    return OPTIMIZERS.get(name)


def hyperparameters(name: str, **overrides: Any) -> Any:
    """The default hyperparameters of `name` with `overrides` applied (validated)."""
    defaults = get(name).defaults
    known = {f.name for f in dataclasses.fields(defaults)}
    unknown = sorted(set(overrides) - known)
    if unknown:
        listing = ", ".join(sorted(known)) or "none"
        raise InputError(
            "hyperparameter", f"{name} has no hyperparameter {unknown[0]!r} (known: {listing})"
        )
    try:
        return dataclasses.replace(defaults, **overrides)
    except TypeError as exc:
        raise InputError("hyperparameter", str(exc)) from None


def make(
    name: str,
    bounds: ArrayLike,
    pop_size: int = 30,
    seed: SeedLike = 0,
    max_iter: int | None = None,
    max_evals: int | None = None,
    repair: Repair = "clip",
    **hyper: Any,
) -> Optimizer:
    """An optimizer `name` ready to ask/tell, with hyperparameter overrides `**hyper`."""
    cls = get(name)
    return cls(
        bounds,
        pop_size,
        seed,
        max_iter=max_iter,
        max_evals=max_evals,
        hyper=hyperparameters(name, **hyper),
        repair=repair,
    )


def catalogue() -> list[dict[str, Any]]:
    """One dict per optimizer: name, description, min_pop, hyperparameters (defaults)."""
    out = []
    for n in OPTIMIZERS.names():
        cls = get(n)
        out.append(
            {
                "name": n,
                "description": cls.description,
                "min_pop": cls.min_pop,
                "hyperparameters": cls.defaults.as_dict(),
            }
        )
    return out
