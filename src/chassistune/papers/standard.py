"""The section "the papers' optimizers against the standard" (docs/bbob.md): does each paper's
proposed optimizer beat CMA-ES and random search at equal evaluations on BBOB, on the shifted
F1-F23 and on its own control problem? Read from the stored, dated record
`data/standard_result.toml` (command, date, setting and numbers of each benchmark); `reproduce`
does not rerun the benchmarks.

Against one reference, on one benchmark, each column (a dimension, a function, a control problem)
is a win or a loss for the proposed optimizer; scores within the benchmark's relative `tie` of
each other are a tie, neither. It beats the reference when it
wins a majority of the columns and is beaten when it loses a majority; otherwise it is undecided.
The question "beats CMA-ES and random search" holds when it beats both, does not hold when either
beats it, is undecided at this budget when neither, and cannot be checked without numbers. It is
our question, not a sentence of the papers: each is declared as a `Claim` whose quote is the
paper's own statement of its optimizer's superiority that the question tests.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from importlib import resources

import pandas as pd

from chassistune.papers import claims, common, deffao_vehicle_abs, derlsp_ao_abs, iabc_suspension
from chassistune.papers.claims import Claim
from chassistune.papers.keys import DEFFAO_VEHICLE_ABS, DERLSP_AO_ABS, IABC_SUSPENSION

RECORD = "data/standard_result.toml"
KEY = "standard"
TITLE = "The papers' optimizers against the standard"
REFERENCES = ("cma-es", "random-search")
PROPOSED = {DERLSP_AO_ABS: "derlsp-ao", DEFFAO_VEHICLE_ABS: "deffao", IABC_SUSPENSION: "iabc"}
"""Paper key -> its proposed optimizer."""
OWN_PROBLEM = {
    DERLSP_AO_ABS: f"{DERLSP_AO_ABS}-pid/",
    DEFFAO_VEHICLE_ABS: f"{DEFFAO_VEHICLE_ABS}-fuzzy-pid/",
    IABC_SUSPENSION: f"{IABC_SUSPENSION}-pid/",
}
"""Paper key -> the prefix of its own control problems in the control-suite part."""
SOURCE_CLAIM = {
    DERLSP_AO_ABS: "fig7-most",
    DEFFAO_VEHICLE_ABS: "table4-best",
    IABC_SUSPENSION: "smaller-objective",
}
"""Paper key -> its declared claim that its optimizer is better (the quote the question tests)."""
PAPER_CLAIMS = {
    DERLSP_AO_ABS: derlsp_ao_abs.CLAIMS,
    DEFFAO_VEHICLE_ABS: deffao_vehicle_abs.CLAIMS,
    IABC_SUSPENSION: iabc_suspension.CLAIMS,
}
BENCHMARKS = ("bbob", "shifted", "control")
BEATS, BEATEN, UNDECIDED, MISSING = (
    "beats",
    "is beaten by",
    "is undecided against",
    "has no numbers",
)


@dataclass(frozen=True)
class Benchmark:
    """One benchmark's stored numbers: a score per optimizer and column, with provenance."""

    name: str
    title: str
    command: str
    date: str
    setting: str
    score: str
    higher_is_better: bool
    columns: tuple[str, ...]
    scores: Mapping[str, tuple[float, ...]]
    tie: float = 0.0
    """Relative difference at or below which two scores are equal."""

    def frame(self) -> pd.DataFrame:
        """The stored scores, a row per column of the benchmark (dimension, function, problem)
        and a column per optimizer (few optimizers, many functions: the table stays narrow)."""
        return pd.DataFrame({"case": self.columns, **{o: s for o, s in self.scores.items()}})


def parse(text: str) -> dict[str, Benchmark]:
    """The benchmarks of a record's TOML text, by name."""
    data = tomllib.loads(text)
    out = {}
    for name in BENCHMARKS:
        part = data[name]
        columns = tuple(part["columns"])
        scores = {o: tuple(float(v) for v in s) for o, s in part["scores"].items()}
        for o, s in scores.items():
            if len(s) != len(columns):
                raise ValueError(f"{name}: {o} has {len(s)} scores for {len(columns)} columns")
        out[name] = Benchmark(
            name,
            part["title"],
            part["command"],
            part["date"],
            part["setting"],
            part["score"],
            part["better"] == "higher",
            columns,
            scores,
            float(part.get("tie", 0.0)),
        )
    return out


