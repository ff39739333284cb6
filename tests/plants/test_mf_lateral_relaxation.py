"""The lateral relaxation length sigma_alpha of a TIR file, by hand: MF 5.2's from PTY1-2 on the
shipped Chrono PAC2002 sample, MF 6.1's |K_yalpha / C_y| from LATERAL_STIFFNESS and PCFY1-2 on
MFeval's MF 6.1 sample; and on the vehicle, `relaxation_length_m=tire` at m g / 4."""

from __future__ import annotations

import math
import warnings
from importlib.resources import files
from pathlib import Path

import pytest

from chassistune.plants import mf_coefficients as mfc
from chassistune.plants.mf_relaxation import (
    lateral_relaxation_length_m,
    longitudinal_relaxation_length_m,
)
from chassistune.plants.tir import read_tir

CHRONO = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")
MF61 = str(Path(__file__).parent / "data" / "MagicFormula61_Parameters.tir")


def _read(path: str, lateral: bool = True):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tire = read_tir(path, lateral=lateral)
    return tire, [str(w.message) for w in caught]


def test_mf52_lateral_length_from_pty1_pty2_by_hand() -> None:
    """Chrono's sample (PTY1 1.8473, PTY2 1.9465, R0 0.376 m, FNOMIN 3800 N, LFZO = LSGAL = 1):
    sigma_alpha = PTY1 sin(2 arctan(F_z / (PTY2 FNOMIN))) R0, largest (PTY1 R0 = 0.6946 m) at
    F_z = PTY2 FNOMIN; PTY1-2 are read, no longer ignored."""
    tire, warned = _read(CHRONO)
    assert (tire.pty1, tire.pty2, tire.lsgal, tire.lateral_stiffness_n_m) == (1.8473, 1.9465, 1, 0)
    assert not any(" PTY1" in w or " PTY2" in w for w in warned if "ignored" in w)
    c = tire.kernel_array()
    for fz in (981.0, 2719.5, 3800.0, 6000.0):
        expected = 1.8473 * math.sin(2.0 * math.atan(fz / (1.9465 * 3800.0))) * 0.376
        assert lateral_relaxation_length_m(c, fz) == pytest.approx(expected, rel=1e-14)
    assert lateral_relaxation_length_m(c, 1.9465 * 3800.0) == pytest.approx(1.8473 * 0.376)
    scaled = c.copy()
    scaled[mfc.LSGAL] = 0.5
    assert lateral_relaxation_length_m(scaled, 3800.0) == 0.5 * lateral_relaxation_length_m(
        c, 3800.0
    )
    none = c.copy()
    none[mfc.PTY1] = 0.0
    assert math.isnan(lateral_relaxation_length_m(none, 3800.0))


def test_mf61_lateral_length_from_the_carcass_stiffness_by_hand() -> None:
    """MFeval's MF 6.1 sample: C_y = LATERAL_STIFFNESS (1 + PCFY1 dfz + PCFY2 dfz^2) and
    K_yalpha = PKY1 F_z0 sin(PKY4 arctan(F_z / (PKY2 F_z0))) (4.E25 at zero camber); at FNOMIN
    MFeval's K_yalpha (-137436.33 N/rad, tests/plants/data/mfeval_reference.csv) over
    LATERAL_STIFFNESS 189871.776 N/m, 0.7238 m (PCFY3, the pressure term, is not read)."""
    tire, _ = _read(MF61)
    assert (tire.lateral_stiffness_n_m, tire.pcfy1, tire.pcfy2) == (189871.776, -0.2334, 0.068881)
    c = tire.kernel_array()
    fz0 = 6752.0
    for fz in (2000.0, 4000.0, fz0, 9000.0):
        dfz = (fz - fz0) / fz0
        ky = -28.3155 * fz0 * math.sin(2.7364 * math.atan(fz / (3.313 * fz0)))
        cy = 189871.776 * (1.0 - 0.2334 * dfz + 0.068881 * dfz * dfz)
        assert lateral_relaxation_length_m(c, fz) == pytest.approx(abs(ky / cy), rel=1e-13)
    assert lateral_relaxation_length_m(c, fz0) == pytest.approx(137436.33267174475 / 189871.776)


def test_a_longitudinal_read_leaves_the_lateral_terms_unread_and_unwarned() -> None:
    tire, warned = _read(MF61, lateral=False)
    assert tire.lateral_stiffness_n_m == 0.0 and tire.pty1 == 0.0
    assert not any("LATERAL_STIFFNESS" in w or "PCFY1" in w for w in warned)


def test_the_vehicle_takes_the_files_lengths_at_a_quarter_of_its_weight() -> None:
    """`relaxation_length_m=tire` and `lateral_relaxation_length_m=tire` with Chrono's file on
    paper-deffao: both lengths at m g / 4 = 2719.5 N, by hand (MF 5.2: PTX1-3 and PTY1-2)."""
    from chassistune.scenarios.abs_vehicle import PLANT

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sc = PLANT.scenario(
            None,
            "dry-concrete",
            "pid",
            {
                "tire": CHRONO,
                "dt_s": 2e-4,
                "relaxation_length_m": "tire",
                "lateral_relaxation_length_m": "tire",
            },
        )
    fz = 1110.0 * 9.8 / 4.0
    dfz = (fz - 3800.0) / 3800.0
    sigma_x = fz * (1.9021 - 0.0014739 * dfz) * math.exp(-0.03631 * dfz) * 0.376 / 3800.0
    sigma_y = 1.8473 * math.sin(2.0 * math.atan(fz / (1.9465 * 3800.0))) * 0.376
    pp = sc.plant_params
    assert pp.relaxation_length_m == pytest.approx(sigma_x, rel=1e-12)
    assert pp.lateral_relaxation_length_m == pytest.approx(sigma_y, rel=1e-12)
    assert sc.params()["lateral_relaxation_length_m"] == pp.lateral_relaxation_length_m
    c = sc.tire.surfaces[0].kernel_array()
    assert pp.relaxation_length_m == longitudinal_relaxation_length_m(c, fz)
