"""The valid choices shown by `--help` (plants, presets, roads, controllers, objectives,
optimizers, rule bases), read from the registries, without making `--help` slow.

Listing them imports every plant (numba, about 1 s of CPU); `--help` takes 0.1 s. So the listing
is computed once per version of the sources (`_numba_cache.source_key`) and kept as a small JSON
file in the package's cache folder (`chassistune warmup` writes it at installation); `--help`
reads that file. Light at import (no numpy), like every CLI module.
"""

from __future__ import annotations

import json
import os
from functools import cache
from pathlib import Path
from typing import Any

import click

CSV_ROADS = "FILE.csv (abs-wheel: a measured mu-slip table, columns slip and mu)"


def collect() -> dict[str, Any]:
    """The choices from the registries (imports every plant and the fuzzy package)."""
    from chassistune.fuzzy.loader import builtin_names, load_rulebase
    from chassistune.optimizers.registry import names as optimizer_names
    from chassistune.scenarios.registry import get_plant, plant_names, plant_spec

    plants = {}
    for name in plant_names():
        plant = get_plant(name)
        scenario = plant.scenario()
        plants[name] = {
            "presets": list(plant.presets()),
            "default_preset": plant_spec(name).default_preset,
            "roads": list(plant.roads()),
            "controllers": [c.name for c in plant.controllers()],
            "objectives": list(scenario.objectives),
            "default_objective": scenario.default_objective,
        }
    rulebases = {}
    for name in builtin_names():
        rb = load_rulebase(name)
        rulebases[name] = {
            "inputs": [v.name for v in rb.inputs],
            "outputs": [v.name for v in rb.outputs],
        }
    return {"plants": plants, "optimizers": optimizer_names(), "rulebases": rulebases}


def _file() -> Path:
    from chassistune._numba_cache import cache_base, source_key

    return cache_base() / f"cli-choices-{source_key()}.json"


@cache
def choices() -> dict[str, Any]:
    """The choices of this version of the sources: from the cache file, else collected now and
    stored (best effort: an unwritable cache only costs the next `--help` the same second)."""
    path = _file()
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        pass
    data = collect()
    store(data, path)
    return data


STALE_AFTER_S = 7 * 86400
"""Choices files of other source versions unused this long are removed (as numba's caches)."""


def store(data: dict[str, Any], path: Path | None = None) -> None:
    """Write the choices file (atomically); remove those of other source versions unused for
    a week (best effort, like the numba cache's pruning)."""
    import time

    path = path or _file()
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp.write_text(json.dumps(data), encoding="utf-8")
        os.replace(tmp, path)
        for old in path.parent.glob("cli-choices-*.json"):
            if old != path and time.time() - old.stat().st_mtime > STALE_AFTER_S:
                old.unlink(missing_ok=True)
    except OSError:
        tmp.unlink(missing_ok=True)


def _per_plant(key: str, default_key: str | None = None) -> list[str]:
    lines = []
    for plant, info in choices()["plants"].items():
        items = [
            f"{x} (default)" if default_key and x == info[default_key] else x for x in info[key]
        ]
        lines.append(f"{plant}: {', '.join(items)}")
    return lines


def describe(kind: str) -> list[str]:
    """The choices of `kind`, one line per plant where they depend on the plant."""
    if kind == "plants":
        return [", ".join(choices()["plants"])]
    if kind == "presets":
        return _per_plant("presets", "default_preset")
    if kind == "roads":
        return [*_per_plant("roads"), f"or {CSV_ROADS}"]
    if kind == "controllers":
        return _per_plant("controllers")
    if kind == "objectives":
        return _per_plant("objectives", "default_objective")
    if kind == "optimizers":
        return [", ".join(choices()["optimizers"])]
    if kind == "rulebases":
        return [
            f"{name}: inputs {', '.join(rb['inputs'])}; outputs {', '.join(rb['outputs'])}"
            for name, rb in choices()["rulebases"].items()
        ] + ["or a TOML file"]
    raise ValueError(f"no choices of {kind!r}")


class ChoicesOption(click.Option):
    """An option whose valid choices (`choices_of`: a kind of `describe`) its command's help
    lists at its end (`ChoicesCommand`)."""

    def __init__(self, *args: Any, choices_of: str, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.choices_of = choices_of


class ChoicesCommand(click.Command):
    """A command whose help ends with a section of valid choices, read only when the help is
    shown: of its arguments (`arguments` maps a metavar such as PLANT to a kind of `describe`)
    and of its ChoicesOptions. Wrapped here, never inside a name (`wet-asphalt` stays whole)."""

    def __init__(self, *args: Any, arguments: dict[str, str] | None = None, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.arguments = arguments or {}

    def format_epilog(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        import textwrap

        kinds: dict[str, list[str]] = {kind: [name] for name, kind in self.arguments.items()}
        for param in self.params:
            if isinstance(param, ChoicesOption):
                kinds.setdefault(param.choices_of, []).append(param.opts[0])
        width = max(formatter.width - formatter.current_indent - 6, 40)
        with formatter.section("Choices"):
            for kind, names in kinds.items():
                formatter.write_text(f"{', '.join(names)}:")
                for line in describe(kind):
                    formatter.write(
                        textwrap.indent(
                            textwrap.fill(
                                line,
                                width,
                                subsequent_indent="  ",
                                break_on_hyphens=False,
                                break_long_words=False,
                            ),
                            " " * (formatter.current_indent + 2),
                        )
                        + "\n"
                    )
        super().format_epilog(ctx, formatter)
