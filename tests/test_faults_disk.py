"""A full disk: on a real small tmpfs (mounted here when the machine allows it), every command's
files appear whole or not at all, and the one error line names the file. Without permission
to mount, a per-file size limit (RLIMIT_FSIZE) injects the same write error at a random size."""

from __future__ import annotations

import errno
import json
import os
import resource
from collections.abc import Iterator
from pathlib import Path

import pandas as pd
import pytest

from chassistune._rng import make_rng
from chassistune.reports.outputs import write_tune_outputs
from chassistune.reports.tables import write_table
from chassistune.tuning.problem import build_problem
from chassistune.tuning.run import TuneResult, run_optimizer
from fs_helpers import mounted_tmpfs

PNG_END = b"IEND\xaeB`\x82"
TUNE_FILES = {
    "best_gains.json",
    "tune.json",
    "history.csv",
    "convergence.png",
    "response-dry-concrete.png",
}


@pytest.fixture(scope="module")
def tuned() -> TuneResult:
    problem = build_problem("abs-wheel", "pid", roads=["dry-concrete"])
    return run_optimizer(problem, "pso", 4, None, 8, 0)


@pytest.fixture(scope="module")
def small_disk(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """A 512 KiB tmpfs, or a skip where mounting is not allowed."""
    with mounted_tmpfs(tmp_path_factory.mktemp("tmpfs"), "512k") as disk:
        yield disk


def _leave_free(disk: Path, free_bytes: int) -> None:
    """Fill `disk` until about `free_bytes` are left (in whole pages)."""
    for p in disk.iterdir():
        p.unlink() if p.is_file() else None
    st = os.statvfs(disk)
    fill = max(0, st.f_bavail * st.f_frsize - free_bytes)
    (disk / "filler").write_bytes(b"\0" * fill)


def _assert_whole(folder: Path, names: set[str]) -> None:
    """Exactly `names` in `folder`, each complete by its format, and no temporaries."""
    assert {p.name for p in folder.iterdir()} == names
    for name in names:
        data = (folder / name).read_bytes()
        if name.endswith(".json"):
            json.loads(data)
        elif name.endswith(".png"):
            assert data.endswith(PNG_END), name
        else:
            assert data.endswith(b"\n"), name


def test_tune_outputs_on_a_disk_that_fills_at_a_random_moment(small_disk, tuned):
    rng = make_rng(2403)
    outcomes = set()
    for free in [0, *rng.integers(0, 200_000, 4).tolist(), 400_000]:
        _leave_free(small_disk, int(free))
        out = small_disk / "tuned"
        try:
            written = write_tune_outputs(tuned, str(out))
        except OSError as exc:
            assert exc.errno == errno.ENOSPC
            assert os.path.dirname(exc.filename) == str(out)
            assert os.path.basename(exc.filename) in TUNE_FILES
            assert not out.exists()  # the folder it created, removed with the set
            outcomes.add("refused")
        else:
            assert {os.path.basename(p) for p in written} == TUNE_FILES
            _assert_whole(out, TUNE_FILES)
            outcomes.add("written")
        if out.exists():
            for p in out.iterdir():
                p.unlink()
            out.rmdir()
    assert outcomes == {"refused", "written"}


def test_each_command_names_the_file_the_full_disk_refused(cli, small_disk):
    _leave_free(small_disk, 0)
    out = small_disk / "t"
    r = cli(
        "tune", "abs-wheel", "--controller", "pid", "--optimizer", "pso",
        "--pop", "4", "--evals", "8", "--out", str(out),
    )  # fmt: skip
    assert (r.code, r.out) == (2, "")
    assert r.err.splitlines()[-1] == (
        f"chassistune: error: {out}/best_gains.json: No space left on device"
    )
    assert not out.exists()
    r = cli("export", "--controller", "pid", "--format", "c", "--out", str(small_disk / "c"))
    assert (r.code, r.out) == (2, "")
    assert r.err.startswith(f"chassistune: error: {small_disk}/c/") and r.err.endswith(
        ": No space left on device\n"
    )
    assert not (small_disk / "c").exists()
    target = small_disk / "runs.csv"
    with pytest.raises(OSError) as exc:
        write_table(pd.DataFrame({"x": range(10_000)}), str(target))  # `study export`
    assert (exc.value.errno, exc.value.filename) == (errno.ENOSPC, str(target))
    assert [p.name for p in small_disk.iterdir()] == ["filler"]


def test_a_file_size_limit_at_a_random_size_leaves_all_or_none(tmp_path, tuned):
    """The fault-injecting writer where no tmpfs can be mounted: RLIMIT_FSIZE makes the write
    that crosses the limit fail (EFBIG; Python ignores SIGXFSZ)."""
    rng = make_rng(2404)
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    outcomes = set()
    for k, limit in enumerate([1, *rng.integers(2, 150_000, 3).tolist(), 10_000_000]):
        out = tmp_path / f"t{k}"
        resource.setrlimit(resource.RLIMIT_FSIZE, (int(limit), hard))
        try:
            write_tune_outputs(tuned, str(out))
        except OSError as exc:
            assert exc.errno == errno.EFBIG
            assert os.path.dirname(exc.filename) == str(out)
            assert not out.exists()
            outcomes.add("refused")
        else:
            outcomes.add("written")
        finally:
            resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        if out.exists():
            _assert_whole(out, TUNE_FILES)
    assert outcomes == {"refused", "written"}
