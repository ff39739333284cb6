"""The Magic Formula 6.1 coefficients our force equations use (`plants.magic_formula`), in SI.

`MagicFormulaTire` is what `plants.tir.read_tir` returns: one frozen dataclass of floats, in the
order of the kernel array (`kernel_array`), whose indices are the upper-case names below, so a
compiled force function reads `c[PCX1]`. Names are the TIR file's, lower-case; the three
dimensional ones carry their SI unit. LONGITUDINAL_STIFFNESS and PCFX1-2 (MF 6.1), or PTX1-3
and LSGKP (MF 5.2), give the longitudinal relaxation length, LATERAL_STIFFNESS and PCFY1-2, or
PTY1-2 and LSGAL, the lateral one (`plants.mf_relaxation`). Absent coefficients
take the neutral values of `neutral`: 0 for shifts and load terms, 1 for the scaling factors
(LFZO, LCX, ...), PKY4 = 2 (MF 5.2's constant, which 6.1 made a coefficient).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class MagicFormulaTire:
    """MF 6.1 coefficients for longitudinal, lateral and combined slip at zero camber, no turn
    slip and nominal inflation pressure (Pacejka 2012, eqs. 4.E1-4.E30, 4.E50-4.E67)."""

    fnomin_n: float
    unloaded_radius_m: float
    fzmin_n: float
    fzmax_n: float
    lfzo: float
    lcx: float
    lmux: float
    lex: float
    lkx: float
    lhx: float
    lvx: float
    lcy: float
    lmuy: float
    ley: float
    lky: float
    lhy: float
    lvy: float
    lxal: float
    lyka: float
    lvyka: float
    pcx1: float
    pdx1: float
    pdx2: float
    pex1: float
    pex2: float
    pex3: float
    pex4: float
    pkx1: float
    pkx2: float
    pkx3: float
    phx1: float
    phx2: float
    pvx1: float
    pvx2: float
    pcy1: float
    pdy1: float
    pdy2: float
    pey1: float
    pey2: float
    pey3: float
    pky1: float
    pky2: float
    pky4: float
    phy1: float
    phy2: float
    pvy1: float
    pvy2: float
    rbx1: float
    rbx2: float
    rcx1: float
    rex1: float
    rex2: float
    rhx1: float
    rby1: float
    rby2: float
    rby3: float
    rcy1: float
    rey1: float
    rey2: float
    rhy1: float
    rhy2: float
    rvy1: float
    rvy2: float
    rvy4: float
    rvy5: float
    rvy6: float
    longitudinal_stiffness_n_m: float
    pcfx1: float
    pcfx2: float
    ptx1: float
    ptx2: float
    ptx3: float
    lsgkp: float
    lateral_stiffness_n_m: float
    pcfy1: float
    pcfy2: float
    pty1: float
    pty2: float
    lsgal: float

    def kernel_array(self) -> np.ndarray:
        """The coefficients as one float64 array, indexed by the module's upper-case constants."""
        return np.array([getattr(self, f.name) for f in dataclasses.fields(self)], dtype=np.float64)


(
    FNOMIN_N,
    UNLOADED_RADIUS_M,
    FZMIN_N,
    FZMAX_N,
    LFZO,
    LCX,
    LMUX,
    LEX,
    LKX,
    LHX,
    LVX,
    LCY,
    LMUY,
    LEY,
    LKY,
    LHY,
    LVY,
    LXAL,
    LYKA,
    LVYKA,
    PCX1,
    PDX1,
    PDX2,
    PEX1,
    PEX2,
    PEX3,
    PEX4,
    PKX1,
    PKX2,
    PKX3,
    PHX1,
    PHX2,
    PVX1,
    PVX2,
    PCY1,
    PDY1,
    PDY2,
    PEY1,
    PEY2,
    PEY3,
    PKY1,
    PKY2,
    PKY4,
    PHY1,
    PHY2,
    PVY1,
    PVY2,
    RBX1,
    RBX2,
    RCX1,
    REX1,
    REX2,
    RHX1,
    RBY1,
    RBY2,
    RBY3,
    RCY1,
    REY1,
    REY2,
    RHY1,
    RHY2,
    RVY1,
    RVY2,
    RVY4,
    RVY5,
    RVY6,
    LONGITUDINAL_STIFFNESS_N_M,
    PCFX1,
    PCFX2,
    PTX1,
    PTX2,
    PTX3,
    LSGKP,
    LATERAL_STIFFNESS_N_M,
    PCFY1,
    PCFY2,
    PTY1,
    PTY2,
    LSGAL,
) = range(79)
"""Index of each coefficient in `MagicFormulaTire.kernel_array()` (the dataclass's field order)."""
if (PCFX1, PCFX2, PCFY1, PCFY2) != (
    LONGITUDINAL_STIFFNESS_N_M + 1,
    LONGITUDINAL_STIFFNESS_N_M + 2,
    LATERAL_STIFFNESS_N_M + 1,
    LATERAL_STIFFNESS_N_M + 2,
):  # pragma: no cover
    raise RuntimeError("a carcass stiffness's load terms must follow it (`carcass_length_m`)")
N_MF_COEFFICIENTS = len(dataclasses.fields(MagicFormulaTire))
"""Length of `MagicFormulaTire.kernel_array`."""

REQUIRED_LONGITUDINAL = ("FNOMIN", "UNLOADED_RADIUS", "PCX1", "PDX1", "PKX1")
"""Coefficients without which there is no longitudinal force: an absent one is an error."""

REQUIRED_LATERAL = ("PCY1", "PDY1", "PKY1", "PKY2")
"""Likewise for the lateral force (required only when lateral forces are asked for)."""

LATERAL_ONLY = frozenset(
    {"LCY", "LMUY", "LEY", "LKY", "LHY", "LVY", "LYKA", "LVYKA"}
    | {f"P{k}Y{i}" for k in "CDEKHV" for i in range(1, 5)}
    | {f"R{k}Y{i}" for k in "BCEHV" for i in range(1, 7)}
    | {"LATERAL_STIFFNESS", "PCFY1", "PCFY2", "PTY1", "PTY2", "LSGAL"}
)
"""TIR names used only by the lateral force (not read, not warned about, for longitudinal use)."""


def tir_name(field_name: str) -> str:
    """The TIR file's name of a field: upper case without the SI suffix."""
    for suffix in ("_n_m", "_n", "_m"):
        if field_name.endswith(suffix):
            return field_name[: -len(suffix)].upper()
    return field_name.upper()


def neutral(name: str) -> float:
    """A coefficient's neutral value (its TIR name): 1 for a scaling factor (L...), 2 for PKY4,
    else 0 (shifts, load and combined-slip terms); FZMAX has none (no upper limit: inf), nor
    LONGITUDINAL_STIFFNESS and LATERAL_STIFFNESS (0: not given, no relaxation length from the
    file)."""
    if name == "FZMAX":
        return float("inf")
    if name in ("LONGITUDINAL_STIFFNESS", "LATERAL_STIFFNESS"):
        return 0.0
    if name == "PKY4":
        return 2.0
    return 1.0 if name.startswith("L") else 0.0
