"""Parameter dataclasses: override by name from strings (`--param NAME=VALUE`), validate, echo.

Every plant, road, solver and controller parameter is a field of a frozen dataclass. Field
metadata `{"positive": True}`, `{"nonnegative": True}` or `{"unit_interval": True}` state the
valid range (outside it: InputError); every float must be finite. `{"plausible": (lo, hi)}` states
the range of real vehicles and rigs: outside it a value is allowed but warned about
(`ImplausibleValue`); `{"unit": "..."}` overrides the unit read from the name's suffix;
`{"open_interval": (lo, hi)}` states a narrower range the dataclass checks itself (robust tuning
draws inside it).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, TypeVar

from chassistune.errors import InputError

T = TypeVar("T")


def positive(lo: float, hi: float, **extra: object) -> dict[str, object]:
    """Field metadata: valid if positive, plausible in [lo, hi] (outside: a warning)."""
    return {"positive": True, "plausible": (lo, hi), **extra}


def nonnegative(lo: float, hi: float, **extra: object) -> dict[str, object]:
    """Field metadata: valid if non-negative, plausible in [lo, hi] (outside: a warning)."""
    return {"nonnegative": True, "plausible": (lo, hi), **extra}


def unit_interval(lo: float, hi: float) -> dict[str, object]:
    """Field metadata: valid in [0, 1], plausible in [lo, hi] (outside: a warning)."""
    return {"unit_interval": True, "plausible": (lo, hi)}


def parse_assignments(items: list[str] | tuple[str, ...], field: str) -> dict[str, str]:
    """Parse ["a=1", "b=x"] into {"a": "1", "b": "x"}; `field` ("params" or "gains") names the
    values for errors; gains may be comma-separated and "@FILE.json" reads a gains file."""
    out: dict[str, str] = {}
    for item in items:
        if field == "gains" and item.startswith("@"):
            out.update(read_gains_file(item[1:]))
            continue
        for part in item.split(",") if field == "gains" else [item]:
            name, sep, value = part.partition("=")
            name, value = name.strip(), value.strip()
            if not sep or not name or not value:
                raise InputError(field, f"expected NAME=VALUE, got {part!r}")
            out[name] = value
    return out


MAX_JSON_BYTES = 64 << 20
"""Largest JSON input read (a tune.json of a long run holds its history: well under this)."""


def read_json(path: str, field: str) -> Any:
    """A JSON file's content; InputError naming `field` when it cannot be read or parsed."""
    import json

    from chassistune._io import read_input

    text = read_input(path, field, MAX_JSON_BYTES)
    try:
        return json.loads(text)
    except ValueError as exc:
        raise InputError(field, f"{path!r} is not JSON: {exc}") from None


def read_gains_file(path: str) -> dict[str, str]:
    """A gains file (`@FILE.json`): a JSON object of gain name -> number (e.g. a tune's
    best_gains.json), or a tune.json (its `best_gains`)."""
    doc = read_json(path, "gains")
    if isinstance(doc, dict) and isinstance(doc.get("best_gains"), dict):
        doc = doc["best_gains"]
    if not isinstance(doc, dict) or not all(
        isinstance(v, int | float) and not isinstance(v, bool) for v in doc.values()
    ):
        raise InputError("gains", f"{path!r} must hold an object of gain name -> number")
    return {str(k): repr(float(v)) for k, v in doc.items()}


def number(text: str) -> float:
    """A float written as a decimal or scientific number; ValueError for anything else that
    Python's float() would take: digit separators (`1_0` is not 10)."""
    if "_" in text:
        raise ValueError(f"not a number: {text!r}")
    return float(text)


def to_float(value: object, field: str) -> float:
    """A finite float from a string or number, else InputError naming `field`."""
    try:
        x = number(value) if isinstance(value, str) else float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(field, f"not a number: {value!r}") from None
    if not math.isfinite(x):
        raise InputError(field, f"must be finite, got {value!r}")
    return x


