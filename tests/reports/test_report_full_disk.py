"""`study report` on a disk that fills while it writes: the page, its tables and its figures are
one set of files, so a report that cannot be written whole leaves the previous one as it was."""

from __future__ import annotations

import errno
import os
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

from chassistune.reports.build import REPORT_NAME, build_report


@pytest.fixture
def disk(tmp_path: Path) -> Iterator[Path]:
    """An 8 MiB tmpfs, or a skip where mounting is not allowed."""
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=8m", "tmpfs", str(tmp_path)],
        capture_output=True,
        check=False,
    )
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {mounted.stderr.decode().strip()}")
    try:
        yield tmp_path
    finally:
        subprocess.run(["umount", str(tmp_path)], check=False)


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
    assert exc.value.filename is not None and Path(exc.value.filename).parent.is_relative_to(study)
    assert not Path(exc.value.filename).name.startswith(".")  # the file, not its temporary
    assert _files(study) == before  # no file changed, none added (no temporaries)
