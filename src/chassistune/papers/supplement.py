"""What every paper's section gets beside its results: the paper's parameter and rule tables
(`param_tables`), its setting figures (mu-slip curves, road input, membership functions), the
tuned parameter sets of the runs shown (`tuned`), the tuned factors (deffao-vehicle-abs Fig. 6)
and the convergence of every controller tuning (`figures`)."""

from __future__ import annotations

from collections.abc import Callable

from chassistune.papers import (
    deffao_vehicle_abs,
    derlsp_ao_abs,
    figures,
    fuzzy_immune_abs,
    iabc_suspension,
    param_tables,
    tuned,
)
from chassistune.papers.common import Context, Figure, PaperSection

CONTROLLER_STUDIES = {
    derlsp_ao_abs.KEY: derlsp_ao_abs.STUDIES[0],
    iabc_suspension.KEY: iabc_suspension.STUDY,
    deffao_vehicle_abs.KEY: deffao_vehicle_abs.VEHICLE_STUDY,
    fuzzy_immune_abs.KEY: fuzzy_immune_abs.STUDY,
}
"""The study of each paper that tunes controllers (the others tune benchmark functions)."""


def _derlsp(ctx: Context) -> list[Figure]:
    return [figures.mu_slip(ctx, derlsp_ao_abs.KEY, [r for r, _, _ in derlsp_ao_abs.ROADS], "2")]


def _iabc(ctx: Context) -> list[Figure]:
    return [figures.road_profiles(ctx, iabc_suspension.KEY, "paper-iabc", ("iso-b", "iso-c"))]


def _deffao(ctx: Context) -> list[Figure]:
    key = deffao_vehicle_abs.KEY
    return [
        figures.mu_slip(ctx, key, ("dry-concrete", "ice"), "2"),
        figures.memberships(ctx, key, "deffao", "4"),
    ]


SETTING_FIGURES: dict[str, Callable[[Context], list[Figure]]] = {
    derlsp_ao_abs.KEY: _derlsp,
    iabc_suspension.KEY: _iabc,
    deffao_vehicle_abs.KEY: _deffao,
}
"""The figures of each paper that draw its setting, in the paper's order (shown first)."""


def _tuned_factors(ctx: Context, sec: PaperSection) -> None:
    """deffao-vehicle-abs Fig. 6, placed before Figs. 7-9."""
    data = ctx.studies[CONTROLLER_STUDIES[sec.key]]
    cell = data.scenarios[0]
    spec = data.runs(cell)[0].spec
    defaults = tuned.default_parameters(spec)
    fig = figures.tuned_factors(ctx, sec.key, data, cell, defaults)
    at = next((i for i, f in enumerate(sec.figures) if "_fig7_" in f.path.name), len(sec.figures))
    sec.figures.insert(at, fig)


def supplement(sec: PaperSection, ctx: Context) -> PaperSection:
    """Add the paper's own tables (first), setting figures (first), tuned parameter tables and
    tuning convergence (last) to `sec`; returns it."""
    sec.tables[:0] = param_tables.paper_tables(sec.key)
    sec.figures[:0] = SETTING_FIGURES.get(sec.key, lambda _: [])(ctx)
    study = CONTROLLER_STUDIES.get(sec.key)
    if study is None or study not in ctx.studies or not ctx.studies[study].records:
        return sec
    data = ctx.studies[study]
    if sec.key == deffao_vehicle_abs.KEY:
        _tuned_factors(ctx, sec)
    sec.tables += tuned.tuned_tables(sec.key, data)
    sec.figures.append(figures.tuning_convergence(ctx, sec.key, data))
    return sec
