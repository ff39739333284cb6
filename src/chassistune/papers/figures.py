"""The papers' figures that show a setting rather than a study's result: the mu-slip curves of the
roads (derlsp-ao-abs Fig. 2, deffao-vehicle-abs Fig. 2), the random road input (iabc-suspension
Fig. 2), the membership functions (deffao-vehicle-abs Fig. 4), the tuned fuzzy factors
(deffao-vehicle-abs Fig. 6), the four controllers of a vehicle road (deffao-vehicle-abs Figs. 7-9)
and the convergence of every controller tuning of a study. Each caption says whether tuned or
default controllers are drawn."""

from __future__ import annotations

from collections.abc import Sequence

from chassistune.fuzzy.loader import load_rulebase
from chassistune.papers.common import Context, Figure
from chassistune.plants.roads import tire_for_road
from chassistune.reports.figures import convergence_panels_figure
from chassistune.reports.tables import StudyData
from chassistune.scenarios.base import Trace
from chassistune.scenarios.registry import get_plant

DEFAULTS_DRAWN = "No controller is drawn: this figure shows the setting."
BENCHMARK_CAPTION = "No controller is drawn: the optimizers on a benchmark function."
WHEELS = ("fl", "fr", "rl", "rr")


def mu_slip(ctx: Context, key: str, roads: Sequence[str], fig: str) -> Figure:
    """The bilinear mu-slip curves of `roads` (eq. 5 with Table 1's S_T, mu_h, mu_g)."""
    from chassistune.plots.roads import plot_mu_slip

    path = ctx.figure(key, f"fig{fig}_mu_slip")
    plot_mu_slip(
        {r: tire_for_road(r, {})[0] for r in roads},
        str(path),
        f"Fig. {fig} redrawn: bilinear tire model, mu against slip",
    )
    return Figure(
        path.stem,
        f"Fig. {fig} redrawn: mu-slip curves of {', '.join(roads)}",
        path,
        "Our roads as the controllers see them (package roads, from the paper's table of road "
        "parameters). " + DEFAULTS_DRAWN,
    )


def road_profiles(ctx: Context, key: str, preset: str, roads: Sequence[str]) -> Figure:
    """Fig. 2 of iabc-suspension: the filtered white-noise road input z0(t) of each class
    (realization 0, the preset's speed and duration)."""
    from chassistune.plots.road_profile import plot_road_profiles

    plant = get_plant("quarter-car")
    profiles = []
    for road in roads:
        sc = plant.scenario(preset, road, "passive", {}, 0)
        tr = sc.trace(sc.gains_array(None))
        profiles.append((road, tr.signals["time_s"], tr.signals["road_m"]))
    path = ctx.figure(key, "fig2_road_profile")
    plot_road_profiles(
        profiles, str(path), "Fig. 2 redrawn: random road input (eq. 3, ISO 8608 classes)"
    )
    return Figure(
        path.stem,
        "Fig. 2 redrawn: road displacement input",
        path,
        "The paper's Fig. 2 is titled class C; its abstract and Table 1's coefficient 64e-6 "
        "are class B, the class we tune on. Realization 0 (seed 0) of each: the same white "
        "noise, so class C is class B doubled. " + DEFAULTS_DRAWN,
    )


def memberships(ctx: Context, key: str, rulebase: str, fig: str) -> Figure:
    """The membership functions of the rule base `rulebase` (package data)."""
    from chassistune.plots.fuzzy import plot_memberships

    rb = load_rulebase(rulebase)
    path = ctx.figure(key, f"fig{fig}_membership")
    plot_memberships(rb, path, f"Fig. {fig} redrawn: membership functions (rule base {rb.name})")
    return Figure(
        path.stem,
        f"Fig. {fig} redrawn: membership functions of the inputs and outputs",
        path,
        "The paper draws the sets without numbers: the universes and peaks are ours (the rule "
        "base file's header says which). " + DEFAULTS_DRAWN,
    )


def tuned_factors(
    ctx: Context, key: str, data: StudyData, cell: str, scenario_defaults: dict[str, float]
) -> Figure:
    """Fig. 6 of deffao-vehicle-abs: every seed's tuned parameter set of each optimizer in its
    search box, beside the defaults."""
    from chassistune.plots.factors import plot_factors_in_box

    tuned = {o: [r.best_gains for r in data.runs(cell, o)] for o in data.optimizers}
    tuned = {o: sets for o, sets in tuned.items() if sets}
    bounds = next(iter(data.runs(cell))).spec.bounds
    path = ctx.figure(key, "fig6_tuned_factors")
    plot_factors_in_box(
        {n: (float(lo), float(hi)) for n, (lo, hi) in bounds.items()},
        tuned,
        scenario_defaults,
        str(path),
        "Fig. 6 redrawn: fuzzy PID factors tuned by each optimizer",
    )
    return Figure(
        path.stem,
        "Fig. 6 redrawn: the tuned fuzzy control factors",
        path,
        "Tuned: every seed's final parameter set of each optimizer (points; bars: the median), "
        "placed in its search box; crosses: the catalogue defaults. The paper plots its factors "
        "without a box; the values are in the tuned-parameters table.",
    )


def vehicle_comparison(
    ctx: Context, key: str, road: str, fig: str, runs: Sequence[tuple[str, Trace]]
) -> Figure:
    """Figs. 7-9 of deffao-vehicle-abs: the four controllers on one road, car speed, distance and
    the four wheels' slips."""
    from chassistune.plots.overlay import Line, plot_overlay

    panels = [("speed_m_s", "car speed [m/s]"), ("distance_m", "distance [m]")]
    panels += [(f"slip_{w}", f"slip {w} [-]") for w in WHEELS]
    lines = [
        Line(
            f"{label}: {tr.metrics['stop_distance_m']:.1f} m",
            tr.signals["time_s"],
            tr.signals,
        )
        for label, tr in runs
    ]
    path = ctx.figure(key, f"fig{fig}_{road}")
    plot_overlay(panels, lines, str(path), f"Fig. {fig} redrawn: {road}, four controllers")
    return Figure(
        path.stem,
        f"Fig. {fig} redrawn ({road}): PID, fuzzy PID, AO- and DEFFAO-fuzzy PID",
        path,
        "PID and fuzzy PID: the catalogue defaults (untuned); AO- and DEFFAO-fuzzy PID: tuned, "
        "each optimizer's median run. The legend gives each stopping distance.",
    )


def tuning_convergence(ctx: Context, key: str, data: StudyData) -> Figure:
    """The convergence of every controller tuning of a study: one panel per cell (scenario and
    road), every optimizer in it."""
    panels = {
        f"{cell} (objective {data.runs(cell)[0].spec.objective})": {
            o: data.runs(cell, o) for o in data.optimizers if data.runs(cell, o)
        }
        for cell in data.scenarios
        if data.runs(cell)
    }
    path = ctx.figure(key, "tuning_convergence")
    convergence_panels_figure(panels, str(path), f"Controller tunings of {data.name}")
    return Figure(
        path.stem,
        f"Convergence of the controller tunings ({data.name})",
        path,
        "Tuned controllers: the objective of each tuning (best so far against evaluations), "
        "every optimizer, every cell of the study; the runs shown in the tables are each "
        "optimizer's median run.",
    )
