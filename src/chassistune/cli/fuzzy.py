"""`chassistune fuzzy show|eval`: inspect and evaluate fuzzy rule bases (design.md 7).

RULEBASE is a built-in name (`deffao`, `classic`, `immune`) or a path to a TOML file with the
structure of `fuzzy show --json`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING

import click

from chassistune.cli.choices import ChoicesCommand
from chassistune.errors import InputError

if TYPE_CHECKING:  # the fuzzy package builds numba ufuncs at import: imported by the commands
    from chassistune.fuzzy.rulebase import RuleBase, Variable

PLOT_SUFFIXES = (".png", ".svg", ".pdf")


@click.group("fuzzy")
def fuzzy_group() -> None:
    """Show and evaluate fuzzy rule bases (a built-in name or a TOML file)."""


def _describe_variable(role: str, var: Variable) -> list[str]:
    lo, hi = var.universe
    lines = [f"{role} {var.name} on [{lo:g}, {hi:g}]:"]
    for s in var.sets:
        lines.append(f"  {s.name:<4} {s.shape:<5} [{', '.join(f'{p:.6g}' for p in s.params)}]")
    return lines


def _rule_table(rb: RuleBase) -> list[str]:
    """Two inputs: a table with rows input 0, columns input 1, cells the output sets."""
    if len(rb.inputs) != 2:
        return [
            f"  {', '.join(r[: len(rb.inputs)])} -> {', '.join(r[len(rb.inputs) :])}"
            for r in rb.rules
        ]
    cell = {(r[0], r[1]): ",".join(r[2:]) for r in rb.rules}
    rows, cols = rb.inputs[0].set_names, rb.inputs[1].set_names
    width = max(len(c) for c in (*cell.values(), *cols)) + 2
    head = f"{rb.inputs[0].name} \\ {rb.inputs[1].name}"
    first = max(len(head), *(len(r) for r in rows)) + 2
    lines = [f"{head:<{first}}" + "".join(f"{c:<{width}}" for c in cols)]
    lines += [f"{r:<{first}}" + "".join(f"{cell[(r, c)]:<{width}}" for c in cols) for r in rows]
    lines.append(f"(cells: {','.join(rb.output_names)})")
    return [f"  {line.rstrip()}" for line in lines]


def _check_plot_path(path: str) -> Path:
    from chassistune.cli.common import check_output_file

    check_output_file(path, "--plot", PLOT_SUFFIXES)
    return Path(path)


@fuzzy_group.command("show", cls=ChoicesCommand, arguments={"RULEBASE": "rulebases"})
@click.argument("rulebase")
@click.option("--json", "as_json", is_flag=True, help="Print the description as one JSON object.")
@click.option("--plot", "plot", metavar="FILE.png", help="Draw the sets and control surfaces.")
def show_command(rulebase: str, as_json: bool, plot: str | None) -> None:
    """Show a rule base: variables, sets, rules (and --plot its control surfaces)."""
    from chassistune.fuzzy.loader import load_rulebase
    from chassistune.fuzzy.rulebase import OPERATORS

    rb = load_rulebase(rulebase)
    out = _check_plot_path(plot) if plot else None
    if out is not None:
        from chassistune.plots.fuzzy import plot_rulebase

        plot_rulebase(rb, out)
    if as_json:
        click.echo(json.dumps(rb.as_dict(), indent=1))
        return
    lines = [f"rule base {rb.name}" + (f": {rb.description}" if rb.description else "")]
    for role, variables in (("input", rb.inputs), ("output", rb.outputs)):
        for var in variables:
            lines += _describe_variable(role, var)
    lines.append(
        f"{len(rb.rules)} rules ({', '.join(f'{k} {v}' for k, v in OPERATORS.items())}; "
        f"inputs clipped to their universes):"
    )
    lines += _rule_table(rb)
    if out is not None:
        lines.append(f"plot: {out}")
    click.echo("\n".join(lines))


def _parse_inputs(items: tuple[str, ...]) -> dict[str, float]:
    values: dict[str, float] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise InputError("--input", f"expected NAME=VALUE, got {item!r}")
        if name in values:
            raise InputError("--input", f"input {name!r} given twice")
        try:
            value = float(text)
        except ValueError:
            raise InputError("--input", f"{name}: not a number: {text!r}") from None
        if not math.isfinite(value):
            raise InputError("--input", f"{name}: not a finite number: {text!r}")
        values[name] = value
    return values


@fuzzy_group.command("eval", cls=ChoicesCommand, arguments={"RULEBASE": "rulebases"})
@click.argument("rulebase")
@click.option(
    "--input",
    "inputs",
    multiple=True,
    metavar="NAME=VALUE",
    help="A crisp input value (repeat for every input); clipped to its universe.",
)
@click.option("--json", "as_json", is_flag=True, help='Print {"outputs": {NAME: VALUE}}.')
def eval_command(rulebase: str, inputs: tuple[str, ...], as_json: bool) -> None:
    """Evaluate a rule base exactly (Mamdani min/max, centroid) at one input point."""
    from chassistune.fuzzy.engine import evaluate_named
    from chassistune.fuzzy.loader import load_rulebase

    rb = load_rulebase(rulebase)
    values = _parse_inputs(inputs)
    result = {name: float(v) for name, v in evaluate_named(rb, values).items()}
    if as_json:
        click.echo(json.dumps({"outputs": result}))
        return
    for var in rb.inputs:
        clipped = float(var.clip(values[var.name]))
        note = f"  (clipped to {clipped:g})" if clipped != values[var.name] else ""
        click.echo(f"{var.name} = {values[var.name]:g}{note}")
    for name, value in result.items():
        click.echo(f"{name} = {value:.6g}")
