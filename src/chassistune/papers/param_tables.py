"""The papers' parameter tables as tables: each printed value as printed, ours beside it (read from
the preset or road the reproduction runs, in the paper's unit) and why they differ; and the fuzzy
rule tables (deffao-vehicle-abs Table 3, fuzzy-immune-abs Table 1) from the rule base files the
controllers load, laid out as the papers print them (rows e, columns ec)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import pandas as pd

from chassistune.fuzzy.loader import builtin_path, load_rulebase
from chassistune.papers.common import Table
from chassistune.plants.abs_vehicle_params import PRESETS as VEHICLE_PRESETS
from chassistune.plants.abs_wheel import PRESETS as WHEEL_PRESETS
from chassistune.plants.iso_roads import RoadParams
from chassistune.plants.quarter_car_params import PRESETS as QUARTER_CAR_PRESETS
from chassistune.plants.roads import BILINEAR_ROADS, ISO_CLASSES

SAME = "same value"
"""The reason shown where ours equals the printed value."""


@dataclass(frozen=True)
class Printed:
    """One printed parameter: its name, symbol and unit as printed, the value as printed (a
    string: its digits kept), ours in the paper's unit, and why ours differs (blank: it does
    not)."""

    quantity: str
    symbol: str
    unit: str
    printed: str
    ours: float
    our_parameter: str
    why: str = ""

    def row(self) -> dict[str, object]:
        value = _number(self.printed)
        differs = value is None or abs(value - self.ours) > 1e-9 * abs(self.ours)
        if differs and not self.why:
            raise ValueError(f"{self.quantity}: ours differs from the paper with no reason given")
        return {
            "quantity": self.quantity,
            "symbol": self.symbol,
            "unit (as printed)": self.unit,
            "paper": self.printed,
            "ours": float(f"{self.ours:.12g}"),
            "our parameter": self.our_parameter,
            "why they differ": self.why if differs else SAME,
        }


def _number(printed: str) -> float | None:
    """The value of a printed number ('200 000', '64×10^-6', '0.900 0'); None for text."""
    text = printed.replace(" ", "").replace("×10^", "e")
    try:
        return float(text)
    except ValueError:
        return None


def _table(name: str, title: str, rows: list[Printed], caption: str) -> Table:
    return Table(
        name,
        title,
        pd.DataFrame([r.row() for r in rows]),
        "paper: the value exactly as printed; ours: the value this reproduction runs, in the "
        "paper's unit. " + caption,
        quoted=("paper",),
    )


ROAD_NAMES = {"dry-concrete": "dry concrete", "wet-asphalt": "wet asphalt", "ice": "ice"}


def _road_rows(printed: dict[str, tuple[str, str, str]], why: dict[str, str]) -> list[Printed]:
    """Table 1 of derlsp-ao-abs and deffao-vehicle-abs: S_T, u_h, u_g per road."""
    rows = []
    for road, values in printed.items():
        ours = BILINEAR_ROADS[road][:3]
        for symbol, text, value in zip(("ST", "uh", "ug"), values, ours, strict=True):
            rows.append(
                Printed(
                    f"{ROAD_NAMES[road]}: "
                    + {"ST": "optimal slip", "uh": "peak mu", "ug": "mu at S = 1"}[symbol],
                    symbol,
                    "-",
                    text,
                    value,
                    f"road {road}",
                    why.get(road, ""),
                )
            )
    return rows


def derlsp_table1() -> Table:
    """derlsp-ao-abs Table 1: the bilinear roads."""
    rows = _road_rows(
        {
            "dry-concrete": ("0.2", "0.900 0", "0.75"),
            "wet-asphalt": ("0.2", "0.780 0", "0.50"),
            "ice": ("0.1", "0.102 8", "0.07"),
        },
        {},
    )
    return _table(
        "table1_roads",
        "Table 1: typical road parameters, paper beside ours",
        rows,
        "Eq. 7 prints a wet-asphalt slope of 0.3125 where this table gives "
        "(0.78 - 0.5)/(1 - 0.2) = 0.35: the table is used.",
    )


def deffao_table1() -> Table:
    """deffao-vehicle-abs Table 1: the bilinear roads."""
    rows = _road_rows(
        {"dry-concrete": ("0.2", "0.9000", "0.75"), "ice": ("0.1", "0.1028", "0.07")}, {}
    )
    return _table(
        "table1_roads",
        "Table 1: typical road parameters, paper beside ours",
        rows,
        "The mu-jump and split-mu roads join these two surfaces.",
    )


def deffao_table2() -> Table:
    """deffao-vehicle-abs Table 2: the vehicle."""
    p = VEHICLE_PRESETS["paper-deffao"].params
    rows = [
        Printed("total mass", "m", "kg", "1110", p.mass_kg, "mass_kg"),
        Printed(
            "front unsprung mass",
            "m1",
            "kg",
            "60",
            p.front_unsprung_kg,
            "front_unsprung_kg",
        ),
        Printed("rear unsprung mass", "m2", "kg", "60", p.rear_unsprung_kg, "rear_unsprung_kg"),
        Printed("wheel radius", "R", "m", "0.4", p.wheel_radius_m, "wheel_radius_m"),
        Printed("wheel inertia", "I", "kg·m2", "0.6", p.wheel_inertia_kg_m2, "wheel_inertia_kg_m2"),
        Printed(
            "yaw inertia",
            "Iz",
            "kg·m2",
            "1.44",
            p.yaw_inertia_kg_m2,
            "yaw_inertia_kg_m2",
            "1.44 kg m^2 is a thousandth of a 1110 kg car's yaw inertia (about m lf lr = "
            "1800 kg m^2); read as 1440 (DESIGN 3.3)",
        ),
        Printed("CG to front axle", "lf", "m", "1.04", p.cg_to_front_m, "cg_to_front_m"),
        Printed("CG to rear axle", "lr", "m", "1.56", p.cg_to_rear_m, "cg_to_rear_m"),
        Printed("initial speed", "v0", "km·h-1", "120", p.v0_m_s * 3.6, "v0_m_s (x 3.6)"),
        Printed("gravity", "g", "m·s-2", "9.8", p.g_m_s2, "g_m_s2"),
    ]
    return _table(
        "table2_vehicle",
        "Table 2: vehicle parameters, paper beside ours",
        rows,
        "The paper gives no CG height, track widths, tire cornering stiffness or brake: ours "
        f"are h = {p.cg_height_m:g} m, tracks {p.track_front_m:g} m, C = "
        f"{p.cornering_stiffness_n_rad:g} N/rad, kq = {p.brake_gain:g}, q_max = {p.q_max:g} "
        "(preset paper-deffao, DESIGN 3.3). m1 and m2 are kept but unused by the planar model.",
    )


def iabc_table1() -> Table:
    """iabc-suspension Table 1: the quarter car and its road."""
    p = QUARTER_CAR_PRESETS["paper-iabc"].params
    road = RoadParams()
    rows = [
        Printed("unsprung mass", "m_u", "kg", "45", p.unsprung_mass_kg, "unsprung_mass_kg"),
        Printed("sprung mass", "m_s", "kg", "320", p.sprung_mass_kg, "sprung_mass_kg"),
        Printed(
            "tire stiffness", "k_t", "N/m", "200 000", p.tire_stiffness_n_m, "tire_stiffness_n_m"
        ),
        Printed("suspension stiffness", "k_s", "N/m", "17 000", p.spring_n_m, "spring_n_m"),
        Printed("suspension damping", "c_s", "N·s/m", "12 000", p.damper_n_s_m, "damper_n_s_m"),
        Printed(
            "road roughness coefficient",
            "Gq(n0)",
            "m2/m-1",
            "64×10^-6",
            ISO_CLASSES["iso-b"],
            "road iso-b",
        ),
        Printed("lower cut-off frequency", "f0", "Hz", "0.1", road.cutoff_hz, "cutoff_hz"),
    ]
    return _table(
        "table1_quarter_car",
        "Table 1: quarter-car parameters, paper beside ours (preset paper-iabc)",
        rows,
        "As printed, c_s = 12000 N s/m is about ten times a car's damper (damping ratio "
        f"{p.damping_ratio:.2f}); preset typical runs c_s = "
        f"{QUARTER_CAR_PRESETS['typical'].params.damper_n_s_m:g}. The text gives Gq(n0) = "
        "256e-6 (class C) and the abstract class B: this table's 64e-6 (class B) is used.",
    )


def fuzzy_immune_table2() -> Table:
    """fuzzy-immune-abs Table 2: the vehicle."""
    p = WHEEL_PRESETS["paper-fuzzy-immune"].params
    rows = [
        Printed(
            "gravity",
            "g",
            "m/s2",
            "9.8",
            p.g_m_s2,
            "g_m_s2",
            "not set by the preset: the plant's default 9.81 (every bound 0.1 % shorter)",
        ),
        Printed("initial speed", "v0", "m/s", "30", p.v0_m_s, "v0_m_s"),
        Printed("wheel rolling radius", "R", "m", "0.28", p.wheel_radius_m, "wheel_radius_m"),
        Printed(
            "moment of inertia",
            "J",
            "kg/m2 (sic)",
            "25",
            p.wheel_inertia_kg_m2,
            "wheel_inertia_kg_m2 (kg m^2)",
        ),
        Printed("brake factor", "kq", "N (sic)", "25", p.brake_gain, "brake_gain (N m/kPa)"),
        Printed("brake pressure range, top", "q", "kPa", "800", p.q_max, "q_max"),
        Printed(
            "quarter mass",
            "M",
            "kg",
            "not given",
            p.mass_kg,
            "mass_kg",
            "the paper gives no mass: 300 kg is our assumption",
        ),
    ]
    return _table(
        "table2_vehicle",
        "Table 2: vehicle parameters, paper beside ours (preset paper-fuzzy-immune)",
        rows,
        "The units marked (sic) are printed so; J = 25 kg m^2 is about twenty times a car "
        "wheel's and 26 kPa already locks the wheel: both kept as printed.",
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
    "derlsp-ao-abs": (derlsp_table1,),
    "iabc-suspension": (iabc_table1,),
    "deffao-vehicle-abs": (
        deffao_table1,
        deffao_table2,
        lambda: rule_table("deffao", "table3_rules", "Table 3: fuzzy control rules (kp, ki, kd)"),
    ),
    "fuzzy-immune-abs": (
        lambda: rule_table("immune", "table1_rules", "Table 1: fuzzy rules of the immune f"),
        fuzzy_immune_table2,
    ),
}
"""The paper's own tables of parameters and rules, in the paper's order, by paper key."""


def paper_tables(key: str) -> list[Table]:
    """The parameter and rule tables of paper `key`."""
    return [build() for build in PARAMETER_TABLES.get(key, ())]
