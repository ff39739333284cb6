"""Point numba's on-disk cache at a folder keyed by the package's source files.

numba's `cache=True` keys a compiled function on its own file only: when a kernel inlines a
jitted helper from another module (a tire curve, a fuzzy surface) and that module changes, the
stale machine code is loaded and can read memory with the old layout. Keying the cache folder on
every source file of the package (path, size, mtime) makes any change start a fresh cache.
Takes effect only if numba has not been imported yet and NUMBA_CACHE_DIR is not set.
"""

from __future__ import annotations

import functools
import hashlib
import os
import shutil
import sys
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


def cache_base() -> Path:
    """The package's cache folder ($XDG_CACHE_HOME/chassistune, else ~/.cache/chassistune)."""
    return Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "chassistune"


def configure() -> None:
    """Set NUMBA_CACHE_DIR (unless set, or numba already imported) to a source-keyed folder."""
    if "NUMBA_CACHE_DIR" in os.environ or "numba" in sys.modules:
        return
    base = cache_base()
    target = base / f"numba-{source_key()}"
    os.environ["NUMBA_CACHE_DIR"] = str(target)
    _prune(base, keep=target)


def _prune(base: Path, keep: Path, max_age_s: float = 7 * 86400) -> None:
    """Remove caches of other source versions unused for a week (best effort)."""
    now = time.time()
    try:
        old = [p for p in base.glob("numba-*") if p != keep and now - p.stat().st_mtime > max_age_s]
    except OSError:
        return
    for path in old:
        shutil.rmtree(path, ignore_errors=True)


COLD_COMPILE_S = 20
"""About how long the first simulation of a plant takes to compile its kernels on an idle 2-core
machine (measured: 17 s single-wheel ABS, 17 s quarter car; several times that under load)."""


def is_cold(plant: str) -> bool:
    """True when the kernel cache holds no compiled kernel of `plant` yet (its kernel module is
    `sim/<plant>_kernel.py` by convention): its next simulation compiles first."""
    folder = os.environ.get("NUMBA_CACHE_DIR")
    if not folder:
        return False
    stem = plant.replace("-", "_") + "_kernel"
    try:
        return not any(Path(folder).rglob(f"{stem}.*.nbi"))
    except OSError:
        return True
