"""The papers' published numbers (package data `data/paper_results.toml`), read in one place.

Each `Quantity` is one printed row of a paper: its paper key, where it is printed (table or
figure), the quantity's name and unit, the road it belongs to (if any), and the values by label
(controller, algorithm or gain): `printed`, the strings exactly as published (47.2160 keeps its
zero), and `values`, the same read as floats. Reports quote them; tests never use them as
expectations of our results.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from importlib import resources

from chassistune.errors import InputError


@dataclass(frozen=True)
class Paper:
    """A paper: its short key, citation and the setting its numbers refer to."""

    key: str
    citation: str
    setting: str


@dataclass(frozen=True)
class Quantity:
    """One published row: values by label, in `unit`, printed at `source` of `paper`."""

    paper: str
    source: str
    name: str
    unit: str
    labels: tuple[str, ...]
    printed: tuple[str, ...]
    road: str | None = None
    note: str = ""

    @property
    def values(self) -> tuple[float, ...]:
        """The printed values as floats."""
        return tuple(float(v) for v in self.printed)

    def as_dict(self) -> dict[str, float]:
        """Label -> value."""
        return dict(zip(self.labels, self.values, strict=True))

    def as_printed(self) -> dict[str, str]:
        """Label -> value as printed."""
        return dict(zip(self.labels, self.printed, strict=True))


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


@cache
def _load() -> tuple[dict[str, Paper], tuple[Quantity, ...]]:
    text = resources.files("chassistune").joinpath("data/paper_results.toml").read_text("utf-8")
    raw = tomllib.loads(text)
    papers = {k: Paper(k, v["citation"], v["setting"]) for k, v in raw["papers"].items()}
    quantities = []
    for q in raw["quantity"]:
        if (
            q["paper"] not in papers
            or len(q["labels"]) != len(q["values"])
            or not all(isinstance(v, str) and _is_number(v) for v in q["values"])
        ):
            raise ValueError(f"paper_results.toml: malformed quantity {q.get('name')!r}")
        quantities.append(
            Quantity(
                paper=q["paper"],
                source=q["source"],
                name=q["name"],
                unit=q["unit"],
                labels=tuple(q["labels"]),
                printed=tuple(q["values"]),
                road=q.get("road"),
                note=q.get("note", ""),
            )
        )
    return papers, tuple(quantities)


def papers() -> tuple[str, ...]:
    """The keys of every paper with published numbers, in file order."""
    return tuple(_load()[0])


def paper(key: str) -> Paper:
    """The paper `key`, or InputError listing the known keys."""
    papers = _load()[0]
    if key not in papers:
        raise InputError("paper", f"unknown paper {key!r} (known: {', '.join(papers)})")
    return papers[key]


def quantities(key: str) -> tuple[Quantity, ...]:
    """Every published quantity of paper `key`, in file order."""
    paper(key)
    return tuple(q for q in _load()[1] if q.paper == key)


def lookup(key: str, name: str, road: str | None = None) -> Quantity:
    """The one quantity `name` (on `road`) of paper `key`; KeyError if it is not published."""
    found = [q for q in quantities(key) if q.name == name and q.road == road]
    if len(found) != 1:
        raise KeyError(f"{key}: no single published {name!r} on road {road!r}")
    return found[0]
