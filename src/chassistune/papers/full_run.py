"""The record of the last full reproduction (package data `data/full_run.toml`) and the banner a
quick run's page opens with: what the quick budget can and cannot decide, and which verdicts the
full protocol decided differently.
"""

from __future__ import annotations

import tomllib
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from importlib import resources

from chassistune.papers.common import UNDECIDED, VERDICT_MARKS, VERDICTS, Verdict


@dataclass(frozen=True)
class RecordedVerdict:
    """One claim's verdict in the last full run (`full`) and in the quick run of the same
    sources (`quick`)."""

    paper: str
    claim: str
    full: str
    quick: str


@dataclass(frozen=True)
class FullRun:
    """The last full run: when, by which command, on which sources, and its verdicts.
    `current_claims`: were its claims the ones this build declares?"""

    date: str
    command: str
    sources: str
    current_claims: bool
    note: str
    verdicts: tuple[RecordedVerdict, ...]


@cache
def last_full_run() -> FullRun:
    """The shipped record."""
    text = resources.files("chassistune").joinpath("data/full_run.toml").read_text("utf-8")
    raw = tomllib.loads(text)
    verdicts = tuple(RecordedVerdict(**v) for v in raw["verdict"])
    for v in verdicts:
        if v.full not in VERDICTS or v.quick not in VERDICTS:
            raise ValueError(f"full_run.toml: unknown verdict for {v.claim!r}")
    return FullRun(
        raw["date"],
        raw["command"],
        raw["sources"],
        raw["current_claims"],
        raw["note"],
        verdicts,
    )


def decided_differently(record: FullRun, verdicts: Sequence[Verdict]) -> list[RecordedVerdict]:
    """The recorded claims whose full-run verdict differs from the quick one: this page's
    verdict where the record holds the current claims, else the record's own quick run."""
    shown = {(v.paper, v.claim.claim): v.verdict for v in verdicts}
    out = []
    for r in record.verdicts:
        quick = shown.get((r.paper, r.claim)) if record.current_claims else r.quick
        if quick is not None and quick != r.full:
            out.append(r)
    return out


def quick_banner(verdicts: Sequence[Verdict]) -> str:
    """The first words of a quick run's page."""
    record = last_full_run()
    undecided = sum(v.verdict == UNDECIDED for v in verdicts)
    differ = decided_differently(record, verdicts)
    decided = [r for r in differ if r.quick == UNDECIDED]
    changed = [r for r in differ if r.quick != UNDECIDED]
    parts = []
    if decided:
        parts.append(
            f"decided {len(decided)} that the quick run leaves undecided: "
            + "; ".join(
                f"{r.paper}: '{r.claim}' ({VERDICT_MARKS[r.full]} {r.full})" for r in decided
            )
        )
    if changed:
        parts.append(
            f"reversed {len(changed)} that the quick run decides: "
            + "; ".join(
                f"{r.paper}: '{r.claim}' (full: {VERDICT_MARKS[r.full]} {r.full}, quick: "
                f"{VERDICT_MARKS[r.quick]} {r.quick})"
                for r in changed
            )
        )
    return (
        "Quick run: a few seeds and iterations. This budget decides what does not depend on "
        "it (the physical bounds of the published numbers, wheel lock counts) and comparisons "
        "between fixed values (untuned baselines, each optimizer's representative run); it "
        "cannot make a ranking of tuned runs significant (1-3 seeds a side cannot reach "
        f"p < 0.05): such claims are marked {VERDICT_MARKS[UNDECIDED]} {UNDECIDED} "
        f"({undecided} here), not 'does not hold'. Last full run: {record.date}, "
        f"`{record.command}`, {record.sources}. {record.note} "
        + (
            f"Of its {len(record.verdicts)} verdicts, the full protocol "
            + "; and it ".join(parts)
            + "."
            if differ
            else "The full protocol decided every recorded verdict as the quick run did."
        )
    )
