"""A tune result as saved (`tune --out`'s tune.json): read and checked, so that a damaged or
edited file is refused naming its key rather than crashing a later command or being completed
with the registry's default gains (`results.load_tune`, `export SOURCE`)."""

from __future__ import annotations

import math
from typing import Any

from chassistune.errors import InputError

TUNE_KEYS = ("plant", "preset", "roads", "controller", "best_gains", "params")
"""What a tune result holds at least (tune.json, the best-so-far of an interrupted tune)."""


def read_tune_json(file: str, field: str) -> dict[str, Any]:
    """The checked document of a tune.json (`check_tune`); InputError naming `field`."""
    from chassistune.params import read_json

    return check_tune(read_json(file, field), field, file)


def check_tune(doc: object, field: str, file: str) -> dict[str, Any]:
    """`doc` if it holds TUNE_KEYS with the types a tune writes (a null preset: the plant's
    default) and its best_gains hold every gain of its controller as a finite number; else
    InputError naming `field`, the file and the key."""
    from chassistune.controllers import catalogue

    if not isinstance(doc, dict) or any(k not in doc for k in TUNE_KEYS):
        raise InputError(field, f"{file!r} is not a tune result (needs {', '.join(TUNE_KEYS)})")

    def bad(key: str, problem: str) -> InputError:
        return InputError(field, f"{file}: {key}: {problem}")

    for key in ("plant", "preset", "controller"):
        if not isinstance(doc[key], str) and not (key == "preset" and doc[key] is None):
            raise bad(key, f"expected a name, got {doc[key]!r}")
    roads = doc["roads"]
    if not isinstance(roads, list) or not roads or not all(isinstance(r, str) for r in roads):
        raise bad("roads", f"expected a non-empty list of road names, got {roads!r}")
    for key in ("best_gains", "params"):
        if not isinstance(doc[key], dict):
            raise bad(key, f"expected an object of name -> value, got {doc[key]!r}")
    for name, value in doc["best_gains"].items():
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise bad(f"best_gains.{name}", f"expected a number, got {value!r}")
        if not math.isfinite(value):
            raise bad(f"best_gains.{name}", f"must be finite, got {value!r}")
    try:
        spec = catalogue.get(doc["plant"], doc["controller"])
    except InputError as exc:
        raise bad("controller", exc.problem) from None
    missing = [n for n in spec.gain_names if n not in doc["best_gains"]]
    if missing:
        raise bad(
            f"best_gains.{missing[0]}",
            f"missing (a tuned {spec.name} has {', '.join(spec.gain_names) or 'no gains'})",
        )
    return doc
