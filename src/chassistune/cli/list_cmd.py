"""`chassistune list {plants|presets|roads|controllers|optimizers|functions} [--json]`,
`chassistune list params PLANT [--preset P] [--json]` and `chassistune list roads --plot FILE.png`
(the friction roads' mu-slip curves)."""

from __future__ import annotations

import json

import click

from chassistune.cli.choices import ChoicesCommand

KINDS = ["plants", "presets", "roads", "controllers", "optimizers", "functions", "params"]


def catalogue(kind: str) -> object:
    """The JSON-ready listing of one kind (grouped by plant where it applies)."""
    from chassistune.scenarios.registry import plant_names, plant_presets, plant_roads, plant_spec

    if kind == "plants":
        return [
            {
                "name": n,
                "description": plant_spec(n).description,
                "default_preset": plant_spec(n).default_preset,
            }
            for n in plant_names()
        ]
    if kind == "presets":
        return {
            n: [
                {"name": p.name, "description": p.description, "roads": list(p.roads)}
                for p in plant_presets(n).values()
            ]
            for n in plant_names()
        }
    if kind == "roads":
        return {
            n: [{"name": r, "description": d} for r, d in plant_roads(n).items()]
            for n in plant_names()
        }
    if kind == "controllers":
        from chassistune.controllers import laws
        from chassistune.controllers.catalogue import for_plant

        out = {}
        for n in plant_names():
            out[n] = [c.as_dict() for c in for_plant(n)]
            for c in out[n]:
                if c["name"] in laws.names() and laws.get(c["name"]).spec(n) is not None:
                    law = laws.get(c["name"])
                    c.update(source=law.source, needs_target=law.needs_target)
        return out
    if kind == "optimizers":
        from chassistune.optimizers.registry import catalogue as opt_catalogue

        return opt_catalogue()
    from chassistune.benchmarks.functions import catalogue as fn_catalogue

    return fn_catalogue()


def _print_human(kind: str, data: object) -> None:
    if isinstance(data, dict):
        for plant, items in data.items():
            click.echo(f"{plant}:")
            for item in items:
                extra = ""
                if kind == "controllers":
                    gains = ", ".join(
                        f"{g['name']}={g['default']:g} [{g['bounds'][0]:g}, "
                        f"{g['bounds'][1]:g}] {g['unit']}"
                        for g in item["gains"]
                    )
                    extra = f"  gains: {gains}" if gains else "  (no gains)"
                    if "source" in item:
                        road = (
                            "a target slip (the road's optimum, or a fixed one)"
                            if item["needs_target"]
                            else "no knowledge of the road"
                        )
                        extra += f"\n  {'':<26}  source: {item['source']}; needs {road}"
                elif kind == "presets":
                    extra = f"  roads: {', '.join(item['roads'])}"
                click.echo(f"  {item['name']:<26} {item['description']}")
                if extra:
                    click.echo(f"  {'':<26}{extra}")
    else:
        for item in data:  # type: ignore[attr-defined]
            click.echo(f"{item['name']:<14} {item.get('description', '')}")


CONTROLLER_GROUP = "controller (each applies to the controllers named)"
"""The `list params` group of the controllers' fixed parameters."""


def parameters(plant: str, preset: str | None) -> dict[str, list[dict[str, object]]]:
    """`list params PLANT`: each parameter group's fields with unit (a pressure in the
    preset's unit), default (the preset's value), valid range and plausible range; the
    controllers' fixed parameters last."""
    from chassistune.params import describe
    from chassistune.scenarios.registry import get_plant
    from chassistune.units import with_pressure

    groups = get_plant(plant).parameter_sets(preset)
    pressure = get_plant(plant).scenario(preset).pressure_unit
    out = {
        group: [{**f, "unit": with_pressure(f["unit"], pressure)} for f in describe(obj)]
        for group, obj in groups.items()
    }
    controller = controller_parameters(plant, preset)
    if controller:
        out[CONTROLLER_GROUP] = controller
    return out


