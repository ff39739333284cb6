"""Where numba's cache goes (`_numba_cache`): an unusable folder falls back to a temporary one
and says so, `--help` never depends on the cache, importing the package removes nothing."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

import chassistune

PACKAGE = Path(chassistune.__file__).resolve().parent

PROBE = """
import json, os
import chassistune
from chassistune.sim.lti import expm_small
print(json.dumps({"env": os.environ["NUMBA_CACHE_DIR"], "numba": expm_small._cache.cache_path}))
"""


def _env(tmp_path: Path, **changes: str) -> dict[str, str]:
    """The test's environment without a NUMBA_CACHE_DIR, with `changes`, the cache home in
    `tmp_path` unless changed."""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path / "cache-home")
    env.update(changes)
    return env


def _run(code: str, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)


@pytest.fixture
def a_file(tmp_path: Path) -> Path:
    path = tmp_path / "a-file"
    path.write_text("not a folder\n")
    return path


@pytest.mark.parametrize("variable", ["NUMBA_CACHE_DIR", "XDG_CACHE_HOME", "HOME"])
def test_an_unusable_cache_folder_falls_back_to_a_temporary_one(
    tmp_path: Path, a_file: Path, variable: str
) -> None:
    """A file where the cache folder should be: numba caches into a fresh temporary folder (not
    `__pycache__` inside the installed sources), one stderr line says why, and the folder is
    gone after the run."""
    env = _env(tmp_path, **{variable: str(a_file)})
    if variable == "HOME":
        del env["XDG_CACHE_HOME"]
    done = _run(PROBE, env)
    assert done.returncode == 0, done.stderr
    seen = json.loads(done.stdout)
    numba_dir = Path(seen["numba"])
    assert numba_dir.is_relative_to(Path(tempfile.gettempdir()))
    assert not numba_dir.is_relative_to(PACKAGE)
    assert not numba_dir.is_relative_to(a_file)
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("chassistune: warning: ")
    assert str(a_file) in lines[0] and "temporary folder" in lines[0]
    assert not Path(seen["env"]).exists()  # removed at exit


@pytest.mark.parametrize("variable", ["XDG_CACHE_HOME", "HOME"])
def test_help_does_not_depend_on_the_cache(tmp_path: Path, a_file: Path, variable: str) -> None:
    env = _env(tmp_path, **{variable: str(a_file)})
    if variable == "HOME":
        del env["XDG_CACHE_HOME"]
    done = _run("from chassistune.cli.main import main; main(['simulate', '--help'])", env)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("Usage: chassistune simulate")


def _old_cache(base: Path, name: str, age_s: float) -> Path:
    folder = base / "chassistune" / name
    folder.mkdir(parents=True)
    (folder / "kernel.nbi").write_bytes(b"")
    then = time.time() - age_s
    os.utime(folder, (then, then))
    return folder


def test_import_removes_no_cache_folder(tmp_path: Path) -> None:
    """Importing only points numba at the source-keyed folder (silently, when it is usable):
    every file and folder of the cache home is still there afterwards, the caches of other
    sources unused for a month included (pruning them is a step of `warmup`)."""
    home = tmp_path / "cache-home"
    old = _old_cache(home, "numba-0000000000000000", 30 * 86400)
    _old_cache(home, "numba-1111111111111111", 86400)
    (home / "chassistune" / "choices.json").write_text("{}")
    before = sorted(home.rglob("*"))
    done = _run(PROBE, _env(tmp_path))
    assert done.returncode == 0 and done.stderr == ""
    assert set(before) <= set(home.rglob("*"))
    numba_dir = Path(json.loads(done.stdout)["numba"])
    assert numba_dir.relative_to(home / "chassistune").parts[0] != old.name


def test_prune_removes_only_other_versions_unused_for_a_week(tmp_path: Path) -> None:
    home = tmp_path / "cache-home"
    old = _old_cache(home, "numba-0000000000000000", 30 * 86400)
    recent = _old_cache(home, "numba-1111111111111111", 86400)
    code = (
        "import os\n"
        "from chassistune._numba_cache import prune\n"
        "print([p.name for p in prune()], os.environ['NUMBA_CACHE_DIR'])"
    )
    done = _run(code, _env(tmp_path))
    assert done.returncode == 0, done.stderr
    removed, current = done.stdout.split("] ")
    assert removed == "['numba-0000000000000000'"
    assert not old.exists() and recent.exists()
    assert Path(current.strip()).parent == home / "chassistune"
