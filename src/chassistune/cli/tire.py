"""`chassistune tire FILE.tir [--lateral]`: what a tyre property file gives the Magic Formula
tire (docs/tires.md): its version, nominal load and radius, the braking peak at the nominal load,
the relaxation lengths at the nominal load and which coefficients give them (`plants.mf_relaxation`:
MF 6.1's carcass stiffness, else MF 5.2's PTX1-3 / PTY1-2), and the coefficients it sets that are
ignored or lacks (neutral values used).

A file the reader refuses is one stderr line naming the file's line, and exit 2 (`cli.main`).
"""

from __future__ import annotations

import math

import click


@click.command("tire")
@click.argument("file", metavar="FILE.tir")
@click.option(
    "--lateral",
    is_flag=True,
    help="Read the lateral coefficients too (PCY1, PDY1, PKY1, PKY2) and report the lateral "
    "relaxation length sigma_alpha.",
)
def tire_command(file: str, lateral: bool) -> None:
    """Inspect a tyre property file (.tir): version, FNOMIN, radius, the braking peak mu and its
    slip at FNOMIN, the relaxation lengths at FNOMIN (m), ignored and absent coefficients."""
    click.echo("\n".join(report_lines(file, lateral)))


def report_lines(file: str, lateral: bool) -> list[str]:
    """What `chassistune tire` prints about the tyre property file `file`."""
    from chassistune.plants.mf_peak import braking_peak
    from chassistune.plants.mf_relaxation import (
        lateral_relaxation_length_m,
        longitudinal_relaxation_length_m,
    )
    from chassistune.plants.tir import read_tir_file

    contents = read_tir_file(file, lateral=lateral)
    tire = contents.tire
    fz_n = tire.fnomin_n
    kappa, force_n = braking_peak(tire, fz_n)
    c = tire.kernel_array()
    sigma = _length(
        float(longitudinal_relaxation_length_m(c, fz_n)),
        tire.longitudinal_stiffness_n_m > 0.0,
        ("LONGITUDINAL_STIFFNESS", "PTX1-3"),
    )
    lines = [
        f"file: {file}",
        f"version: {contents.version} (FITTYP {contents.fittyp}), read by the MF 6.1 equations "
        "at zero camber and nominal pressure",
        f"FNOMIN: {fz_n:g} N",
        f"UNLOADED_RADIUS: {tire.unloaded_radius_m:g} m",
        f"braking peak at FNOMIN: mu = {-force_n / fz_n:.4f} at kappa = {kappa:.4f} "
        f"(F_x = {force_n:.1f} N)",
        f"relaxation length sigma_kappa at FNOMIN: {sigma}",
        f"lateral coefficients: {'read' if lateral else 'not read (--lateral)'}",
    ]
    if lateral:
        sigma_alpha = _length(
            float(lateral_relaxation_length_m(c, fz_n)),
            tire.lateral_stiffness_n_m > 0.0,
            ("LATERAL_STIFFNESS", "PTY1-2"),
        )
        lines.append(f"relaxation length sigma_alpha at FNOMIN: {sigma_alpha}")
    lines += [
        _names("ignored", contents.ignored),
        _names("absent, neutral values used", contents.absent),
    ]
    return lines


def _length(sigma_m: float, carcass: bool, names: tuple[str, str]) -> str:
    """A relaxation length and what gives it: MF 6.1's carcass stiffness `names[0]`, else MF
    5.2's coefficients `names[1]` (`mf_relaxation`, NaN where the file gives neither)."""
    if math.isnan(sigma_m):
        return f"not given (neither {names[0]} nor {names[1]})"
    source = f"MF 6.1, |K / C| with {names[0]}" if carcass else f"MF 5.2, {names[1]}"
    return f"{sigma_m:.4g} m ({source})"


def _names(what: str, names: tuple[str, ...]) -> str:
    return f"{what} ({len(names)}): {' '.join(names) if names else '-'}"
