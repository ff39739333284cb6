"""The papers' parameter tables as tables: each printed value as printed, ours beside it (read from
the preset or road the reproduction runs, in the paper's unit) and why they differ; and the fuzzy
rule tables (deffao-vehicle-abs Table 3, fuzzy-immune-abs Table 1) from the rule base files the
controllers load, laid out as the papers print them (rows e, columns ec)."""

from __future__ import annotations

import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources

import pandas as pd

from chassistune.fuzzy.loader import builtin_path, load_rulebase
from chassistune.papers.common import Table
from chassistune.papers.keys import (
    DEFFAO_VEHICLE_ABS,
    DERLSP_AO_ABS,
    FUZZY_IMMUNE_ABS,
    IABC_SUSPENSION,
)
from chassistune.plants.abs_vehicle_params import PRESETS as VEHICLE_PRESETS
from chassistune.plants.abs_wheel import PRESETS as WHEEL_PRESETS
from chassistune.plants.iso_roads import RoadParams
from chassistune.plants.quarter_car_params import PRESETS as QUARTER_CAR_PRESETS
from chassistune.plants.roads import BILINEAR_ROADS, ISO_CLASSES
from chassistune.plants.tires import BilinearTire

SAME = "same value"
"""The reason shown where ours equals the printed value."""

SOURCES: dict[str, object] = {
    **{
        road: BilinearTire(*BILINEAR_ROADS[road][:3])
        for road in ("dry-concrete", "wet-asphalt", "ice")
    },
    "iso-b": RoadParams(gq_m3=ISO_CLASSES["iso-b"]),
    "paper-iabc": QUARTER_CAR_PRESETS["paper-iabc"].params,
    "paper-deffao": VEHICLE_PRESETS["paper-deffao"].params,
    "paper-fuzzy-immune": WHEEL_PRESETS["paper-fuzzy-immune"].params,
}
"""What an entry's `ours` names before its dot: a road or a preset's plant parameters."""


@dataclass(frozen=True)
class Printed:
    """One printed parameter (package data paper_parameters.toml): name, symbol and unit as
    printed, the value as printed (its digits kept), ours (`source.field`, times `scale` into the
    paper's unit) and why ours differs."""

    paper: str
    table: str
    quantity: str
    symbol: str
    unit: str
    printed: str
    ours: str
    scale: float = 1.0
    why: str = ""

    @property
    def our_value(self) -> float:
        source, name = self.ours.split(".", 1)
        return float(f"{float(getattr(SOURCES[source], name)) * self.scale:.12g}")

    def row(self) -> dict[str, object]:
        value = _number(self.printed)
        differs = value is None or abs(value - self.our_value) > 1e-9 * abs(self.our_value)
        if differs and not self.why:
            raise ValueError(f"{self.quantity}: ours differs from the paper with no reason given")
        return {
            "quantity": self.quantity,
            "symbol": self.symbol,
            "unit (as printed)": self.unit,
            "paper": self.printed,
            "ours": self.our_value,
            "our parameter": self.ours + (f" x {self.scale:g}" if self.scale != 1.0 else ""),
            "why they differ": self.why if differs else SAME,
        }


def _number(printed: str) -> float | None:
    """The value of a printed number ('200 000', '64×10^-6', '0.900 0'); None for text."""
    text = printed.replace(" ", "").replace("×10^", "e")
    try:
        return float(text)
    except ValueError:
        return None


def printed_parameters() -> list[Printed]:
    """Every entry of the package data paper_parameters.toml, in file order."""
    text = resources.files("chassistune").joinpath("data/paper_parameters.toml").read_text("utf-8")
    return [Printed(**entry) for entry in tomllib.loads(text)["parameter"]]


