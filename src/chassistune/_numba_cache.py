"""Point numba's on-disk cache at a folder keyed by the package's source files.

numba's `cache=True` keys a compiled function on its own file only: when a kernel inlines a
jitted helper from another module (a tire curve, a fuzzy surface) and that module changes, the
stale machine code is loaded and can read memory with the old layout. Keying the cache folder on
every source file of the package (path, size, mtime) makes any change start a fresh cache.
Takes effect only if numba has not been imported yet; a NUMBA_CACHE_DIR the user set is kept
when numba can write it.
"""

from __future__ import annotations

import atexit
import functools
import hashlib
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path


@functools.cache
def source_key() -> str:
    """16 hex digits naming this version of the package's sources (every .py file's path, size
    and mtime): anything cached from the sources is valid while this key is unchanged."""
    root = Path(__file__).resolve().parent
    digest = hashlib.sha1()
    for path in sorted(root.rglob("*.py")):
        st = path.stat()
        digest.update(f"{path.relative_to(root)}:{st.st_size}:{st.st_mtime_ns};".encode())
    return digest.hexdigest()[:16]


def _preferred_base() -> Path:
    """$XDG_CACHE_HOME/chassistune (an absolute XDG_CACHE_HOME only, as the XDG spec says), else
    ~/.cache/chassistune."""
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    if os.path.isabs(xdg):
        return Path(xdg) / "chassistune"
    return Path.home() / ".cache" / "chassistune"


def _unusable(folder: Path) -> str | None:
    """Why a cache could not be kept in `folder` (None when it can): a file in the way, or no
    write permission on the folder or, if it does not exist yet, on its nearest existing
    ancestor (numba creates it). Nothing is created."""
    try:
        probe = folder.absolute()
        while not probe.exists():
            probe = probe.parent
        if not probe.is_dir():
            return f"{probe} is not a folder"
        if not os.access(probe, os.W_OK | os.X_OK):
            return f"{probe} is not writable"
    except OSError as exc:
        return exc.strerror or str(exc)
    return None


_WARNED: set[str] = set()


def _fallback(reason: str) -> Path:
    """This process's temporary cache folder (created on first use, removed at exit), with one
    stderr line per distinct `reason` saying why it is used."""
    if reason not in _WARNED:
        _WARNED.add(reason)
        sys.stderr.write(
            f"chassistune: warning: {reason}; caching in the temporary folder "
            f"{_temporary_folder()} instead, removed at exit (kernels compile again next run)\n"
        )
    return _temporary_folder()


_temporary: Path | None = None


def _temporary_folder() -> Path:
    global _temporary
    if _temporary is None:
        _temporary = Path(tempfile.mkdtemp(prefix="chassistune-cache-"))
        atexit.register(shutil.rmtree, _temporary, ignore_errors=True)
    return _temporary


def numba_cache_is_temporary() -> bool:
    """True when numba caches into this process's temporary fallback folder (nothing compiled
    now outlives the run)."""
    folder = os.environ.get("NUMBA_CACHE_DIR", "")
    return _temporary is not None and Path(folder).is_relative_to(_temporary)


def cache_base() -> Path:
    """The package's cache folder ($XDG_CACHE_HOME/chassistune, else ~/.cache/chassistune), or,
    when that cannot be used (a file in the way, no permission, no home), a temporary folder
    removed at exit, with one stderr line saying so. Read from the environment at each call."""
    try:
        base = _preferred_base()
    except RuntimeError as exc:  # Path.home(): no HOME and no password entry
        return _fallback(f"no cache folder ({exc})")
    problem = _unusable(base)
    return base if problem is None else _fallback(f"cache folder {base}: {problem}")


def configure() -> None:
    """Set NUMBA_CACHE_DIR (unless numba is already imported): the folder the user set, else the
    source-keyed folder `cache_base()/numba-<source_key()>`; a folder numba could not write (it
    would silently fall back to `__pycache__` inside the installed sources, outside the
    source-keyed cache) is replaced by a temporary one, with one stderr line saying so. Nothing
    is removed here: `prune` is a step of `chassistune warmup`."""
    if "numba" in sys.modules:
        return
    given = os.environ.get("NUMBA_CACHE_DIR", "")
    folder = Path(given) if given else cache_base() / f"numba-{source_key()}"
    problem = _unusable(folder)
    if problem is not None:
        folder = _fallback(f"NUMBA_CACHE_DIR {folder}: {problem}")
    os.environ["NUMBA_CACHE_DIR"] = str(folder)


def prune(max_age_s: float = 7 * 86400) -> list[Path]:
    """Remove the numba caches of other source versions unused for `max_age_s` (best effort);
    the folders removed."""
    base = cache_base()
    keep = base / f"numba-{source_key()}"
    now = time.time()
    try:
        old = [p for p in base.glob("numba-*") if p != keep and now - p.stat().st_mtime > max_age_s]
    except OSError:
        return []
    for path in old:
        shutil.rmtree(path, ignore_errors=True)
    return [p for p in old if not p.exists()]
