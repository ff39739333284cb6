"""Uncertain parameters as data: `--vary` specs and the study `[uncertainty]` table.

Grammar of one spec (CLI `--vary`, or a value of the table's `vary` sub-table):
    NAME=LO:HI  (or NAME=uniform:LO:HI)   uniform on [LO, HI], LO < HI, inside the valid range;
    NAME=normal:MEAN:SD                    normal, SD > 0, MEAN inside the valid range; draws are
                                           clipped to the valid range.
In the table a uniform range may also be written as a two-element list `[LO, HI]`.

Every name is checked against the caller's `known` ranges (which parameters of the plant, road
and actuator may vary, and where each is valid); bad input raises `InputError` naming the domain
field (`vary.mass_kg`, `scenarios`, `pass.max_distance_ratio`): the CLI maps it to its flag
(`--vary mass_kg`), a study to its config path (`scenarios[0].uncertainty.vary.mass_kg`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from chassistune.errors import InputError
from chassistune.params import to_float
from chassistune.tuning.robust.aggregate import Aggregate, parse_aggregate

SAMPLERS = ("sobol", "lhs")


@dataclass(frozen=True)
class ParamRange:
    """Where a parameter is valid: [lo, hi], each end open or closed (a mass: (0, inf))."""

    lo: float = -math.inf
    hi: float = math.inf
    lo_open: bool = False
    hi_open: bool = False

    def contains(self, x: float) -> bool:
        above = x > self.lo if self.lo_open else x >= self.lo
        below = x < self.hi if self.hi_open else x <= self.hi
        return above and below

    def clip_bounds(self) -> tuple[float, float]:
        """The closed interval draws are clipped to (an open end moves to the next float inside)."""
        lo = math.nextafter(self.lo, math.inf) if self.lo_open else self.lo
        hi = math.nextafter(self.hi, -math.inf) if self.hi_open else self.hi
        return lo, hi

    def __str__(self) -> str:
        left = "(" if self.lo_open or math.isinf(self.lo) else "["
        right = ")" if self.hi_open or math.isinf(self.hi) else "]"
        return f"{left}{self.lo:g}, {self.hi:g}{right}"


@dataclass(frozen=True)
class UncertainParam:
    """One varied parameter: uniform on [lo, hi], or normal(mean, sd) clipped to `valid`."""

    name: str
    dist: str
    lo: float = math.nan
    hi: float = math.nan
    mean: float = math.nan
    sd: float = math.nan
    valid: ParamRange = field(default_factory=ParamRange)

    def describe(self) -> str:
        if self.dist == "uniform":
            return f"{self.name} uniform on [{self.lo:g}, {self.hi:g}]"
        return f"{self.name} normal(mean {self.mean:g}, sd {self.sd:g}) clipped to {self.valid}"


@dataclass(frozen=True)
class PassCriterion:
    """Validation pass test of one draw (default: stops, no wheel lock above v_stop, distance at
    most 1.10 x the adhesion bound). `max_distance_ratio` 0 switches the distance test off;
    `max_cost` > 0 adds "objective at most max_cost" (for plants without a stop, e.g. the quarter
    car's RMS ratio against passive: 1.0)."""

    require_stop: bool = True
    allow_lock: bool = False
    max_distance_ratio: float = 1.10
    max_cost: float = 0.0


@dataclass(frozen=True)
class UncertaintySpec:
    """Varied parameters, the training set (K scenarios, sampler; K = 0: the nominal plant
    alone), the aggregate over them, and validation (N fresh Monte Carlo draws, confidence
    1 - beta, pass criterion)."""

    params: tuple[UncertainParam, ...]
    scenarios: int = 16
    sampler: str = "sobol"
    aggregate: Aggregate = field(default_factory=Aggregate)
    validate: int = 0
    beta: float = 0.05
    criterion: PassCriterion = field(default_factory=PassCriterion)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.params)


def _check_name(name: str, known: Mapping[str, ParamRange], where: str) -> ParamRange:
    if name not in known:
        raise InputError(
            where, f"unknown uncertain parameter {name!r} (known: {', '.join(sorted(known))})"
        )
    return known[name]


def parse_one(
    name: str, text: str | Sequence[Any], known: Mapping[str, ParamRange], where: str
) -> UncertainParam:
    """One parameter from 'LO:HI', 'uniform:LO:HI', 'normal:MEAN:SD' or a list [LO, HI]."""
    valid = _check_name(name, known, where)
    if isinstance(text, str):
        parts = [p.strip() for p in text.split(":")]
        kind = parts[0].lower() if parts and parts[0].lower() in ("uniform", "normal") else ""
        numbers = parts[1:] if kind else parts
    elif isinstance(text, list | tuple):
        kind, numbers = "", list(text)
    else:
        raise InputError(where, f"expected 'LO:HI', 'normal:MEAN:SD' or [LO, HI], got {text!r}")
    if len(numbers) != 2 or any(isinstance(v, bool) for v in numbers):
        raise InputError(where, f"expected LO:HI, uniform:LO:HI or normal:MEAN:SD, got {text!r}")
    a, b = (to_float(v, where) for v in numbers)
    if kind == "normal":
        if not b > 0:
            raise InputError(where, f"the standard deviation must be positive, got {b:g}")
        if not valid.contains(a):
            raise InputError(where, f"mean {a:g} outside the valid range {valid}")
        return UncertainParam(name, "normal", mean=a, sd=b, valid=valid)
    if not a < b:
        raise InputError(where, f"need LO < HI, got {a:g}:{b:g}")
    if not (valid.contains(a) and valid.contains(b)):
        raise InputError(where, f"range [{a:g}, {b:g}] outside the valid range {valid}")
    return UncertainParam(name, "uniform", lo=a, hi=b, valid=valid)


