"""`chassistune reproduce all --quick --out DIR [ARGS...]` with every config's [quick] table
shrunk to 2 seeds, population 6 and 2 iterations: the kill test's tiny budget (run as a script)."""

from __future__ import annotations

import sys

from chassistune.cli.main import main
from chassistune.papers import reproduce
from chassistune.studies.spec import QuickConfig, StudyConfig

TINY = QuickConfig(seeds=2, pop_size=6, iterations=2)
_shipped = reproduce.shipped_config


def tiny_config(name: str) -> StudyConfig:
    """The shipped config `name` with the tiny [quick] table."""
    return _shipped(name).model_copy(update={"quick": TINY})


if __name__ == "__main__":
    reproduce.shipped_config = tiny_config
    main(["reproduce", "all", "--quick", "--out", *sys.argv[1:]])
