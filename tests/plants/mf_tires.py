"""Tires for the Magic Formula tests: the shipped sample file and CommonRoad's parameter set."""

from __future__ import annotations

import dataclasses
import warnings
from importlib.resources import files

from chassistune.plants.mf_coefficients import MagicFormulaTire, neutral, tir_name
from chassistune.plants.tir import read_tir

SAMPLE_TIR = str(files("chassistune") / "data" / "tires" / "commonroad_pac2002.tir")
CHRONO_TIR = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")


def sample_tire() -> MagicFormulaTire:
    """The shipped sample (longitudinal coefficients only; its warnings silenced)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_tir(SAMPLE_TIR)


def chrono_tire() -> MagicFormulaTire:
    """The shipped Project Chrono 185/80 R14 (PAC2002, load terms, lateral coefficients)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_tir(CHRONO_TIR, lateral=True)


def neutral_tire(**values: float) -> MagicFormulaTire:
    """A tire of neutral coefficients, FNOMIN 4000 N, radius 0.3 m, and `values` set."""
    base = {f.name: neutral(tir_name(f.name)) for f in dataclasses.fields(MagicFormulaTire)}
    base.update(fnomin_n=4000.0, unloaded_radius_m=0.3)
    return MagicFormulaTire(**{**base, **values})


def load_sensitive_tire() -> MagicFormulaTire:
    """The sample's coefficients plus load, asymmetry and lateral terms of MF 6.1 magnitudes
    (test values, not a measured tire), so that every dfz path is exercised."""
    t = sample_tire()
    return dataclasses.replace(
        t, pdx2=-0.07, pex2=0.12, pex3=-0.03, pex4=0.2, pkx2=-0.5, pkx3=0.4, phx2=0.001,
        pvx2=1e-4, pcy1=1.35, pdy1=1.05, pdy2=-0.08, pey1=-0.5, pey2=-0.2, pey3=0.15,
        pky1=-21.9, pky2=2.0, pky4=1.9, phy1=0.0027, phy2=0.0011, pvy1=0.037, pvy2=-0.01,
    )  # fmt: skip
