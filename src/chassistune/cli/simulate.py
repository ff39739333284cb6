"""`chassistune simulate PLANT ...`: one closed-loop run, its metrics, plot and trace."""

from __future__ import annotations

import csv
from typing import TYPE_CHECKING, Any

import click

from chassistune.cli.choices import ChoicesCommand, ChoicesOption
from chassistune.cli.common import check_output_file, echo_json, fmt
from chassistune.cli.options import ecu_option, param_option, preset_option, tire_option, with_tire
from chassistune.errors import InputError
from chassistune.units import shown_unit, with_pressure

if TYPE_CHECKING:
    from chassistune.scenarios.base import Scenario
    from chassistune.simulate import Comparison, SimulationResult

DIAGNOSTICS = ("slip_clip_max", "min_slip_unclipped")
"""Internal diagnostics: in the JSON, not in the text table."""


def write_csv(result: SimulationResult, path: str) -> None:
    """The trace as CSV, one row per step, written atomically."""
    import numpy as np

    from chassistune._io import atomic_path

    sig = result.trace.shown
    names = list(sig)
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        units = result.trace.units
        w.writerow([f"{n} [{units[n]}]" if n in units else n for n in names])
        w.writerows(np.column_stack([sig[n] for n in names]).tolist())


def _shown(name: str, value: object) -> object:
    """A metric's value in the unit it is shown in (`units.shown_unit`: mm for travel)."""
    factor = shown_unit(name)[1]
    return value * factor if isinstance(value, float) and factor != 1.0 else value


def _label(name: str, sc: Scenario) -> str:
    """A metric's name with the unit its value is shown in: `susp_travel_rms [mm]`, a pressure
    in the preset's unit (`pressure_max [kPa]`), and the plant's note on it (`metric_unit`)."""
    from chassistune.scenarios.registry import plant_spec

    unit = with_pressure(shown_unit(name)[0], sc.pressure_unit)
    return f"{name} [{plant_spec(sc.plant).metric_unit(name, unit)}]" if unit else name


def _print_metrics(metrics: dict[str, object], sc: Scenario) -> None:
    """Metrics with their units as a list; those with a `passive_` twin as an active / passive /
    ratio table."""
    metrics = {k: v for k, v in metrics.items() if k not in DIAGNOSTICS}
    paired = [k for k in metrics if f"passive_{k}" in metrics]
    alone = [
        k
        for k in metrics
        if k not in paired and not (k.startswith("passive_") and k[len("passive_") :] in paired)
    ]
    width = max(len(_label(k, sc)) for k in metrics)
    if paired:
        click.echo(f"  {'':<{width}}  {'active':>10}  {'passive':>10}  {'ratio':>7}")
        for k in paired:
            a, b = metrics[k], metrics[f"passive_{k}"]
            ratio = a / b if isinstance(a, float) and isinstance(b, float) and b else None
            click.echo(
                f"  {_label(k, sc):<{width}}  {fmt(_shown(k, a)):>10}  "
                f"{fmt(_shown(k, b)):>10}  {fmt(ratio):>7}"
            )
    for k in alone:
        click.echo(f"  {_label(k, sc):<{width}}  {fmt(_shown(k, metrics[k]))}")


def _why_not(result: SimulationResult) -> str | None:
    """One line saying why the run did not stop (its stop metrics are then null)."""
    m = result.metrics
    if m.get("stopped", True):
        return None
    status = str(m.get("status"))
    reason = result.scenario.status_reasons.get(status, status)
    return f"did not stop ({status}): {reason}; stop metrics are left empty"


