"""`study report` on a disk that fills while it writes, and stopped by Ctrl-C: the page, its
tables and its figures are one set of files, so a report that cannot be written whole leaves the
previous one as it was, and no temporary file behind."""

from __future__ import annotations

import errno
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from chassistune._rng import make_rng
from chassistune.reports.build import REPORT_NAME, build_report
from fs_helpers import mounted_tmpfs


@pytest.fixture
def disk(tmp_path: Path) -> Iterator[Path]:
    """An 8 MiB tmpfs, or a skip where mounting is not allowed."""
    with mounted_tmpfs(tmp_path, "8m") as mounted:
        yield mounted


def _files(root: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(root)): p.read_bytes()
        for p in sorted(root.rglob("*"))
        if p.is_file() and p.name != "filler"
    }


def test_a_report_that_fills_the_disk_leaves_the_previous_one_whole(reported, disk):
    study = disk / "study"
    study.mkdir()
    shutil.copy(reported.dir / "study.sqlite", study / "study.sqlite")
    first = build_report(study)
    before = _files(study)
    assert first.html.name == REPORT_NAME and len(first.figures) > 2 and len(first.tables) > 2
    st = os.statvfs(disk)
    half = sum(len(v) for k, v in before.items() if k != "study.sqlite") // 2
    (disk / "filler").write_bytes(b"\0" * max(0, st.f_bavail * st.f_frsize - half))
    with pytest.raises(OSError) as exc:
        build_report(study)
    assert exc.value.errno == errno.ENOSPC
    assert exc.value.filename is not None
    named = Path(exc.value.filename).relative_to(study).parts
    assert not any(part.startswith(".") for part in named)  # the file, not its temporary
    assert _files(study) == before  # no file changed, none added (no temporaries)


@pytest.mark.slow
def test_ctrl_c_at_a_random_moment_of_a_report_leaves_no_temporary(reported, tmp_path):
    """A real Ctrl-C (SIGINT to the command) while the figures are drawn: exit 130, and the
    folder holds the previous report unchanged or the new one whole, never a hidden .tmp.png."""
    study = tmp_path / "study"
    study.mkdir()
    shutil.copy(reported.dir / "study.sqlite", study / "study.sqlite")
    command = [sys.executable, "-m", "chassistune.cli", "study", "report", str(study)]
    start = time.monotonic()
    subprocess.run(command, check=True, capture_output=True)
    wall_s = time.monotonic() - start
    before = _files(study)
    rng = make_rng(2415)
    for delay_s in rng.uniform(0.4 * wall_s, 0.9 * wall_s, 2):
        proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        time.sleep(float(delay_s))
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
        if proc.returncode == -signal.SIGINT:
            # The signal met the interpreter's shutdown, after the command had finished: Python
            # restores the default action there, so the process ends by the signal (a shell
            # reports 130). Only a command that printed its last line ("wrote .../report.html
            # (N tables, ...)") may end this way.
            last = out.decode().splitlines()[-1]
            assert last.startswith("wrote ") and f"{REPORT_NAME} (" in last, err
        else:
            assert proc.returncode in (0, 130), err
        hidden = [p for p in study.rglob(".*")]
        assert hidden == []
        after = _files(study)
        assert set(after) == set(before)  # the same files: the previous set or the new one
        if proc.returncode == 130:
            assert err.decode().splitlines()[-1] == "chassistune: interrupted"
            assert after == before
