"""What a controller declares: its tunable gains (unit, default, bounds) and fixed parameters.

The specs of every (plant, controller) pair are listed in `chassistune.controllers.catalogue`.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class GainSpec:
    """A tunable gain: name, unit, default value and tuning bounds [lo, hi]."""

    name: str
    unit: str
    default: float
    lo: float
    hi: float
    description: str = ""

    def as_dict(self) -> dict[str, object]:
        return {
            "name": self.name,
            "unit": self.unit,
            "default": self.default,
            "bounds": [self.lo, self.hi],
            "description": self.description,
        }


@dataclass(frozen=True)
class ParamSpec:
    """A fixed (not tuned) controller parameter, set with `--param NAME=VALUE`.

    `default` is a float, or a string for symbolic choices (then `choices` lists them; an empty
    tuple means free text such as a file path).
    """

    name: str
    unit: str
    default: float | str | None
    description: str = ""
    choices: tuple[str, ...] = ()
    positive: bool = False
    integers: tuple[int, int] | None = None
    """An integer in this closed range (lo, hi), or None for any number."""

    def as_dict(self) -> dict[str, object]:
        out: dict[str, object] = {
            "name": self.name,
            "unit": self.unit,
            "default": self.default,
            "description": self.description,
        }
        if self.choices:
            out["choices"] = list(self.choices)
        if self.integers is not None:
            out["integers"] = list(self.integers)
        return out


@dataclass(frozen=True)
class ControllerSpec:
    """A controller structure available for one plant."""

    plant: str
    name: str
    description: str
    gains: tuple[GainSpec, ...] = ()
    params: tuple[ParamSpec, ...] = ()

    @property
    def gain_names(self) -> tuple[str, ...]:
        return tuple(g.name for g in self.gains)

    @property
    def param_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.params)

    def default_gains(self) -> dict[str, float]:
        return {g.name: g.default for g in self.gains}

    def bounds(self) -> list[tuple[float, float]]:
        return [(g.lo, g.hi) for g in self.gains]

    def as_dict(self) -> dict[str, object]:
        return {
            "name": self.name,
            "description": self.description,
            "gains": [g.as_dict() for g in self.gains],
            "params": [p.as_dict() for p in self.params],
        }
