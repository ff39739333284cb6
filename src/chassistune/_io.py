"""File input and output and JSON: one reader of whole input files, one atomic writer and one
JSON normalizer for the whole package.

Input files read whole (road tables, configs, results) are read up to a stated size (`read_input`),
so that a wrong path (`/dev/zero`, a log of gigabytes) is refused instead of filling memory; a
UTF-8 byte-order mark, as spreadsheet programs write it, is dropped.

Atomic: the data goes to a temporary file beside the target (in a hidden folder of the same
folder, so the final `os.replace` is a rename on one file system) and replaces the target only
once complete; on any error the temporary is removed and the target is left as it was. Files
that belong together (a tune's outputs, an export, a report) are staged as one `file_set` and
renamed into place together once all are written. An OSError while writing names the target,
not the temporary. The temporary file is created with mode 0o666 less the umask, as a plain
`open(path, "w")` would (tempfile.mkstemp would give 0o600).
"""

from __future__ import annotations

import json
import math
import os
import secrets
import shutil
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from chassistune._interrupt import on_interrupt
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


_live: set[Path] = set()
"""Hidden folders holding a temporary file not yet renamed into place or removed."""
_renaming = threading.Lock()
"""Held while a temporary is created, while a set is renamed into place and while Ctrl-C removes
the temporaries: a set interrupted by Ctrl-C is either wholly in place or not at all."""
_stopper: int | None = None
"""The thread that ran the Ctrl-C hook; any other thread that would write a file after it waits
for the end of the process instead (which comes at once: `_interrupt` calls os._exit)."""


def _remove_temporaries() -> None:
    """The Ctrl-C hook: remove every temporary file with its hidden folder (the process ends
    without unwinding; a writer still holding a temporary's path can no longer create it) and
    stop the other threads from making new ones."""
    global _stopper
    with _renaming:
        _stopper = threading.get_ident()
        for folder in list(_live):
            shutil.rmtree(folder, ignore_errors=True)
        _live.clear()


on_interrupt(_remove_temporaries)


def _stopped() -> bool:
    """Whether Ctrl-C stopped the writes of this thread (with `_renaming` held)."""
    return _stopper is not None and _stopper != threading.get_ident()


def _wait_for_exit() -> None:
    """Park this thread: the Ctrl-C watcher ends the process in a moment."""
    threading.Event().wait()


def _create_beside(path: Path) -> Path:
    """A new empty file named as `path`, in a new hidden folder beside it (`.NAME.HEX.tmp`),
    with the umask's mode."""
    while True:
        folder = path.with_name(f".{path.name}.{secrets.token_hex(6)}.tmp")
        tmp = folder / path.name
        with _renaming:
            stopped = _stopped()
            if not stopped:
                try:
                    folder.mkdir(0o700)
                except FileExistsError:  # pragma: no cover - 48 random bits
                    continue
                except OSError as exc:
                    raise _naming(exc, path, folder) from None
                _live.add(folder)
                try:
                    os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
                except OSError as exc:
                    raise _naming(exc, path, folder) from None
                return tmp
        _wait_for_exit()


def _naming(exc: OSError, target: Path, folder: Path) -> OSError:
    """`exc` about the file `target` (one line of the CLI names it) when it was about no file
    or about the temporary in `folder` standing in for it (a full disk: `No space left on
    device`)."""
    if exc.filename is not None and not os.fspath(exc.filename).startswith(str(folder)):
        return exc
    return OSError(exc.errno, exc.strerror or str(exc), str(target))


