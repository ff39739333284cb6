"""`chassistune tire FILE.tir [--lateral]`: what a tyre property file gives the Magic Formula
tire (docs/tires.md): its version, nominal load and radius, the braking peak at the nominal load,
and the coefficients it sets that are ignored or lacks (neutral values used).

A file the reader refuses is one stderr line naming the file's line, and exit 2 (`cli.main`).
"""

from __future__ import annotations

import click


@click.command("tire")
@click.argument("file", metavar="FILE.tir")
@click.option(
    "--lateral", is_flag=True, help="Read the lateral coefficients too (PCY1, PDY1, PKY1, PKY2)."
)
def tire_command(file: str, lateral: bool) -> None:
    """Inspect a tyre property file (.tir): version, FNOMIN, radius, the braking peak mu and its
    slip at FNOMIN, ignored and absent coefficients."""
    from chassistune.plants.mf_peak import braking_peak
    from chassistune.plants.mf_relaxation import longitudinal_relaxation_length_m
    from chassistune.plants.tir import read_tir_file

    contents = read_tir_file(file, lateral=lateral)
    tire = contents.tire
    fz_n = tire.fnomin_n
    kappa, force_n = braking_peak(tire, fz_n)
    c = tire.kernel_array()
    sigma = (
        f"{longitudinal_relaxation_length_m(c, fz_n):.4g} m"
        if tire.longitudinal_stiffness_n_m > 0.0
        else "not given (no LONGITUDINAL_STIFFNESS)"
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
        _names("ignored", contents.ignored),
        _names("absent, neutral values used", contents.absent),
    ]
    click.echo("\n".join(lines))


def _names(what: str, names: tuple[str, ...]) -> str:
    return f"{what} ({len(names)}): {' '.join(names) if names else '-'}"