def check_field(obj: Any, f: dataclasses.Field[Any], value: float, where: str) -> None:
    """Range checks from field metadata."""
    name = f"{where}{f.name}"
    if f.metadata.get("positive") and not value > 0:
        raise InputError(name, f"must be positive, got {value:g}")
    if f.metadata.get("nonnegative") and not value >= 0:
        raise InputError(name, f"must be non-negative, got {value:g}")
    if f.metadata.get("unit_interval") and not 0 <= value <= 1:
        raise InputError(name, f"must be in [0, 1], got {value:g}")


class ImplausibleValue(UserWarning):
    """A parameter outside its plausible range: allowed, warned about (one line in the CLI)."""

    def __init__(self, field: str, problem: str) -> None:
        self.field = field
        self.problem = problem
        super().__init__(f"{field}: {problem}")


def unit_of(f: dataclasses.Field[Any]) -> str:
    """A field's unit: its metadata `unit`, else read from its name (`units.si_unit`)."""
    from chassistune.units import si_unit

    if "unit" in f.metadata:
        return str(f.metadata["unit"])
    return si_unit(f.name) or "-"


def valid_range(f: dataclasses.Field[Any]) -> str:
    """The valid range stated by a field's metadata, as text."""
    if f.metadata.get("positive"):
        return "> 0"
    if f.metadata.get("nonnegative"):
        return ">= 0"
    if f.metadata.get("unit_interval"):
        return "[0, 1]"
    return "finite"


def implausible(obj: Any, where: str = "params.") -> list[ImplausibleValue]:
    """The fields of a parameter dataclass outside their plausible range."""
    out = []
    for f in dataclasses.fields(obj):
        span = f.metadata.get("plausible")
        value = getattr(obj, f.name)
        if span is None or not isinstance(value, float | int) or isinstance(value, bool):
            continue
        lo, hi = span
        if not lo <= value <= hi:
            out.append(
                ImplausibleValue(
                    f"{where}{f.name}",
                    f"{value:g} {unit_of(f)} is outside the plausible range [{lo:g}, {hi:g}]",
                )
            )
    return out


def describe(obj: Any) -> list[dict[str, Any]]:
    """Each field of a parameter dataclass: name, unit, default (its value in `obj`), valid and
    plausible range (`list params`)."""
    return [
        {
            "name": f.name,
            "unit": unit_of(f),
            "default": getattr(obj, f.name),
            "valid": valid_range(f),
            "plausible": list(f.metadata["plausible"]) if "plausible" in f.metadata else None,
        }
        for f in dataclasses.fields(obj)
    ]


def validate(obj: T, where: str = "") -> T:
    """Check every float field of a parameter dataclass (finite, and its metadata range)."""
    for f in dataclasses.fields(obj):  # type: ignore[arg-type]
        value = getattr(obj, f.name)
        if isinstance(value, float | int) and not isinstance(value, bool):
            if not math.isfinite(value):
                raise InputError(f"{where}{f.name}", f"must be finite, got {value!r}")
            check_field(obj, f, float(value), where)
    return obj


def override(obj: T, values: Mapping[str, object], where: str = "params.") -> tuple[T, set[str]]:
    """Return (copy of `obj` with the fields named in `values` replaced, names used).

    Names that are not fields of `obj` are left for the caller (who reports unknown ones).
    Numeric fields are parsed as finite floats; string fields are taken as they are.
    """
    changes: dict[str, object] = {}
    used: set[str] = set()
    for f in dataclasses.fields(obj):  # type: ignore[arg-type]
        if f.name not in values:
            continue
        raw = values[f.name]
        current = getattr(obj, f.name)
        if isinstance(current, str):
            changes[f.name] = str(raw)
        elif isinstance(current, int) and not isinstance(current, bool):
            x = to_float(raw, f"{where}{f.name}")
            if x != int(x):
                raise InputError(f"{where}{f.name}", f"must be a whole number, got {raw!r}")
            changes[f.name] = int(x)
        else:
            changes[f.name] = to_float(raw, f"{where}{f.name}")
        used.add(f.name)
    new = dataclasses.replace(obj, **changes)  # type: ignore[type-var]
    return validate(new, where), used


def as_dict(obj: Any) -> dict[str, Any]:
    """Field name -> value, for the JSON `params` echo."""
    return {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}
