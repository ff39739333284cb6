"""Validate a rule-base description (parsed TOML or `fuzzy show --json`) into a `RuleBase`.

Every problem raises `InputError` naming the field, e.g. `inputs[1].sets[2].params` or
`rules[12][1]`. Rules must form a complete table: every combination of input sets exactly once
(a missing cell leaves a hole where no rule fires; a repeated one is a conflict).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from chassistune.errors import InputError
from chassistune.fuzzy.rulebase import OPERATORS, RuleBase, Variable
from chassistune.fuzzy.sets import SHAPES, FuzzySet, params_problem

_TOP_KEYS = {"inputs", "outputs", "rules", "operators", "description"}
_VAR_KEYS = {"name", "universe", "sets"}
_SET_KEYS = {"name", "shape", "params"}


class _Checker:
    """Raises `InputError` with the field path prefixed by where the description came from."""

    def __init__(self, where: str) -> None:
        self.where = where

    def fail(self, path: str, problem: str) -> InputError:
        return InputError(f"{self.where}: {path}" if path else self.where, problem)

    def table(
        self, value: Any, path: str, allowed: set[str], required: set[str]
    ) -> Mapping[str, Any]:
        if not isinstance(value, Mapping):
            raise self.fail(path, f"expected a table, got {_kind(value)}")
        unknown = sorted(set(value) - allowed)
        if unknown:
            raise self.fail(
                path, f"unknown key {unknown[0]!r} (allowed: {', '.join(sorted(allowed))})"
            )
        missing = sorted(required - set(value))
        if missing:
            raise self.fail(path, f"missing key {missing[0]!r}")
        return value

    def array(self, value: Any, path: str) -> Sequence[Any]:
        if isinstance(value, str | bytes) or not isinstance(value, Sequence):
            raise self.fail(path, f"expected an array, got {_kind(value)}")
        if not value:
            raise self.fail(path, "must not be empty")
        return value

    def name(self, value: Any, path: str) -> str:
        if not isinstance(value, str) or not value.strip():
            raise self.fail(path, f"expected a non-empty string, got {_kind(value)}")
        return value

    def number(self, value: Any, path: str) -> float:
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise self.fail(path, f"expected a finite number, got {value!r}")
        return float(value)


def _kind(value: Any) -> str:
    return "nothing" if value is None else f"{type(value).__name__} {value!r}"[:60]


def _fuzzy_set(ck: _Checker, raw: Any, path: str, universe: tuple[float, float]) -> FuzzySet:
    t = ck.table(raw, path, _SET_KEYS, _SET_KEYS)
    name = ck.name(t["name"], f"{path}.name")
    shape = ck.name(t["shape"], f"{path}.shape")
    params = tuple(
        ck.number(p, f"{path}.params[{i}]")
        for i, p in enumerate(ck.array(t["params"], f"{path}.params"))
    )
    problem = params_problem(shape, params)
    if problem:
        raise ck.fail(f"{path}.params" if shape in SHAPES else f"{path}.shape", problem)
    fs = FuzzySet(name, shape, params)
    lo, hi = fs.core
    if hi < universe[0] or lo > universe[1]:
        raise ck.fail(
            f"{path}.params", f"the peak of set {name!r} lies outside the universe {list(universe)}"
        )
    return fs


def _variable(ck: _Checker, raw: Any, path: str) -> Variable:
    t = ck.table(raw, path, _VAR_KEYS, _VAR_KEYS)
    name = ck.name(t["name"], f"{path}.name")
    uni = ck.array(t["universe"], f"{path}.universe")
    if len(uni) != 2:
        raise ck.fail(f"{path}.universe", f"expected [lo, hi], got {len(uni)} values")
    lo = ck.number(uni[0], f"{path}.universe[0]")
    hi = ck.number(uni[1], f"{path}.universe[1]")
    if lo >= hi:
        raise ck.fail(f"{path}.universe", f"lo must be < hi, got [{lo:g}, {hi:g}]")
    sets = tuple(
        _fuzzy_set(ck, s, f"{path}.sets[{i}]", (lo, hi))
        for i, s in enumerate(ck.array(t["sets"], f"{path}.sets"))
    )
    names = [s.name for s in sets]
    for i, n in enumerate(names):
        if n in names[:i]:
            raise ck.fail(f"{path}.sets[{i}].name", f"duplicate set name {n!r} in {name!r}")
    return Variable(name, (lo, hi), sets)


def _rules(
    ck: _Checker, raw: Any, inputs: tuple[Variable, ...], outputs: tuple[Variable, ...]
) -> tuple[tuple[str, ...], ...]:
    variables = inputs + outputs
    width = len(variables)
    rows: list[tuple[str, ...]] = []
    seen: dict[tuple[str, ...], int] = {}
    for r, row in enumerate(ck.array(raw, "rules")):
        path = f"rules[{r}]"
        cells = ck.array(row, path)
        if len(cells) != width:
            raise ck.fail(
                path,
                f"expected {width} set names ({len(inputs)} inputs "
                f"{', '.join(v.name for v in inputs)}, then {len(outputs)} outputs "
                f"{', '.join(v.name for v in outputs)}), got {len(cells)}",
            )
        for c, (var, cell) in enumerate(zip(variables, cells, strict=True)):
            kind = "input" if c < len(inputs) else "output"
            if not isinstance(cell, str) or cell not in var.set_names:
                raise ck.fail(
                    f"{path}[{c}]",
                    f"unknown set {cell!r} of {kind} {var.name!r} "
                    f"(sets: {', '.join(var.set_names)})",
                )
        key = tuple(cells[: len(inputs)])
        if key in seen:
            raise ck.fail(path, f"repeats the antecedent {list(key)} of rules[{seen[key]}]")
        seen[key] = r
        rows.append(tuple(cells))
    expected = math.prod(len(v.sets) for v in inputs)
    if len(rows) != expected:
        shape = " x ".join(str(len(v.sets)) for v in inputs)
        raise ck.fail(
            "rules", f"expected a complete {shape} table of {expected} rules, got {len(rows)}"
        )
    return tuple(rows)


def rulebase_from_dict(data: Any, name: str, where: str | None = None) -> RuleBase:
    """Validate a description (the structure of `fuzzy show --json`) into a `RuleBase`."""
    ck = _Checker(where or f"rulebase {name!r}")
    top = ck.table(data, "", _TOP_KEYS, {"inputs", "outputs", "rules"})
    inputs = tuple(
        _variable(ck, v, f"inputs[{i}]") for i, v in enumerate(ck.array(top["inputs"], "inputs"))
    )
    outputs = tuple(
        _variable(ck, v, f"outputs[{i}]") for i, v in enumerate(ck.array(top["outputs"], "outputs"))
    )
    names = [v.name for v in inputs + outputs]
    for i, n in enumerate(names):
        if n in names[:i]:
            raise ck.fail(
                "outputs" if i >= len(inputs) else "inputs", f"duplicate variable name {n!r}"
            )
    ops = ck.table(top.get("operators", OPERATORS), "operators", set(OPERATORS), set())
    for key, value in ops.items():
        if value != OPERATORS[key]:
            raise ck.fail(
                f"operators.{key}", f"only {OPERATORS[key]!r} is supported, got {value!r}"
            )
    description = top.get("description", "")
    if not isinstance(description, str):
        raise ck.fail("description", f"expected a string, got {_kind(description)}")
    return RuleBase(name, inputs, outputs, _rules(ck, top["rules"], inputs, outputs), description)
