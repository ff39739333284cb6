"""File input and output and JSON: one reader of whole input files, one atomic writer and one
JSON normalizer for the whole package.

Input files read whole (road tables, configs, results) are read up to a stated size (`read_input`),
so that a wrong path (`/dev/zero`, a log of gigabytes) is refused instead of filling memory; a
UTF-8 byte-order mark, as spreadsheet programs write it, is dropped.

Atomic: the data goes to a temporary file beside the target (same folder, so the final
`os.replace` is a rename on one file system) and replaces the target only once complete; on any
error the temporary file is removed and the target is left as it was. The temporary file is
created with mode 0o666 less the umask, as a plain `open(path, "w")` would (tempfile.mkstemp
would give 0o600).
"""

from __future__ import annotations

import json
import math
import os
import secrets
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from chassistune.errors import InputError


def read_input(path: str | os.PathLike[str], field: str, max_bytes: int) -> str:
    """The UTF-8 text of an input file (a leading byte-order mark dropped), at most `max_bytes`
    long; InputError naming `field` when it cannot be read, is longer or is not UTF-8."""
    name = os.fspath(path)
    try:
        with open(name, "rb") as fh:
            data = fh.read(max_bytes + 1)
    except OSError as exc:
        raise InputError(field, f"cannot read {name!r}: {exc.strerror or exc}") from None
    if len(data) > max_bytes:
        raise InputError(
            field, f"{name!r} is larger than {max_bytes:,} bytes, the most read for this input"
        )
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise InputError(field, f"{name!r} is not UTF-8 text") from None


def _create_beside(path: Path) -> Path:
    """A new empty file in `path`'s folder, named after it, with the umask's mode."""
    while True:
        tmp = path.with_name(f".{path.stem}.{secrets.token_hex(6)}.tmp{path.suffix}")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:  # pragma: no cover - 48 random bits
            continue
        os.close(fd)
        return tmp


@contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[str]:
    """Yield a temporary file path beside `path` (same suffix); it replaces `path` on success."""
    target = Path(path)
    tmp = _create_beside(target)
    try:
        yield str(tmp)
        os.replace(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)


def write_text(path: str | os.PathLike[str], text: str, newline: str | None = None) -> None:
    """Write `text` (UTF-8) to `path` atomically."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline=newline) as fh:
        fh.write(text)


def jsonable(x: Any) -> Any:
    """Plain JSON values: numpy scalars and arrays -> Python, tuples -> lists, keys -> str,
    NaN and +-inf -> None (strict JSON has neither)."""
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return [jsonable(v) for v in x.tolist()]
    if isinstance(x, bool | np.bool_):
        return bool(x)
    if isinstance(x, int | np.integer):
        return int(x)
    if isinstance(x, float | np.floating):
        f = float(x)
        return f if math.isfinite(f) else None
    if isinstance(x, np.str_):
        return str(x)
    return x


def dumps(obj: Any, indent: int | None = None, sort_keys: bool = False) -> str:
    """`obj` normalized by `jsonable`, as strict JSON text."""
    return json.dumps(jsonable(obj), indent=indent, sort_keys=sort_keys, allow_nan=False)


def write_json(path: str | os.PathLike[str], obj: Any, indent: int | None = 1) -> None:
    """`obj` as a JSON file (normalized by `jsonable`, one final newline), atomically."""
    write_text(path, dumps(obj, indent=indent) + "\n")
