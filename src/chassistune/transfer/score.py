"""The transfer study's rows (docs/transfer.md, "Scores"): every source on every cell and road,
with the paper's gains and with the gains re-tuned on the cell, scored by the league's code
(`league.score.score_on`: stop distance over the adhesion bound, UN R13-H utilisation, locked
time, the peak yaw rate in the first second); a cell no kernel runs is one row saying what is
missing."""

from __future__ import annotations

import math
from collections.abc import Mapping

import pandas as pd

from chassistune.league.cases import Case, LeaguePlant
from chassistune.league.plan import Setting as LeagueSetting
from chassistune.league.score import COLUMNS, score_on
from chassistune.transfer.cells import Cell, Source, missing
from chassistune.transfer.plan import Setting, Tunings

KNOWING = LeagueSetting(plants=(), road_knowledge="oracle")
"""The papers' road knowledge: a law that regulates a target slip is handed the road's peak
(the reproduction's setting, so each source runs as it was tuned)."""

GAINS = ("paper", "re-tuned")
"""The gains a cell is scored with: the source's as the paper tuned them, and re-tuned on it."""

NOT_AVAILABLE = "not available: "
"""The status of a cell no kernel runs, before what is missing."""

ROWS = ["source", "controller", "target", "tire", "ecu", "gains", *COLUMNS]


def league_plant(cell: Cell) -> LeaguePlant:
    """The cell as a league plant: its preset, ECU and the source's roads, each a case holding
    the cell's other parameters."""
    params = cell.params()
    ecu = tuple((k, v) for k, v in params.items() if k == "ecu")
    rest = tuple((k, v) for k, v in params.items() if k != "ecu")
    return LeaguePlant(
        plant=cell.source.plant,
        preset=cell.target,
        params=ecu,
        mode=f"{cell.ecu} ECU, {cell.tire} tire",
        training=cell.source.roads,
        held_out=tuple(Case(road, road, params=rest) for road in cell.source.roads),
    )


def _ident(cell: Cell, gains: str) -> dict[str, object]:
    return {
        "source": cell.source.key,
        "controller": cell.source.controller,
        "target": cell.target,
        "tire": cell.tire,
        "ecu": cell.ecu,
        "gains": gains,
    }


def cell_rows(cell: Cell, paper: Tunings, retuned: Tunings | None) -> list[dict[str, object]]:
    """The cell's rows: per road, the paper's gains for it and the re-tuned ones (on the home
    plant the paper's are the tuned ones; a re-tuning not yet run has no rows)."""
    lack = missing(cell)
    if lack is not None:
        blank = dict.fromkeys(COLUMNS, math.nan)
        return [{**_ident(cell, "paper"), **blank, "status": NOT_AVAILABLE + lack}]
    lp = league_plant(cell)
    cases = {c.road: c for c in lp.held_out}
    sets = {"paper": paper, "re-tuned": paper if cell.is_home else retuned or {}}
    return [
        {**_ident(cell, name), **score_on(lp, t, cases[road], KNOWING)}
        for name, tuned in sets.items()
        for roads, t in tuned.items()
        for road in roads
    ]


def score_transfer(
    setting: Setting,
    paper: Mapping[Source, Tunings],
    retuned: Mapping[Cell, Tunings],
) -> pd.DataFrame:
    """Every source on each of its cells, a row per (cell, gains, road) (`ROWS`)."""
    rows = [
        row
        for source in setting.sources
        for cell in setting.cells(source)
        for row in cell_rows(cell, paper[source], retuned.get(cell))
    ]
    return pd.DataFrame(rows, columns=ROWS)
