"""`chassistune tire FILE.tir`: a good file's report, and a bad file refused in one stderr line
naming the file's line, exit 2, with nothing on stdout and no warning."""

from __future__ import annotations

import math
from importlib.resources import files
from pathlib import Path

import pytest

from chassistune.plants.mf_peak import braking_peak
from chassistune.plants.tir import read_tir_file

SAMPLE_TIR = str(files("chassistune") / "data" / "tires" / "commonroad_pac2002.tir")
SAMPLE = Path(SAMPLE_TIR).read_text(encoding="utf-8")
CHRONO_TIR = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")
MF61_TIR = str(Path(__file__).parents[1] / "plants" / "data" / "MagicFormula61_Parameters.tir")


def line_of(text: str, start: str) -> int:
    return next(i for i, ln in enumerate(text.splitlines(), 1) if ln.startswith(start))


def test_the_report_of_the_sample(cli) -> None:
    r = cli("tire", SAMPLE_TIR)
    assert r.code == 0, r.err
    kappa, force_n = braking_peak(read_tir_file(SAMPLE_TIR).tire, 4000.0)
    assert "version: MF 5.2 (FITTYP 6)" in r.out
    assert "FNOMIN: 4000 N" in r.out and "UNLOADED_RADIUS: 0.344 m" in r.out
    assert f"mu = {-force_n / 4000.0:.4f} at kappa = {kappa:.4f}" in r.out
    assert "mu = 1.1739 at kappa = -0.1516" in r.out
    assert "absent, neutral values used (17): LFZO " in r.out
    assert "warning" not in r.err


def test_an_mf61_file_with_lateral_coefficients(cli) -> None:
    r = cli("tire", MF61_TIR, "--lateral")
    assert r.code == 0, r.err
    assert "version: MF 6.1 (FITTYP 61)" in r.out
    assert "mu = 1.0951 at kappa = -0.1071" in r.out
    assert "sigma_kappa at FNOMIN: 0.568 m" in r.out
    assert "ignored (80): PDX3 " in r.out and "absent, neutral values used (0): -" in r.out
    assert "sigma_alpha at FNOMIN: 0.7238 m (MF 6.1, |K / C| with LATERAL_STIFFNESS)" in r.out


def test_an_mf52_file_gives_its_lengths_from_ptx_and_pty(cli) -> None:
    """Chrono's PAC2002 file has no carcass stiffness: its lengths are MF 5.2's, at FNOMIN
    (dfz = 0) sigma_kappa = PTX1 R_0 LSGKP and sigma_alpha = PTY1 sin(2 arctan(1 / PTY2)) R_0
    LSGAL, by hand from the file's PTX1 1.9021, PTY1 1.8473, PTY2 1.9465, R_0 0.376 m."""
    r = cli("tire", CHRONO_TIR, "--lateral")
    assert r.code == 0, r.err
    sigma_kappa = 1.9021 * 0.376
    sigma_alpha = 1.8473 * math.sin(2.0 * math.atan(1.0 / 1.9465)) * 0.376
    assert f"sigma_kappa at FNOMIN: {sigma_kappa:.4g} m (MF 5.2, PTX1-3)" in r.out
    assert f"sigma_alpha at FNOMIN: {sigma_alpha:.4g} m (MF 5.2, PTY1-2)" in r.out
    r = cli("tire", CHRONO_TIR)
    assert "sigma_alpha" not in r.out


def test_a_file_without_lengths_says_which_coefficients_are_missing(cli) -> None:
    r = cli("tire", SAMPLE_TIR)
    assert "sigma_kappa at FNOMIN: not given (neither LONGITUDINAL_STIFFNESS nor PTX1-3)" in r.out


def test_a_file_named_like_a_field_is_named_as_given(
    cli, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`params.tir` is a file, not the parameter `tir` (`cli_field` leaves a file's line alone)."""
    monkeypatch.chdir(tmp_path)
    Path("params.tir").write_text(SAMPLE.replace("PDX1                     = 1.1739", "PDX1 = x"))
    r = cli("tire", "params.tir")
    assert r.code == 2
    assert r.err.startswith(f"chassistune: error: params.tir:{line_of(SAMPLE, 'PDX1')}: PDX1 = ")
    r = cli("tire", "absent.tir")
    assert r.code == 2
    assert (
        r.err == "chassistune: error: tire: cannot read 'absent.tir': No such file or directory\n"
    )


@pytest.mark.parametrize(
    ("edit", "bad_line", "problem"),
    [
        (("[VERTICAL]\n", ""), None, "without a [VERTICAL] section"),
        (("PDX1                     = 1.1739", "PDX1 = 1.17.39"), "PDX1", "not a finite number"),
        (("= 6                $", "= 62 $"), "FITTYP", "FITTYP = 62 is not a Magic"),
        (("[VERTICAL]\n", "[VERTICAL]\nFZMIN = -100\n"), "FZMIN", "must not be negative"),
    ],
)
def test_a_bad_file_is_one_line_and_exit_2(
    cli, tmp_path: Path, edit: tuple[str, str], bad_line: str | None, problem: str
) -> None:
    text = SAMPLE.replace(*edit)
    assert text != SAMPLE
    path = tmp_path / "bad.tir"
    path.write_text(text, encoding="utf-8")
    r = cli("tire", str(path))
    assert r.code == 2
    assert r.out == ""
    number = line_of(text, bad_line) if bad_line else len(text.splitlines())
    assert r.err.startswith(f"chassistune: error: {path}:{number}: ")
    assert problem in r.err
    assert r.err.count("\n") == 1  # one line, and no warning before it
