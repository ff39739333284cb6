"""A study config (the validated, JSON-ready dict) written back as TOML text for the report.

Covers what a config holds: tables, arrays of tables, strings, numbers, booleans, lists and
inline tables. Keys whose value is None (TOML has no null: the default applies) are left out.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from typing import Any

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return ("inf" if v > 0 else "-inf") if math.isinf(v) else "nan" if v != v else repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_value(x) for x in v if x is not None) + "]"
    if isinstance(v, Mapping):
        return (
            "{ "
            + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items() if x is not None)
            + " }"
            if v
            else "{}"
        )
    raise TypeError(f"cannot write {type(v).__name__} as TOML")


def _body(table: Mapping[str, Any]) -> list[str]:
    return [f"{_key(k)} = {_value(v)}" for k, v in table.items() if v is not None]


def to_toml(config: Mapping[str, Any]) -> str:
    """TOML text of `config`: top-level dicts become [tables], lists of dicts [[arrays]]."""
    lines = _body(
        {k: v for k, v in config.items() if not isinstance(v, Mapping) and not _is_table_array(v)}
    )
    for name, v in config.items():
        if isinstance(v, Mapping):
            lines += ["", f"[{_key(name)}]", *_body(v)]
        elif _is_table_array(v):
            for item in v:
                lines += ["", f"[[{_key(name)}]]", *_body(item)]
    return "\n".join(lines).lstrip("\n") + "\n"


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, Mapping) for x in v)
