"""cli_field: the one mapping from domain field paths to the words a command line uses."""

from __future__ import annotations

import pytest

from chassistune.cli.common import cli_field


@pytest.mark.parametrize(
    ("field", "command", "words"),
    [
        ("params.dt_s", None, "--param dt_s"),
        ("gains.kp", "tune", "--gains kp"),
        ("roads", "tune", "--road"),
        ("plant", "simulate", "PLANT"),
        ("plant", "export", "--plant"),  # export takes the plant as an option
        ("source", "export", "SOURCE"),
        ("out", "export", "--out"),
        ("params.ecu_ts_s", "export", "--param ecu_ts_s"),
        ("bounds.kp", "tune", "bounds.kp"),  # no command-line word: the path itself
        ("params.tir:12", "tire", "params.tir:12"),  # a file's line, not a field
    ],
)
def test_field_paths_become_the_commands_words(field: str, command: str | None, words: str) -> None:
    assert cli_field(field, command) == words
