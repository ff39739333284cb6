"""The papers' claims, declared as data: each claim's sentence as the paper prints it (`quote`, in
the paper's language) and in our English (`claim`), where it stands, what it compares, at which
mass, and the rule by which we judge it. Every verdict of a reproduction names one of these; the
report prints the quote beside the verdict and `verdicts.csv` carries every field.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass

FIELDS = ("quote", "location", "compares", "mass", "rule")
"""The columns `verdicts.csv` adds after `paper, claim, verdict, evidence`."""


@dataclass(frozen=True)
class Claim:
    """One claim of paper `paper`, known in code by `name`."""

    paper: str
    name: str
    quote: str
    claim: str
    location: str
    compares: str
    rule: str
    mass: str = "not applicable"

    def __post_init__(self) -> None:
        for key, value in asdict(self).items():
            if not value.strip():
                raise ValueError(f"claim {self.name!r} of {self.paper}: empty {key}")

    def columns(self) -> dict[str, str]:
        """The claim's fields as `verdicts.csv` columns (besides paper and claim)."""
        return {k: getattr(self, k) for k in FIELDS}


def declared(claims: Sequence[Claim], name: str) -> Claim:
    """The claim `name` of `claims` (KeyError: no such declaration)."""
    for c in claims:
        if c.name == name:
            return c
    raise KeyError(f"no claim {name!r} declared")
