"""`chassistune optimize FUNCTION [--dim D] --optimizer O [--pop N] [--iters N | --evals N]
[--seed S] [--shift] [--json]`: minimize one benchmark function with one optimizer."""

from __future__ import annotations

import json
from typing import Any

import click

from chassistune.cli.choices import ChoicesOption
from chassistune.errors import InputError


def run_optimize(
    function: str,
    dim: int | None,
    optimizer: str,
    pop: int,
    iters: int | None,
    evals: int | None,
    seed: int,
    shift: bool = False,
) -> dict[str, Any]:
    """Run one optimizer on one benchmark function (with `shift`, its optimum moved to a point
    of the box drawn from the seed: `benchmarks.shifted`); the `optimize --json` object."""
    from chassistune._io import jsonable
    from chassistune._rng import child_seed, make_rng
    from chassistune.benchmarks.functions import get as get_function
    from chassistune.benchmarks.shifted import shifted
    from chassistune.optimizers.base import check_covers_population
    from chassistune.optimizers.minimize import minimize

    if iters is not None and evals is not None:
        raise InputError("--iters", "give --iters or --evals, not both")
    if iters is None and evals is None:
        iters = 100
    check_covers_population(pop, evals)
    base = get_function(function)
    fn = shifted(function, dim, child_seed(seed, 1)) if shift else base
    bounds = base.bounds(dim)
    # F7's noise has its own stream, derived from the seed
    noise = make_rng(child_seed(seed, 0)) if fn.noisy else None

    def objective(x: Any) -> Any:
        return fn(x, noise)

    res = minimize(
        objective,
        bounds,
        method=optimizer,
        pop_size=pop,
        max_iter=iters,
        max_evals=evals,
        seed=seed,
    )
    out = {
        "function": fn.name,
        "dim": int(bounds.shape[0]),
        "optimizer": optimizer.lower(),
        "best_f": jsonable(res.fun),
        "best_x": jsonable(res.x),
        "nfev": res.nfev,
        "nit": res.nit,
        "history": jsonable(res.history),
        "history_nfev": jsonable(res.history_nfev),
    }
    if shift:
        out["optimum"] = jsonable(fn.minimizer())
    return out


@click.command("optimize")
@click.argument("function")
@click.option(
    "--dim", type=int, default=None, help="Dimension (default: the function's usual one)."
)
@click.option(
    "--optimizer",
    required=True,
    cls=ChoicesOption,
    choices_of="optimizers",
    help="Optimizer name (see `chassistune list optimizers`).",
)
@click.option("--pop", type=int, default=30, show_default=True, help="Population size.")
@click.option("--iters", type=int, default=None, help="Iterations (default 100 unless --evals).")
@click.option("--evals", type=int, default=None, help="Exact evaluation budget.")
@click.option("--seed", type=int, default=0, show_default=True, help="Random seed.")
@click.option(
    "--shift",
    is_flag=True,
    help="Move the optimum to a random point of the box, drawn from --seed (docs/bbob.md).",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
def optimize_command(as_json: bool, **run: Any) -> None:
    """Minimize a benchmark function F1..F23 (or, with --shift, its moved-optimum version)
    with one optimizer."""
    out = run_optimize(**run)
    if as_json:
        click.echo(json.dumps(out))
        return
    best = out["best_f"]
    click.echo(
        f"{out['optimizer']} on {out['function']} (dim {out['dim']}): "
        f"best f = {best if best is None else f'{best:.10g}'}"
    )
    click.echo(f"  nfev {out['nfev']}, nit {out['nit']}")
    click.echo("  best x = [" + ", ".join(f"{v:.6g}" for v in out["best_x"]) + "]")
