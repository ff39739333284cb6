"""Every road surface by name (design.md 3.2, 3.4): tire-road friction curves for the wheel plants
and ISO 8608 roughness classes for the suspension.

Friction roads: the bilinear curves of Tian et al.'s Table 1 (`derlsp-ao-abs`) and the peaks of
Ding 2023 (`fuzzy-immune-abs`), Burckhardt's seven surfaces (`burckhardt-<surface>`) and
MathWorks' sldemo table (`sldemo-table`), and a measured mu-slip table read from a CSV file
(a road named by its path, `*.csv`: columns `slip` and `mu`). Roughness roads: `iso-a` ...
`iso-h`.
"""

from __future__ import annotations

import csv
import io
import math
import warnings
from collections.abc import Mapping

import numpy as np

from chassistune._io import read_input
from chassistune.errors import InputError
from chassistune.params import ImplausibleValue, implausible, number, override
from chassistune.plants.tires import (
    BURCKHARDT_SURFACES,
    KIND_BURCKHARDT,
    PLAUSIBLE_MU_PEAK,
    SLDEMO_TABLE,
    BilinearTire,
    BurckhardtTire,
    TableTire,
    TireCurve,
    table_problem,
)

BILINEAR_ROADS: dict[str, tuple[float, float, float, str]] = {
    "dry-concrete": (0.2, 0.9, 0.75, "derlsp-ao-abs Table 1"),
    "wet-asphalt": (
        0.2,
        0.78,
        0.50,
        "derlsp-ao-abs Table 1 (its eq. 7 slope 0.3125 is a misprint)",
    ),
    "ice": (0.1, 0.1028, 0.07, "derlsp-ao-abs Table 1"),
    "asphalt-0.8": (
        0.2,
        0.8,
        0.6,
        "fuzzy-immune-abs peak 0.8; slip and lock values our assumption",
    ),
    "dirt-0.2": (0.15, 0.2, 0.15, "fuzzy-immune-abs peak 0.2; slip and lock values our assumption"),
}
"""Road name -> (S_T, mu_h, mu_g, source) of the bilinear curve."""

BURCKHARDT_PREFIX = "burckhardt-"

CSV_SUFFIX = ".csv"
"""A road whose name ends so is a measured mu-slip table: the path of its CSV file."""

ISO_CLASSES: dict[str, float] = {
    f"iso-{letter}": 16e-6 * 4.0**i for i, letter in enumerate("abcdefgh")
}
"""Road name -> geometric mean Gd(n0) of the ISO 8608 class, m^3 (16e-6 ... 262144e-6)."""


def friction_roads() -> dict[str, str]:
    """Friction road name -> one-line description."""
    out = {
        n: f"bilinear slip_opt={s}, mu_peak={h}, mu_lock={g}: {d}"
        for n, (s, h, g, d) in BILINEAR_ROADS.items()
    }
    out["sldemo-table"] = "MathWorks sldemo_absbrake mu-slip table (peak 1.0 at S = 0.2)"
    for name, (c1, c2, c3) in BURCKHARDT_SURFACES.items():
        out[f"{BURCKHARDT_PREFIX}{name}"] = f"Burckhardt c1={c1}, c2={c2}, c3={c3}"
    return out


def tire_for_road(road: str, values: Mapping[str, object]) -> tuple[TireCurve, set[str]]:
    """The road's tire curve with overrides (slip_opt/mu_peak/mu_lock or c1/c2/c3, and mu_scale
    on every road) applied, and the names of `values` used."""
    base: TireCurve
    surface = road[len(BURCKHARDT_PREFIX) :]
    if road in BILINEAR_ROADS:
        s, h, g, _ = BILINEAR_ROADS[road]
        base = BilinearTire(s, h, g)
    elif road == "sldemo-table":  # its table is fixed; only the scale of the curve varies
        base, values = SLDEMO_TABLE, {k: v for k, v in values.items() if k == "mu_scale"}
    elif road.lower().endswith(CSV_SUFFIX):  # a measured table: likewise
        base = read_mu_slip_csv(road)
        values = {k: v for k, v in values.items() if k == "mu_scale"}
    elif road.startswith(BURCKHARDT_PREFIX) and surface in BURCKHARDT_SURFACES:
        base = BurckhardtTire(*BURCKHARDT_SURFACES[surface])
    else:
        raise InputError(
            "road",
            f"unknown road {road!r} for abs-wheel (known: {', '.join(friction_roads())}; "
            f"or a measured mu-slip table, FILE{CSV_SUFFIX})",
        )
    tire, used = override(base, values)
    return checked_grip(road, tire), used


