"""The papers' control problems as a benchmark (`data/studies/control-suite.toml`), read from
its study store in COCO's manner (Hansen et al. 2021, "Anytime performance assessment").

Each cell of the study (a plant, controller and road) is a problem. Its targets are relative to
a reference cost f_ref: f_ref + eps |f_ref| for eps in `PRECISIONS`. The reference is the value
shipped in `data/control-suite-references.toml` (the best cost of a long reference run over all
optimizers, with the command, date and budget that made it), else the best cost any run in the
store reached (a problem the reference run left out). The ECDF of an
optimizer at n evaluations is the fraction of (problem, target, seed) triples whose best-so-far
cost after n evaluations is at or below the target (the history is per iteration, so a target is
credited at the end of the iteration that reached it); its area is the mean over a log grid of n.
"""

from __future__ import annotations

import math
import tomllib
from collections import defaultdict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np

from chassistune.studies.store import RunRecord

PRECISIONS = (1.0, 0.3, 0.1, 0.03, 0.01, 0.003, 0.001)
CONFIG = "control-suite"
"""The package's study config (`data/studies/control-suite.toml`)."""


REFERENCES_FILE = "data/control-suite-references.toml"


@dataclass(frozen=True)
class References:
    """Stored reference costs per problem and how they were made."""

    command: str
    date: str
    budget: str
    values: Mapping[str, float]


@cache
def shipped_references() -> References:
    """The package's reference costs (`data/control-suite-references.toml`)."""
    text = resources.files("chassistune").joinpath(REFERENCES_FILE).read_text("utf-8")
    data = tomllib.loads(text)
    return References(data["command"], data["date"], data["budget"], dict(data["reference"]))


def best_costs(records: Iterable[RunRecord]) -> dict[str, float]:
    """The best final cost of the store's completed runs, per problem."""
    best: dict[str, float] = {}
    for r in records:
        if r.completed and r.best_cost is not None:
            best[r.spec.scenario] = min(best.get(r.spec.scenario, math.inf), r.best_cost)
    return best


def references(
    records: Iterable[RunRecord], given: Mapping[str, float] | None = None
) -> dict[str, float]:
    """Reference cost per problem of the store: `given` (default: the shipped references), else
    the best completed run of the store."""
    stored = shipped_references().values if given is None else given
    best = best_costs(records)
    return {p: stored.get(p, best[p]) for p in best}


def references_toml(records: Iterable[RunRecord], command: str, date: str, budget: str) -> str:
    """The text of a references file: the best cost per problem of a reference run's store."""
    lines = [
        "# Reference costs of the control suite (studies/control_suite.py): per problem, the",
        "# best final cost over every optimizer of a long reference run. Made by:",
        f"command = {_quoted(command)}",
        f"date = {_quoted(date)}",
        f"budget = {_quoted(budget)}",
        "",
        "[reference]",
    ]
    lines += [f"{_quoted(p)} = {c!r}" for p, c in sorted(best_costs(records).items())]
    return "\n".join(lines) + "\n"


def _quoted(text: str) -> str:
    """A TOML basic string."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def targets(reference: float) -> np.ndarray:
    """The targets of a problem with reference cost `reference`."""
    return reference + np.asarray(PRECISIONS) * abs(reference)


@dataclass(frozen=True)
class ECDF:
    """One optimizer's ECDF over (problem, target, seed) triples on an evaluation grid."""

    optimizer: str
    evaluations: np.ndarray
    fraction: np.ndarray

    @property
    def area(self) -> float:
        """Mean fraction over the (log-spaced) grid: 1 = every target at once."""
        return float(np.mean(self.fraction))


def ecdfs(records: Sequence[RunRecord], refs: Mapping[str, float], points: int = 50) -> list[ECDF]:
    """The ECDF of each optimizer on a log grid from 1 to the largest budget of the store."""
    runs: dict[str, list[RunRecord]] = defaultdict(list)
    for r in records:
        if r.completed and r.history_nfev:
            runs[r.spec.optimizer].append(r)
    budget = max(r.history_nfev[-1] for rs in runs.values() for r in rs)
    grid = np.unique(np.geomspace(1, budget, points).round().astype(np.int64))
    out = []
    for opt, rs in runs.items():
        hits = np.zeros(grid.size)
        count = 0
        for r in rs:
            nfev = np.asarray(r.history_nfev)
            cost = np.asarray(r.history)
            for t in targets(refs[r.spec.scenario]):
                reached = np.flatnonzero(cost <= t)
                if reached.size:
                    hits += grid >= nfev[reached[0]]
                count += 1
        out.append(ECDF(opt, grid, hits / count))
    return out


def final_costs(
    records: Sequence[RunRecord], refs: Mapping[str, float]
) -> dict[tuple[str, str], tuple[float, float, float]]:
    """(optimizer, problem) -> quartiles (25, 50, 75 %) of the final cost over f_ref."""
    costs: dict[tuple[str, str], list[float]] = defaultdict(list)
    for r in records:
        if r.completed and r.best_cost is not None:
            costs[(r.spec.optimizer, r.spec.scenario)].append(r.best_cost / refs[r.spec.scenario])
    return {k: tuple(np.percentile(v, [25, 50, 75]).tolist()) for k, v in costs.items()}


def markdown(records: Sequence[RunRecord], refs: Mapping[str, float]) -> str:
    """ECDF areas and median final cost over f_ref per optimizer and problem."""
    problems = sorted(refs)
    quartiles = final_costs(records, refs)
    lines = [
        "| optimizer | ECDF area | " + " | ".join(problems) + " |",
        "| --- | --- |" + " --- |" * len(problems),
    ]
    for e in sorted(ecdfs(records, refs), key=lambda e: -e.area):
        medians = " | ".join(
            f"{quartiles[(e.optimizer, p)][1]:.4g}" if (e.optimizer, p) in quartiles else ""
            for p in problems
        )
        lines.append(f"| {e.optimizer} | {e.area:.3f} | {medians} |")
    lines.append("")
    lines.append("| problem | f_ref |\n| --- | --- |")
    lines.extend(f"| {p} | {refs[p]:.6g} |" for p in problems)
    return "\n".join(lines)
