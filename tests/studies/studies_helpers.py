"""Tiny study configs for the tests: the quarter car's exact objective is the cheapest plant."""

from __future__ import annotations

from pathlib import Path

from chassistune.studies.spec import StudyPlan, load_plan

TINY = """
[study]
name = "tiny"
seeds = {seeds}
seed = 11

[[scenarios]]
name = "qc"
plant = "quarter-car"
roads = {roads}
controller = "pid"
objective = "rms-ratio-exact"
bounds = {{ kp = [0.0, 500.0], ki = [0.0, 500.0], kd = [0.0, 500.0] }}
{extra}
[[optimizers]]
name = "pso"

[[optimizers]]
name = "de"

[budget]
pop_size = 6
iterations = 3
"""

RAISING = """
[[scenarios]]
name = "boom"
plant = "raising-quarter-car"
controller = "skyhook"
objective = "raises"
"""


def tiny_config(seeds: int | str = 2, roads: str = '["iso-b"]', extra: str = "") -> str:
    return TINY.format(seeds=seeds, roads=roads, extra=extra)


def write_plan(folder: Path, text: str, name: str = "study.toml") -> tuple[Path, StudyPlan]:
    path = folder / name
    path.write_text(text)
    return path, load_plan(path)
