"""Parameter dataclasses: override by name from strings (`--param NAME=VALUE`), validate, echo.

Every plant, road, solver and controller parameter is a field of a frozen dataclass. Field
metadata `{"positive": True}`, `{"nonnegative": True}` or `{"unit_interval": True}` state the
valid range; every float must be finite.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, TypeVar

from chassistune.errors import InputError

T = TypeVar("T")


def parse_assignments(items: list[str] | tuple[str, ...], field: str) -> dict[str, str]:
    """Parse ["a=1", "b=x"] into {"a": "1", "b": "x"}; `field` names the option for errors."""
    out: dict[str, str] = {}
    for item in items:
        for part in item.split(",") if field == "--gains" else [item]:
            name, sep, value = part.partition("=")
            name, value = name.strip(), value.strip()
            if not sep or not name or not value:
                raise InputError(field, f"expected NAME=VALUE, got {part!r}")
            out[name] = value
    return out


def to_float(value: object, field: str) -> float:
    """A finite float from a string or number, else InputError naming `field`."""
    try:
        x = float(value)  # type: ignore[arg-type]
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