def shipped() -> dict[str, Benchmark]:
    """The package's record (`data/standard_result.toml`)."""
    return parse(resources.files("chassistune").joinpath(RECORD).read_text("utf-8"))


def against(bench: Benchmark, optimizer: str, reference: str, prefix: str = "") -> tuple[str, str]:
    """(BEATS | BEATEN | UNDECIDED, wins and losses) of `optimizer` against `reference` over the
    columns starting with `prefix`; MISSING with the reason when a score is missing."""
    if optimizer not in bench.scores or reference not in bench.scores:
        return MISSING, f"no {bench.name} numbers for {optimizer} or {reference}"
    pairs = [
        (a, b)
        for c, a, b in zip(
            bench.columns, bench.scores[optimizer], bench.scores[reference], strict=True
        )
        if c.startswith(prefix)
    ]
    if not pairs:
        return MISSING, f"no {bench.name} column for {prefix or 'it'}"
    sign = 1.0 if bench.higher_is_better else -1.0
    margins = [sign * (a - b) for a, b in pairs if abs(a - b) > bench.tie * max(abs(a), abs(b))]
    wins = sum(m > 0 for m in margins)
    losses = len(margins) - wins
    word = BEATS if 2 * wins > len(pairs) else BEATEN if 2 * losses > len(pairs) else UNDECIDED
    return word, f"{wins} better, {losses} worse of {len(pairs)} against {reference}"


ON = {
    "bbob": "the COCO/BBOB suite",
    "shifted": "F1-F23 with the optimum moved off the centre",
    "control": "its own control problems",
}
"""Benchmark -> the words of the question's claim."""


def _claim(paper: str, bench: str) -> Claim:
    """Our question of `paper`'s proposed optimizer on `bench`, quoting the paper's own claim of
    superiority that it tests."""
    optimizer = PROPOSED[paper]
    return Claim(
        paper=paper,
        name=f"standard-{bench}",
        quote=claims.declared(PAPER_CLAIMS[paper], SOURCE_CLAIM[paper]).quote,
        claim=f"{optimizer} beats CMA-ES and random search at equal evaluations on {ON[bench]}",
        location="our question of the paper's optimizer claims (docs/bbob.md)",
        compares=f"{optimizer} against {' and '.join(REFERENCES)}",
        rule="a majority of the columns won against each reference; see the section's text",
    )


CLAIMS = tuple(_claim(paper, bench) for paper in PROPOSED for bench in BENCHMARKS)
"""Every question of the section, declared once (three per paper that proposes an optimizer)."""


def verdict(paper: str, bench: Benchmark, prefix: str = "") -> common.Verdict:
    """Whether the paper's proposed optimizer beats both references on `bench`."""
    optimizer = PROPOSED[paper]
    results = [against(bench, optimizer, ref, prefix) for ref in REFERENCES]
    words = [w for w, _ in results]
    if all(w == BEATS for w in words):
        word = common.HOLDS
    elif BEATEN in words:
        word = common.FAILS
    elif MISSING in words:
        word = common.UNCHECKED
    else:
        word = common.UNDECIDED
    evidence = "; ".join(
        f"{optimizer} {w} {ref} ({why})" for ref, (w, why) in zip(REFERENCES, results, strict=True)
    )
    claim = claims.declared([c for c in CLAIMS if c.paper == paper], f"standard-{bench.name}")
    return common.Verdict(claim, word, f"{evidence} [{bench.score}; {bench.setting}]")


def build(
    record: Mapping[str, Benchmark] | None = None, papers: Sequence[str] = tuple(PROPOSED)
) -> common.PaperSection:
    """The section: the record's provenance, its tables, and three verdicts for each of `papers`
    that proposes an optimizer."""
    benches = shipped() if record is None else record
    setting = [
        (f"{b.title}: command", f"{b.command} ({b.date}; {b.setting})") for b in benches.values()
    ]
    sec = common.PaperSection(KEY, TITLE, setting)
    for b in benches.values():
        better = "higher" if b.higher_is_better else "lower"
        sec.tables.append(
            common.Table(b.name, b.title, b.frame(), f"{b.score} ({better} is better).")
        )
    for paper in (p for p in PROPOSED if p in papers):
        sec.verdicts.append(verdict(paper, benches["bbob"]))
        sec.verdicts.append(verdict(paper, benches["shifted"]))
        sec.verdicts.append(verdict(paper, benches["control"], OWN_PROBLEM[paper]))
    return sec