class FileSet:
    """Files written as one (`file_set`): each to a temporary twin beside its target; all
    renamed into place at the end, or all removed."""

    def __init__(self) -> None:
        self._staged: list[tuple[Path, Path]] = []

    @contextmanager
    def path(self, target: str | os.PathLike[str]) -> Iterator[str]:
        """Yield the temporary path standing in for `target` (same name, in a hidden folder
        beside it): write it in the block; an OSError about it is raised about `target`."""
        where = Path(target)
        tmp = _create_beside(where)
        self._staged.append((tmp, where))
        try:
            yield str(tmp)
        except OSError as exc:
            with _renaming:
                stopped = _stopped()
            if stopped:  # Ctrl-C removed the temporary under the writer: no error to report
                _wait_for_exit()
            raise _naming(exc, where, tmp.parent) from None

    def write_bytes(self, target: str | os.PathLike[str], data: bytes) -> None:
        """Stage `data` as the content of `target`."""
        with self.path(target) as tmp, open(tmp, "wb") as fh:
            fh.write(data)

    def write_text(
        self, target: str | os.PathLike[str], text: str, newline: str | None = None
    ) -> None:
        """Stage `text` (UTF-8) as the content of `target`."""
        with self.path(target) as tmp, open(tmp, "w", encoding="utf-8", newline=newline) as fh:
            fh.write(text)

    def write_json(self, target: str | os.PathLike[str], obj: Any, indent: int | None = 1) -> None:
        """Stage `obj` as a JSON file (normalized by `jsonable`, one final newline)."""
        self.write_text(target, dumps(obj, indent=indent) + "\n")

    def _commit(self) -> None:
        with _renaming:
            stopped = _stopped()
            if not stopped:
                if any(tmp.parent not in _live for tmp, _ in self._staged):
                    raise KeyboardInterrupt  # Ctrl-C removed some before the set was complete
                for tmp, target in self._staged:
                    try:
                        os.replace(tmp, target)
                    except OSError as exc:
                        raise _naming(exc, target, tmp.parent) from None
                for tmp, _ in self._staged:
                    tmp.parent.rmdir()
                    _live.discard(tmp.parent)
                return
        _wait_for_exit()

    def _discard(self) -> None:
        for tmp, _ in self._staged:
            shutil.rmtree(tmp.parent, ignore_errors=True)
            _live.discard(tmp.parent)


@contextmanager
def file_set(folder: str | os.PathLike[str] | None = None) -> Iterator[FileSet]:
    """Yield a `FileSet` to stage files in; when the block ends without an exception they all
    replace their targets, else none does and the temporaries are removed. `folder` is created
    first if missing (with its parents), and removed again on failure.

    All or nothing against errors (a full disk), exceptions and Ctrl-C (the CLI's hook waits for
    a set being renamed and removes the temporaries of the others); a SIGKILL can leave hidden
    temporaries and, during the renames of a set, part of it, each file whole."""
    created = _make_folder(Path(folder)) if folder is not None else None
    staged = FileSet()
    try:
        yield staged
        staged._commit()
    except BaseException:
        if created is not None:
            shutil.rmtree(created, ignore_errors=True)
        raise
    finally:
        staged._discard()


def _make_folder(folder: Path) -> Path | None:
    """Create `folder` with its parents; the topmost folder created (None: it existed)."""
    full = folder.absolute()
    created = next((p for p in reversed(full.parents) if not p.exists()), None)
    if created is None and not full.exists():
        created = full
    try:
        full.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        if created is not None:
            shutil.rmtree(created, ignore_errors=True)
        raise OSError(exc.errno, exc.strerror or str(exc), str(folder)) from None
    return created


@contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[str]:
    """Yield a temporary file path beside `path` (same suffix); it replaces `path` on success
    (a set of one file)."""
    with file_set() as staged, staged.path(path) as tmp:
        yield tmp


def write_text(path: str | os.PathLike[str], text: str, newline: str | None = None) -> None:
    """Write `text` (UTF-8) to `path` atomically."""
    with file_set() as staged:
        staged.write_text(path, text, newline)


def write_json(path: str | os.PathLike[str], obj: Any, indent: int | None = 1) -> None:
    """`obj` as a JSON file (normalized by `jsonable`, one final newline), atomically."""
    with file_set() as staged:
        staged.write_json(path, obj, indent)


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
