"""chassistune._io: the atomic writer respects the umask and never leaves half a file."""

from __future__ import annotations

import json
import math
import os
import stat
from pathlib import Path

import numpy as np
import pytest

from chassistune._io import atomic_path, dumps, jsonable, write_json, write_text


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


def test_temporary_keeps_the_suffix_and_lives_beside_the_target(tmp_path: Path) -> None:
    with atomic_path(tmp_path / "fig.png") as tmp:
        assert Path(tmp).parent == tmp_path and tmp.endswith(".png")
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
