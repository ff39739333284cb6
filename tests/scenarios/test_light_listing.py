"""Listing presets and roads reads the plants' light modules only: no numba, no kernel, no
scenario builder is imported (PlantSpec.presets / .roads point at data, not at the kernels)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from chassistune.scenarios.registry import plant_names, plant_presets, plant_roads, plant_spec

HEAVY = (
    "numba",
    "chassistune.sim.abs_wheel_kernel",
    "chassistune.sim.quarter_car_kernel",
    "chassistune.sim.abs_vehicle_kernel",
    "chassistune.fuzzy.sets",
    "chassistune.scenarios.abs_wheel",
    "chassistune.scenarios.quarter_car",
)

PROBE = """
import json, sys
from chassistune.cli import main
try:
    main({args!r})
except SystemExit as exc:
    code = exc.code
print(json.dumps([code, sorted(m for m in {heavy!r} if m in sys.modules)]), file=sys.stderr)
"""


def _heavy_imports(*args: str) -> list[str]:
    """The heavy modules a CLI call imported (it must exit 0)."""
    done = subprocess.run(
        [sys.executable, "-c", PROBE.format(args=list(args), heavy=HEAVY)],
        capture_output=True,
        text=True,
        check=True,
    )
    code, heavy = json.loads(done.stderr.strip().splitlines()[-1])
    assert code == 0, done.stderr
    assert done.stdout
    return list(heavy)


@pytest.mark.parametrize("args", [("list", "roads"), ("list", "roads", "--json")])
def test_list_roads_imports_no_numba(args: tuple[str, ...]) -> None:
    assert _heavy_imports(*args) == []


def test_list_presets_imports_no_numba() -> None:
    assert _heavy_imports("list", "presets") == []


@pytest.mark.parametrize("plant", ["abs-wheel", "quarter-car"])
def test_a_plants_presets_import_no_numba(plant: str) -> None:
    code = (
        f"import sys\nfrom chassistune.scenarios.registry import plant_presets\n"
        f"assert plant_presets({plant!r})\n"
        f"print(sorted(m for m in {HEAVY!r} if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


@pytest.mark.parametrize("plant", plant_names())
def test_the_listed_presets_name_listed_roads(plant: str) -> None:
    presets, roads = plant_presets(plant), plant_roads(plant)
    assert plant_spec(plant).default_preset in presets
    for info in presets.values():
        assert info.roads and set(info.roads) <= set(roads), info.name
