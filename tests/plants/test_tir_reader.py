"""The TIR reader: values in SI, one warning each for absent and ignored coefficients, and bad
files refused with one line naming the file and line, with no warning."""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import pytest
from mf_tires import SAMPLE_TIR

from chassistune.errors import InputError
from chassistune.plants import mf_coefficients
from chassistune.plants.mf_coefficients import MagicFormulaTire
from chassistune.plants.tir import TirWarning, read_tir

SAMPLE = Path(SAMPLE_TIR).read_text(encoding="utf-8")


def line_of(text: str, start: str) -> int:
    """The 1-based number of the first line of `text` starting with `start`."""
    return next(i for i, ln in enumerate(text.splitlines(), 1) if ln.startswith(start))


def write(tmp_path: Path, text: str) -> str:
    path = tmp_path / "tyre.tir"
    path.write_text(text, encoding="utf-8")
    return str(path)


def read_recording(path: str, lateral: bool = False) -> tuple[MagicFormulaTire, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tire = read_tir(path, lateral=lateral)
    return tire, [str(w.message) for w in caught if issubclass(w.category, TirWarning)]


def refused(path: str, lateral: bool = False) -> str:
    """The error message of a refused file (asserting no warning came with it)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(InputError) as exc:
            read_tir(path, lateral=lateral)
    assert caught == []
    message = str(exc.value)
    assert "\n" not in message
    return message


def test_kernel_indices_follow_the_dataclass_fields() -> None:
    for i, f in enumerate(dataclasses.fields(MagicFormulaTire)):
        assert getattr(mf_coefficients, f.name.upper()) == i


def test_the_sample_reads_with_one_warning_listing_the_absent_coefficients() -> None:
    tire, warned = read_recording(SAMPLE_TIR)
    assert (tire.fnomin_n, tire.unloaded_radius_m, tire.pcx1, tire.pkx1) == (
        4000.0, 0.344, 1.6411, 22.303,
    )  # fmt: skip
    assert tire.pky4 == 2.0  # FITTYP 6: MF 5.2's constant
    assert (tire.lmux, tire.pdx2, tire.fzmax_n) == (1.0, 0.0, float("inf"))
    assert len(warned) == 1
    assert "absent" in warned[0] and " PDX2 " in warned[0] and " LMUX " in warned[0]
    assert "PCY1" not in warned[0]  # lateral coefficients not asked for
    assert "PCFX1" not in warned[0]  # relaxation: not a force coefficient


def test_units_convert_to_si_and_ignored_coefficients_warn_once(tmp_path: Path) -> None:
    text = SAMPLE.replace("'newton'", "'kN'").replace("'meter'", "'mm'")
    text = text.replace("= 4000 ", "= 4 ").replace("= 0.344 ", "= 344 ")
    text = text.replace("PDX3                     = 0", "PDX3 = 0.1\nQSX1 = 0.02\nPPX1 = 0")
    tire, warned = read_recording(write(tmp_path, text))
    assert tire.fnomin_n == pytest.approx(4000.0) and tire.unloaded_radius_m == pytest.approx(0.344)
    ignored = [w for w in warned if "ignored" in w]
    assert len(ignored) == 1 and ignored[0].endswith(": PDX3 QSX1")  # PPX1 = 0 is neutral


def test_lateral_forces_need_pky2(tmp_path: Path) -> None:
    message = refused(SAMPLE_TIR, lateral=True)
    assert f"{SAMPLE_TIR}:{len(SAMPLE.splitlines())}" in message and "PKY2" in message
    text = SAMPLE.replace("PKY1 ", "PKY2 = 2.0\nPKY1 ")
    tire, warned = read_recording(write(tmp_path, text), lateral=True)
    assert (tire.pky1, tire.pky2) == (-21.92, 2.0)
    assert any("PDY3" in w for w in warned if "ignored" in w)  # a camber term, ignored


def test_missing_section(tmp_path: Path) -> None:
    path = write(tmp_path, SAMPLE.replace("[VERTICAL]\n", ""))
    message = refused(path)
    n_lines = len(SAMPLE.splitlines()) - 1
    assert message.startswith(f"{path}:{n_lines}: ")
    assert "[VERTICAL]" in message


def test_non_numeric_value(tmp_path: Path) -> None:
    path = write(tmp_path, SAMPLE.replace("PDX1                     = 1.1739", "PDX1 = 1.17.39"))
    message = refused(path)
    assert message.startswith(f"{path}:{line_of(SAMPLE, 'PDX1')}: ")
    assert "PDX1" in message and "'1.17.39'" in message and "not a finite number" in message


@pytest.mark.parametrize("fittyp", ["52", "62", "'abc'"])
def test_unknown_mf_version(tmp_path: Path, fittyp: str) -> None:
    path = write(tmp_path, SAMPLE.replace("= 6                $", f"= {fittyp} $"))
    message = refused(path)
    assert message.startswith(f"{path}:{line_of(SAMPLE, 'FITTYP')}: ")
    assert "FITTYP" in message


@pytest.mark.parametrize(
    ("limits", "bad", "problem"),
    [
        ("FZMIN = -100\nFZMAX = 9000\n", "FZMIN", "must not be negative"),
        ("FZMIN = 5000\nFZMAX = 1000\n", "FZMAX", "inverted"),
    ],
)
def test_negative_or_inverted_load_range(
    tmp_path: Path, limits: str, bad: str, problem: str
) -> None:
    text = SAMPLE.replace("[VERTICAL]\n", f"[VERTICAL]\n{limits}")
    path = write(tmp_path, text)
    message = refused(path)
    assert message.startswith(f"{path}:{line_of(text, bad)}: ")
    assert problem in message


@pytest.mark.parametrize(
    ("edit", "problem"),
    [
        (("PCX1                     = 1.6411", "PCX1 1.6411"), "expected NAME = value"),
        (("PKX1 ", "PKX1 = 3\nPKX1 "), "given twice"),
        (("'meter'", "'furlong'"), "unknown unit"),
        (("PKX1                     = 22.303", ""), "without PKX1"),
    ],
)
def test_other_malformed_files(tmp_path: Path, edit: tuple[str, str], problem: str) -> None:
    path = write(tmp_path, SAMPLE.replace(*edit))
    message = refused(path)
    assert message.startswith(f"{path}:") and problem in message


def test_a_pac2002_file_without_fittyp_is_mf52_and_names_may_recur_across_sections(
    tmp_path: Path,
) -> None:
    text = SAMPLE.replace("FITTYP                   = 6                $ MF 5.2 / PAC2002",
                          "PROPERTY_FILE_FORMAT = 'PAC2002'")  # fmt: skip
    text = text.replace("[VERTICAL]\n", "[INERTIA]\nMASS = 9.3\n[VERTICAL]\n")  # and in [UNITS]
    tire, _ = read_recording(write(tmp_path, text))
    assert tire == read_recording(SAMPLE_TIR)[0]


def test_an_unknown_property_file_format_without_fittyp(tmp_path: Path) -> None:
    text = SAMPLE.replace("FITTYP                   = 6                $ MF 5.2 / PAC2002",
                          "PROPERTY_FILE_FORMAT = 'MF_TYRE_99'")  # fmt: skip
    path = write(tmp_path, text)
    message = refused(path)
    assert message.startswith(f"{path}:{line_of(SAMPLE, 'FITTYP')}: ")
    assert "PROPERTY_FILE_FORMAT" in message and "MF_TYRE_99" in message


def test_a_force_coefficient_in_two_sections(tmp_path: Path) -> None:
    text = SAMPLE.replace("[LATERAL_COEFFICIENTS]\n", "[LATERAL_COEFFICIENTS]\nPKX1 = 20\n")
    path = write(tmp_path, text)
    message = refused(path)
    assert message.startswith(f"{path}:{line_of(text, 'PKX1 = 20')}: ")
    assert f"first on line {line_of(SAMPLE, 'PKX1')}" in message