@click.command("simulate", cls=ChoicesCommand, arguments={"PLANT": "plants"})
@click.argument("plant", metavar="PLANT", required=False)
@preset_option
@click.option(
    "--road", cls=ChoicesOption, choices_of="roads", help="Road (default: the preset's first road)."
)
@click.option(
    "--controller",
    cls=ChoicesOption,
    choices_of="controllers",
    help="Controller structure (default: pid, or the --from result's); "
    "`chassistune list controllers` shows them.",
)
@param_option
@click.option(
    "--gains",
    "gains",
    multiple=True,
    metavar="NAME=VALUE,...|@FILE.json",
    help="Controller gains (default: the registry's defaults); @FILE.json reads a "
    "JSON object such as a tune's best_gains.json.",
)
@click.option(
    "--from",
    "from_path",
    metavar="RESULT.json",
    help="A tune's tune.json (or its folder), or an export's JSON: its plant, preset, "
    "road, controller, parameters and gains; options given here override them.",
)
@click.option(
    "--compare",
    metavar="C1,C2,...",
    cls=ChoicesOption,
    choices_of="controllers",
    help="Simulate these controllers (with their default gains; the --from result "
    "as `tuned`) on one figure and one table.",
)
@click.option("--seed", type=int, help="Seed of any random draw (road realizations; default 0).")
@ecu_option
@tire_option
@click.option(
    "--r13h",
    is_flag=True,
    help="abs-wheel: add the UN R13-H adhesion utilisation to the metrics (r13h_epsilon = "
    "r13h_z_al / r13h_k_adhesion; docs/ecu.md), in ideal and realistic ECU mode.",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@click.option("--plot", "plot_path", metavar="FILE.png", help="Draw the response into FILE.png.")
@click.option("--csv", "csv_path", metavar="FILE.csv", help="Write the time series to FILE.csv.")
def simulate_command(
    plant: str | None,
    preset: str | None,
    road: str | None,
    controller: str | None,
    params: tuple[str, ...],
    gains: tuple[str, ...],
    from_path: str | None,
    compare: str | None,
    seed: int | None,
    ecu: str | None,
    tire: str | None,
    r13h: bool,
    as_json: bool,
    plot_path: str | None,
    csv_path: str | None,
) -> None:
    """Simulate one closed-loop run of PLANT and report its metrics.

    PLANT is one of the plants of `chassistune list plants`. Units are SI.
    Example: chassistune simulate abs-wheel --road wet-asphalt --gains kp=5000,kd=230 --plot out.png
    """
    from chassistune.params import parse_assignments
    from chassistune.results import load_tune, overrides
    from chassistune.scenarios.registry import get_plant, plant_names

    doc = load_tune(from_path, "--from") if from_path else None
    if doc is not None:
        if plant is not None and plant != doc["plant"]:
            raise InputError(
                "PLANT", f"{plant!r} differs from the --from result's {doc['plant']!r}"
            )
        plant = doc["plant"]
    if plant is None:
        raise InputError("PLANT", "missing (or give --from RESULT.json)")
    if plant not in plant_names():
        get_plant(plant)  # raises the one-line error listing the plants
    check_output_file(plot_path, "--plot", (".png",))
    check_output_file(csv_path, "--csv", (".csv",))
    if compare is not None and csv_path is not None:
        raise InputError("--csv", "one time series per file: not with --compare")
    if r13h and (plant != "abs-wheel" or compare is not None):
        raise InputError("--r13h", "takes one abs-wheel run: not with another plant or --compare")
    values: dict[str, object] = dict(overrides(doc)) if doc else {}
    values.update(parse_assignments(params, "params"))
    if ecu:
        values["ecu"] = ecu
    with_tire(plant, tire, values)
    given = parse_assignments(gains, "gains")
    if doc is not None:
        preset = preset or doc["preset"]
        road = road or doc["roads"][0]
        seed = doc["params"].get("seed", 0) if seed is None else seed
        if controller in (None, doc["controller"]):
            given = {**doc["best_gains"], **given}
        controller = controller or doc["controller"]
    if road is None and "tire" in values:
        from chassistune.plants.mf_curve import TIRE_SURFACE

        road = TIRE_SURFACE
    if compare is not None:
        _compare(
            plant,
            compare,
            preset,
            road,
            controller,
            values,
            given,
            doc,
            seed or 0,
            as_json,
            plot_path,
        )
        return
    _one_run(
        plant,
        preset,
        road,
        controller or "pid",
        values,
        given,
        seed or 0,
        as_json,
        plot_path,
        csv_path,
        r13h,
    )


def r13h_metrics(result: SimulationResult, values: dict[str, object]) -> dict[str, float]:
    """The UN R13-H figures of a run's controller and gains on its preset and road
    (`scenarios.r13h`, with the run's parameters, the ECU mode included): epsilon, z_AL, k_M."""
    from chassistune.scenarios.r13h import r13h_epsilon

    sc = result.scenario
    out = r13h_epsilon(sc.controller.name, sc.preset, sc.road, result.gains, values, seed=sc.seed)
    return {
        "r13h_epsilon": out.epsilon,
        "r13h_z_al": out.z_al,
        "r13h_k_adhesion": out.adhesion.k_m,
    }


def _one_run(
    plant: str,
    preset: str | None,
    road: str | None,
    controller: str,
    values: dict[str, object],
    gains: dict[str, Any],
    seed: int,
    as_json: bool,
    plot_path: str | None,
    csv_path: str | None,
    r13h: bool,
) -> None:
    from chassistune.simulate import prepare, run

    scenario, vector = prepare(plant, preset, road, controller, values, gains, seed)
    result = run(scenario, vector)
    if r13h:
        result.metrics.update(r13h_metrics(result, values))
    if plot_path:
        result.plot(plot_path)
    if csv_path:
        write_csv(result, csv_path)
    if as_json:
        echo_json(result.as_dict())
        return
    sc = result.scenario
    click.echo(f"{plant}  preset {sc.preset}  road {sc.road}  controller {sc.controller.name}")
    if result.gains:
        click.echo("gains: " + ", ".join(f"{k}={v!r}" for k, v in result.gains.items()))
    _print_metrics(result.metrics, sc)
    why = _why_not(result)
    if why:
        click.echo(why)
    for path in (plot_path, csv_path):
        if path:
            click.echo(f"wrote {path}")


def _compare(
    plant: str,
    names: str,
    preset: str | None,
    road: str | None,
    controller: str | None,
    values: dict[str, object],
    gains: dict[str, Any],
    doc: dict[str, Any] | None,
    seed: int,
    as_json: bool,
    plot_path: str | None,
) -> None:
    from chassistune.simulate import Comparison, compare, simulate

    wanted = [n.strip() for n in names.split(",") if n.strip() and n.strip() != "tuned"]
    per = {controller: gains} if doc is None and controller and gains else {}
    cmp = compare(plant, wanted, preset, road, values, per, seed)
    if doc is not None and controller is not None:
        tuned = simulate(plant, preset, road, controller, values, gains, seed)
        cmp = Comparison({"tuned": tuned, **cmp.results})
    if plot_path:
        cmp.plot(plot_path)
    if as_json:
        echo_json({"plant": plant, "runs": {k: r.as_dict() for k, r in cmp.results.items()}})
        return
    _print_comparison(cmp)
    if plot_path:
        click.echo(f"wrote {plot_path}")


def _print_comparison(cmp: Comparison) -> None:
    """Metrics as rows, runs as columns; why a run did not stop, below."""
    first = next(iter(cmp.results.values())).scenario
    click.echo(f"{first.plant}  preset {first.preset}  road {first.road}")
    labels = list(cmp.results)
    keys = [k for k in next(iter(cmp.results.values())).metrics if k not in DIAGNOSTICS]
    width = max(len(_label(k, first)) for k in keys)
    col = max(10, *(len(x) for x in labels))
    click.echo(f"  {'':<{width}}  " + "  ".join(f"{x:>{col}}" for x in labels))
    for k in keys:
        click.echo(
            f"  {_label(k, first):<{width}}  "
            + "  ".join(f"{fmt(_shown(k, cmp.results[x].metrics.get(k))):>{col}}" for x in labels)
        )
    for label, r in cmp.results.items():
        if r.gains:
            click.echo(f"{label} gains: " + ", ".join(f"{k}={v!r}" for k, v in r.gains.items()))
        why = _why_not(r)
        if why:
            click.echo(f"{label}: {why}")