def checked_grip(road: str, tire: TireCurve) -> TireCurve:
    """`tire`, refused when it cannot brake (its peak mu is not positive: no deceleration, no
    stopping-distance bound) and warned about when its peak mu is outside PLAUSIBLE_MU_PEAK
    (unless a parameter of the curve is already warned about)."""
    kind, _, _, nodes_mu = tire.kernel_data()
    if kind == KIND_BURCKHARDT:  # smooth: its maximum on a fine grid (TireCurve.peak refines)
        mu_peak = float(np.max(tire.mu(np.linspace(0.0, 1.0, 4001))))
    else:  # piecewise linear: the largest node
        mu_peak = float(np.max(nodes_mu))
    if not mu_peak > 0.0:
        raise InputError("road", f"{road} cannot brake: its peak mu is {mu_peak:g} (must be > 0)")
    lo, hi = PLAUSIBLE_MU_PEAK
    if not lo <= mu_peak <= hi and not implausible(tire):
        warnings.warn(
            ImplausibleValue(
                "road",
                f"{road}: peak mu {mu_peak:g} is outside the plausible range [{lo:g}, {hi:g}]",
            ),
            stacklevel=2,
        )
    return tire


MAX_CSV_BYTES = 64 * 1024
"""Largest road CSV read: a table of at most MAX_TABLE_NODES rows is far smaller."""


def read_mu_slip_csv(path: str) -> TableTire:
    """A measured road: the mu-slip table of a UTF-8 CSV file (a byte-order mark allowed) with a
    header naming the columns `slip` and `mu` once each (other named columns are ignored), one
    node per row and no field beyond the header (TableTire's rules: 2 to 32 nodes, slips
    increasing strictly from 0 to 1, mu >= 0 and 0 at slip 0). Errors name the file, the row
    (the header is row 1) and the column."""
    text = read_input(path, "road", MAX_CSV_BYTES)
    try:
        rows = list(csv.reader(io.StringIO(text, newline="")))
    except csv.Error as exc:
        raise InputError("road", f"{path} is not a CSV file: {exc}") from None
    header = [h.strip().lower() for h in rows[0]] if rows else []
    missing = [c for c in ("slip", "mu") if c not in header]
    if missing:
        raise InputError(
            "road",
            f"{path} row 1: the header needs the columns slip and mu "
            f"(missing: {', '.join(missing)})",
        )
    twice = next((h for h in header if h and header.count(h) > 1), None)
    if twice is not None:
        raise InputError("road", f"{path} row 1: the column {twice} is named twice")
    columns = {c: header.index(c) for c in ("slip", "mu")}
    data: dict[str, list[float]] = {"slip": [], "mu": []}
    body = [(k, r) for k, r in enumerate(rows[1:], start=2) if any(x.strip() for x in r)]
    for k, row in body:
        if len(row) > len(header):
            raise InputError(
                "road",
                f"{path} row {k}: {len(row)} fields, more than the header's {len(header)}",
            )
        for name, j in columns.items():
            value_text = row[j].strip() if j < len(row) else ""
            try:
                value = number(value_text)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise InputError(
                    "road",
                    f"{path} row {k}, column {name}: expected a finite number, got {value_text!r}",
                )
            data[name].append(value)
    slips, mus = tuple(data["slip"]), tuple(data["mu"])
    problem = table_problem(slips, mus)
    if problem is not None:
        node, column, problem_text = problem
        where = f"row {body[node][0]}, column {column}" if node is not None else "rows"
        raise InputError("road", f"{path} {where}: {problem_text}")
    return TableTire(slips, mus)


def roughness_roads() -> dict[str, str]:
    """ISO 8608 road name -> one-line description."""
    return {
        name: f"ISO 8608 class {name[-1].upper()} random road, Gd(n0) = {gq * 1e6:g}e-6 m^3"
        for name, gq in ISO_CLASSES.items()
    }


def roughness_class(name: str) -> float:
    """Gq of an ISO 8608 road name (m^3), or InputError listing the known roads."""
    try:
        return ISO_CLASSES[name]
    except KeyError:
        raise InputError(
            "road", f"unknown road {name!r} for quarter-car (known: {', '.join(ISO_CLASSES)})"
        ) from None