CAPTIONS: dict[tuple[str, str], tuple[str, str, str]] = {
    (DERLSP_AO_ABS, "Table 1"): (
        "table1_roads",
        "typical road parameters",
        "Eq. 7 prints a wet-asphalt slope of 0.3125 where this table gives (0.78 - 0.5)/"
        "(1 - 0.2) = 0.35: the table is used.",
    ),
    (IABC_SUSPENSION, "Table 1"): (
        "table1_quarter_car",
        "quarter-car parameters (preset paper-iabc)",
        "As printed, c_s = 12000 N s/m is about ten times a car's damper (damping ratio 2.57); "
        "preset typical runs 1200. The text gives Gq(n0) = 256e-6 (class C) and the abstract "
        "class B: this table's 64e-6 (class B) is used.",
    ),
    (DEFFAO_VEHICLE_ABS, "Table 1"): (
        "table1_roads",
        "typical road parameters",
        "The mu-jump and split-mu roads join these two surfaces.",
    ),
    (DEFFAO_VEHICLE_ABS, "Table 2"): (
        "table2_vehicle",
        "vehicle parameters (preset paper-deffao)",
        "The paper gives no CG height, track widths, tire cornering stiffness or brake: ours are "
        "in the preset (DESIGN 3.3). m1 and m2 are kept but unused by the planar model.",
    ),
    (FUZZY_IMMUNE_ABS, "Table 2"): (
        "table2_vehicle",
        "vehicle parameters (preset paper-fuzzy-immune)",
        "The units marked (sic) are printed so; J = 25 kg m^2 is about twenty times a car "
        "wheel's and 26 kPa already locks the wheel: both kept as printed.",
    ),
}
"""(CSV name, title, caption) of each paper's parameter table."""


def parameter_table(key: str, table: str) -> Table:
    """Paper `key`'s parameter table `table`: each printed value beside ours."""
    name, title, caption = CAPTIONS[(key, table)]
    rows = [p.row() for p in printed_parameters() if (p.paper, p.table) == (key, table)]
    return Table(
        name,
        f"{table}: {title}, paper beside ours",
        pd.DataFrame(rows),
        "paper: the value exactly as printed; ours: the value this reproduction runs, in the "
        "paper's unit. " + caption,
        quoted=("paper",),
    )


def rule_table(rulebase: str, name: str, title: str) -> Table:
    """The rule base `rulebase` (package data) as the paper prints it: rows the first input's
    sets, columns the second's, each cell the outputs' sets joined by commas."""
    rb = load_rulebase(rulebase)
    first, second = rb.inputs
    cells = {(r[0], r[1]): ",".join(r[2:]) for r in rb.rules}
    corner = f"{first.name} \\ {second.name}"
    frame = pd.DataFrame(
        [
            {corner: a, **{b: cells.get((a, b), "") for b in second.set_names}}
            for a in first.set_names
        ]
    )
    return Table(
        name,
        title,
        frame,
        f"Rows {first.name}, columns {second.name}; each cell: "
        f"{', '.join(rb.output_names)}. From the rule base the controller loads "
        f"(package data rulebases/{builtin_path(rulebase).name}); check it against the paper "
        "cell by cell.",
        missing={b: "no rule" for b in second.set_names},
    )


PARAMETER_TABLES: dict[str, tuple[Callable[[], Table], ...]] = {
    DERLSP_AO_ABS: (lambda: parameter_table(DERLSP_AO_ABS, "Table 1"),),
    IABC_SUSPENSION: (lambda: parameter_table(IABC_SUSPENSION, "Table 1"),),
    DEFFAO_VEHICLE_ABS: (
        lambda: parameter_table(DEFFAO_VEHICLE_ABS, "Table 1"),
        lambda: parameter_table(DEFFAO_VEHICLE_ABS, "Table 2"),
        lambda: rule_table("deffao", "table3_rules", "Table 3: fuzzy control rules (kp, ki, kd)"),
    ),
    FUZZY_IMMUNE_ABS: (
        lambda: rule_table("immune", "table1_rules", "Table 1: fuzzy rules of the immune f"),
        lambda: parameter_table(FUZZY_IMMUNE_ABS, "Table 2"),
    ),
}
"""The paper's own tables of parameters and rules, in the paper's order, by paper key."""


def paper_tables(key: str) -> list[Table]:
    """The parameter and rule tables of paper `key`."""
    return [build() for build in PARAMETER_TABLES.get(key, ())]
