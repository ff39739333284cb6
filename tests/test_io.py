"""chassistune._io: the atomic writer respects the umask and never leaves half a file."""

from __future__ import annotations

import errno
import json
import math
import os
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from chassistune._io import (
    _remove_temporaries,
    atomic_path,
    dumps,
    file_set,
    jsonable,
    write_json,
    write_text,
)
from chassistune._rng import make_rng


@pytest.mark.parametrize("mask", [0o022, 0o077, 0o002])
def test_new_file_mode_follows_the_umask(tmp_path: Path, mask: int) -> None:
    old = os.umask(mask)
    try:
        write_text(tmp_path / "a.txt", "x")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "a.txt").stat().st_mode) == 0o666 & ~mask


def test_failure_keeps_the_old_file_and_leaves_no_temporary(tmp_path: Path) -> None:
    target = tmp_path / "out.json"
    write_text(target, "old\n")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        Path(tmp).write_text("half")
        raise RuntimeError("interrupted")
    assert target.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]


def test_temporary_keeps_the_name_and_lives_in_a_hidden_folder_beside_the_target(
    tmp_path: Path,
) -> None:
    with atomic_path(tmp_path / "fig.png") as tmp:
        assert Path(tmp).name == "fig.png" and Path(tmp).parent.parent == tmp_path
        assert Path(tmp).parent.name.startswith(".fig.png.")
        Path(tmp).write_bytes(b"png")
    assert (tmp_path / "fig.png").read_bytes() == b"png"


def test_jsonable_converts_numpy_and_non_finite_values() -> None:
    data = {
        1: np.float64(0.5),
        "a": np.arange(3),
        "b": (np.int64(2), np.bool_(True)),
        "nan": math.nan,
        "inf": np.array([np.inf, -1.0]),
        "s": np.str_("x"),
        "n": None,
    }
    out = jsonable(data)
    assert out == {
        "1": 0.5,
        "a": [0, 1, 2],
        "b": [2, True],
        "nan": None,
        "inf": [None, -1.0],
        "s": "x",
        "n": None,
    }
    assert type(out["a"][0]) is int and type(out["1"]) is float
    assert json.loads(dumps(data)) == out


def test_write_json_round_trips_floats_exactly(tmp_path: Path) -> None:
    x = [0.1 + 0.2, 1e-300, 2.0**0.5]
    write_json(tmp_path / "x.json", {"x": np.array(x)})
    text = (tmp_path / "x.json").read_text()
    assert text.endswith("}\n") and json.loads(text)["x"] == x


# -- sets of files -----------------------------------------------------------------------------


def test_a_set_is_written_all_or_none(tmp_path: Path) -> None:
    (tmp_path / "a.txt").write_text("old a")
    with pytest.raises(RuntimeError), file_set(tmp_path) as staged:
        staged.write_text(tmp_path / "a.txt", "new a")
        staged.write_text(tmp_path / "b.txt", "new b")
        raise RuntimeError("the third file could not be made")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]
    assert (tmp_path / "a.txt").read_text() == "old a"
    with file_set(tmp_path) as staged:
        staged.write_text(tmp_path / "a.txt", "new a")
        staged.write_bytes(tmp_path / "b.bin", b"\x00b")
        staged.write_json(tmp_path / "c.json", {"c": np.float64(1.5)})
    assert (tmp_path / "a.txt").read_text() == "new a"
    assert (tmp_path / "b.bin").read_bytes() == b"\x00b"
    assert json.loads((tmp_path / "c.json").read_text()) == {"c": 1.5}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.bin", "c.json"]


def test_a_failed_set_removes_the_folders_it_created(tmp_path: Path) -> None:
    out = tmp_path / "new" / "deeper"
    with pytest.raises(KeyboardInterrupt), file_set(out) as staged:
        staged.write_text(out / "a.txt", "a")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_a_write_error_names_the_target_not_the_temporary(tmp_path: Path) -> None:
    target = tmp_path / "tune.json"
    with pytest.raises(OSError) as exc, file_set() as staged, staged.path(target):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    assert (exc.value.errno, exc.value.filename) == (errno.ENOSPC, str(target))
    assert list(tmp_path.iterdir()) == []


def test_ctrl_c_removes_the_temporaries_and_stops_an_unfinished_set(tmp_path: Path) -> None:
    """What the CLI's Ctrl-C hook does while a set is being written: nothing of it appears."""
    with pytest.raises(KeyboardInterrupt), file_set(tmp_path) as staged:
        staged.write_text(tmp_path / "a.txt", "a")
        _remove_temporaries()  # the hook, run by the watcher thread on Ctrl-C
        staged.write_text(tmp_path / "b.txt", "b")
    assert list(tmp_path.iterdir()) == []


WRITER = """
import os, sys
from pathlib import Path
from chassistune._interrupt import install
from chassistune._io import file_set

install()
out = Path(sys.argv[1])
print("ready", flush=True)
for k in range(1, 1_000_000):
    with file_set(out) as staged:
        for name in ("a.bin", "b.bin", "c.bin"):
            staged.write_bytes(out / name, bytes([k % 251]) * 300_000)
"""


def _kill_at_random_moments(tmp_path: Path, signum: int, trials: int) -> list[Path]:
    """Run WRITER and send `signum` after a random delay, `trials` times; the output folders."""
    rng = make_rng(24)
    folders = []
    for trial in range(trials):
        out = tmp_path / f"out{trial}"
        proc = subprocess.Popen(
            [sys.executable, "-c", WRITER, str(out)], stdout=subprocess.PIPE, text=True
        )
        assert proc.stdout is not None and proc.stdout.readline() == "ready\n"
        time.sleep(float(rng.uniform(0.0, 0.3)))
        proc.send_signal(signum)
        code = proc.wait(timeout=60)
        assert code == (130 if signum == signal.SIGINT else -signal.SIGKILL)
        folders.append(out)
    return folders


def _whole_files(out: Path) -> dict[str, int]:
    """Each visible file of `out` -> the one byte value it is made of (asserting it is whole)."""
    values = {}
    for p in out.iterdir() if out.exists() else []:
        if p.name.startswith("."):
            continue
        data = p.read_bytes()
        assert len(data) == 300_000 and data == data[:1] * len(data), p
        values[p.name] = data[0]
    return values


def test_a_killed_writer_leaves_every_file_whole_or_absent(tmp_path: Path) -> None:
    for out in _kill_at_random_moments(tmp_path, signal.SIGKILL, 4):
        assert set(_whole_files(out)) <= {"a.bin", "b.bin", "c.bin"}


def test_ctrl_c_leaves_one_whole_set_and_no_temporaries(tmp_path: Path) -> None:
    for out in _kill_at_random_moments(tmp_path, signal.SIGINT, 4):
        values = _whole_files(out)
        assert set(values) in (set(), {"a.bin", "b.bin", "c.bin"})
        assert len(set(values.values())) <= 1  # the three files of one set, none of another
        hidden = [p.name for p in out.iterdir() if p.name.startswith(".")] if out.exists() else []
        assert hidden == []