def controller_parameters(plant: str, preset: str | None) -> list[dict[str, object]]:
    """The fixed parameters `--param` sets on the controllers of `plant` (and abs-wheel's
    `target_slip`), each with unit, default (as resolved on the preset's first road; one row
    per distinct default), valid range and the controllers that read it."""
    from chassistune.scenarios.registry import get_plant

    rows: dict[str, dict[str, object]] = {}
    for spec in get_plant(plant).controllers():
        values = get_plant(plant).scenario(preset, None, spec.name).params()
        fields = [(ps.name, ps.unit, _valid_text(ps.positive, ps.choices)) for ps in spec.params]
        if "target_slip" in values:
            fields.append(("target_slip", "-", "(0, 1)"))
        for name, unit, valid in fields:
            row = rows.setdefault(
                f"{name}={values.get(name)!r}",
                {
                    "name": name,
                    "unit": unit,
                    "default": values.get(name),
                    "valid": valid,
                    "plausible": None,
                    "controllers": [],
                },
            )
            row["controllers"].append(spec.name)  # type: ignore[attr-defined]
    return list(rows.values())


def _valid_text(positive: bool, choices: tuple[str, ...]) -> str:
    if choices:
        return " | ".join(choices)
    return "> 0" if positive else "text"


def _shown_default(value: object) -> str:
    """A default as text: numbers in %g, a tuple of numbers as one (a table road's slips)."""
    if isinstance(value, tuple):
        return "(" + ", ".join(_shown_default(v) for v in value) + ")"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _print_params(data: dict[str, list[dict[str, object]]]) -> None:
    for group, fields in data.items():
        click.echo(f"{group}:")
        for f in fields:
            span = f["plausible"]
            plausible = f"plausible [{span[0]:g}, {span[1]:g}]" if span else ""  # type: ignore[index]
            used_by = ", ".join(f.get("controllers", []))  # type: ignore[arg-type]
            used_by = f"used by {used_by}" if used_by else ""
            click.echo(
                f"  {f['name']:<22} {_shown_default(f['default']):>12} {f['unit']:<22} "
                f"valid {f['valid']:<7} {plausible}{used_by}".rstrip()
            )


@click.command("list", cls=ChoicesCommand, arguments={"PLANT": "plants"})
@click.argument("kind", type=click.Choice(KINDS))
@click.argument("plant", required=False, metavar="[PLANT]")
@click.option("--preset", help="With `params`: the preset whose values are the defaults.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@click.option(
    "--plot",
    "plot_path",
    metavar="FILE.png",
    help="With `roads`: draw the mu-slip curve of every friction road into FILE.png.",
)
def list_command(
    kind: str, plant: str | None, preset: str | None, as_json: bool, plot_path: str | None
) -> None:
    """List plants, presets, roads, controllers (with gain bounds), optimizers or functions;
    `list params PLANT`: every parameter with unit, default, valid and plausible range;
    `list roads --plot FILE.png`: the friction roads' mu-slip curves."""
    from chassistune.cli.common import check_output_file
    from chassistune.errors import InputError

    if plot_path is not None:
        if kind != "roads":
            raise InputError(
                "--plot",
                f"draws the roads' friction curves: `list roads --plot "
                f"FILE.png`, not `list {kind}`",
            )
        check_output_file(plot_path, "--plot", (".png",))
    if kind == "params":
        if plant is None:
            raise InputError("PLANT", "`list params` needs a plant (chassistune list plants)")
        data: object = parameters(plant, preset)
    elif plant is not None or preset is not None:
        raise InputError("PLANT", f"`list {kind}` takes no plant or preset")
    else:
        data = catalogue(kind)
    if plot_path is not None:
        plot_roads(plot_path)
    if as_json:
        click.echo(json.dumps({kind: data}, indent=1))
    elif kind == "params":
        _print_params(data)  # type: ignore[arg-type]
    else:
        _print_human(kind, data)
    if plot_path is not None and not as_json:
        click.echo(f"wrote {plot_path}")


def plot_roads(path: str) -> None:
    """The mu-slip curve of every friction road (abs-wheel's, by the names `--road` takes)."""
    from chassistune.plants.roads import friction_roads, tire_for_road
    from chassistune.plots.roads import plot_friction_curves

    plot_friction_curves({r: tire_for_road(r, {})[0] for r in friction_roads()}, path)