def parse_vary(items: Sequence[str], known: Mapping[str, ParamRange]) -> tuple[UncertainParam, ...]:
    """Repeated `--vary NAME=SPEC` options, in the order given; a name given twice is an error."""
    out: dict[str, UncertainParam] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name or not text.strip():
            raise InputError("vary", f"expected NAME=LO:HI or NAME=normal:MEAN:SD, got {item!r}")
        where = f"vary.{name}"
        if name in out:
            raise InputError(where, "listed twice")
        out[name] = parse_one(name, text, known, where)
    return tuple(out.values())


def check_sampler(sampler: str, scenarios: int, minimum: int = 1) -> None:
    """A known sampler; K >= minimum (a training set may be 0: tune on the nominal plant, the
    uncertainty serving validation and sensitivity only), and for Sobol a power of two (its
    balance properties need it)."""
    if sampler not in SAMPLERS:
        raise InputError("sampler", f"must be sobol or lhs, got {sampler!r}")
    if isinstance(scenarios, bool) or not isinstance(scenarios, int) or scenarios < minimum:
        raise InputError("scenarios", f"must be an integer >= {minimum}, got {scenarios!r}")
    if sampler == "sobol" and scenarios > 0 and scenarios & (scenarios - 1):
        raise InputError(
            "scenarios", f"must be a power of two for the sobol sampler, got {scenarios}"
        )


def check_validation(n: int, beta: float) -> None:
    """N >= 0 draws (0: no validation), 0 < beta < 1."""
    if isinstance(n, bool) or not isinstance(n, int) or n < 0:
        raise InputError("validate", f"must be a non-negative integer, got {n!r}")
    if not 0.0 < beta < 1.0:
        raise InputError("beta", f"must be in (0, 1), got {beta:g}")


def spec_from_options(
    known: Mapping[str, ParamRange],
    vary: Sequence[str],
    scenarios: int = 16,
    sampler: str = "sobol",
    aggregate: str = "mean",
    validate: int = 0,
    beta: float = 0.05,
) -> UncertaintySpec:
    """The spec of `tune --vary ... --scenarios K --sampler S --aggregate A --validate N --beta B`,
    all checked before any work (errors name the fields vary.NAME, scenarios, sampler, aggregate,
    validate, beta)."""
    params = parse_vary(vary, known)
    check_sampler(sampler, scenarios, minimum=0)
    check_validation(validate, beta)
    return UncertaintySpec(params, scenarios, sampler, parse_aggregate(aggregate), validate, beta)


_TABLE_KEYS = ("vary", "scenarios", "sampler", "aggregate", "validate", "beta", "pass")
_PASS_KEYS = ("require_stop", "allow_lock", "max_distance_ratio", "max_cost")


def _criterion(table: Any) -> PassCriterion:
    if not isinstance(table, Mapping):
        raise InputError("pass", "expected a table")
    for key in table:
        if key not in _PASS_KEYS:
            raise InputError(f"pass.{key}", f"unknown key (known: {', '.join(_PASS_KEYS)})")
    flags = {}
    for key in ("require_stop", "allow_lock"):
        if key in table:
            if not isinstance(table[key], bool):
                raise InputError(f"pass.{key}", f"must be true or false, got {table[key]!r}")
            flags[key] = table[key]
    ratio = PassCriterion.max_distance_ratio
    if "max_distance_ratio" in table:
        ratio = to_float(table["max_distance_ratio"], "pass.max_distance_ratio")
        if ratio != 0.0 and not ratio >= 1.0:
            raise InputError(
                "pass.max_distance_ratio",
                f"must be at least 1 (no run beats the "
                f"bound) or 0 for no distance test, got {ratio:g}",
            )
    max_cost = to_float(table.get("max_cost", 0.0), "pass.max_cost")
    if max_cost < 0.0:
        raise InputError(
            "pass.max_cost", f"must be positive, or 0 for no cost test, got {max_cost:g}"
        )
    return PassCriterion(max_distance_ratio=ratio, max_cost=max_cost, **flags)


def parse_table(table: Mapping[str, Any], known: Mapping[str, ParamRange]) -> UncertaintySpec:
    """A study's `[uncertainty]` table (as tomllib reads it) into an `UncertaintySpec`; errors
    name the field inside the table (vary.NAME, scenarios, pass.KEY, ...)."""
    for key in table:
        if key not in _TABLE_KEYS:
            raise InputError(str(key), f"unknown key (known: {', '.join(_TABLE_KEYS)})")
    vary = table.get("vary")
    if not isinstance(vary, Mapping) or not vary:
        raise InputError("vary", 'expected a non-empty table NAME = "LO:HI" | ...')
    params = tuple(parse_one(str(n), s, known, f"vary.{n}") for n, s in vary.items())
    scenarios = table.get("scenarios", UncertaintySpec.scenarios)
    sampler = table.get("sampler", UncertaintySpec.sampler)
    check_sampler(sampler, scenarios, minimum=0)
    aggregate = parse_aggregate(str(table.get("aggregate", "mean")))
    n_validate = table.get("validate", 0)
    beta = to_float(table.get("beta", UncertaintySpec.beta), "beta")
    check_validation(n_validate, beta)
    criterion = _criterion(table.get("pass", {}))
    return UncertaintySpec(params, scenarios, sampler, aggregate, n_validate, beta, criterion)
