"""`tune`'s robust-tuning options: `--vary NAME=LO:HI` (repeatable), `--scenarios K`,
`--sampler sobol|lhs`, `--validate N`, `--beta B` (and `--aggregate cvar:ALPHA`, which `tune`
owns), turned into an `UncertaintySpec` before any work; without `--vary` the others are refused.

Light at import (no numpy): the spec is parsed inside `uncertainty_spec`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import click

from chassistune.cli.common import fmt
from chassistune.cli.options import stacked
from chassistune.errors import InputError

if TYPE_CHECKING:
    from chassistune.tuning.problem import TuningProblem
    from chassistune.tuning.robust.spec import UncertaintySpec
    from chassistune.tuning.run import TuneResult

robust_options = stacked(
    click.option(
        "--vary",
        "vary",
        multiple=True,
        metavar="NAME=LO:HI",
        help="Tune robustly over this parameter: uniform LO:HI or normal:MEAN:SD "
        "(repeatable; any plant, road or actuator parameter, and mu_scale).",
    ),
    click.option(
        "--scenarios",
        type=int,
        metavar="K",
        help="Training scenarios per candidate (default 16; a power of two for sobol; "
        "0: tune on the nominal plant, validate on the uncertainty).",
    ),
    click.option(
        "--sampler",
        type=click.Choice(["sobol", "lhs"]),
        help="Training-set sampler (default sobol, scrambled).",
    ),
    click.option(
        "--validate",
        type=int,
        metavar="N",
        help="Validate the winner on N fresh Monte Carlo draws (default 0: none).",
    ),
    click.option(
        "--beta",
        type=float,
        help="Confidence 1 - beta of the validation certificate (default 0.05).",
    ),
)
"""The robust-tuning options (keyword arguments ROBUST_KEYS)."""
ROBUST_KEYS = ("vary", "scenarios", "sampler", "validate", "beta")
"""The keyword arguments the options add to the command."""


def uncertainty_spec(
    nominal: TuningProblem, aggregate: str, options: Mapping[str, Any]
) -> UncertaintySpec | None:
    """The spec of the options (None without --vary), checked against the parameters every
    scenario of `nominal` may vary; errors name the field (vary.NAME, scenarios, ...)."""
    vary = tuple(options.get("vary") or ())
    if not vary:
        for key in ROBUST_KEYS[1:]:
            if options.get(key) is not None:
                raise InputError(key, "needs --vary NAME=LO:HI (the parameters that vary)")
        return None
    from chassistune.tuning.robust.problem import known_for
    from chassistune.tuning.robust.spec import UncertaintySpec, spec_from_options

    def pick(key: str, default: Any) -> Any:
        value = options.get(key)
        return default if value is None else value

    return spec_from_options(
        known_for(nominal),
        vary,
        pick("scenarios", UncertaintySpec.scenarios),
        pick("sampler", UncertaintySpec.sampler),
        aggregate,
        pick("validate", 0),
        pick("beta", UncertaintySpec.beta),
    )


def robust_or_nominal(
    nominal: TuningProblem,
    aggregate: str,
    options: Mapping[str, Any],
    params: Mapping[str, object],
    seed: int,
) -> TuningProblem:
    """The robust problem of the options over `nominal` (built with `params`), or `nominal`
    itself without --vary; the training set is drawn here, before any evaluation."""
    spec = uncertainty_spec(nominal, aggregate, options)
    if spec is None:
        return nominal
    from chassistune.tuning.robust.problem import robust_problem

    return robust_problem(nominal, spec, params, seed)


def robust_fields(result: TuneResult) -> dict[str, Any]:
    """What `tune --json` adds for a robust run (`uncertainty`, `training`, `validation`: the
    winner validated on the run's N fresh draws, None when N = 0); {} for a nominal run."""
    from chassistune.tuning.robust.problem import RobustProblem
    from chassistune.tuning.robust.run import robust_summary

    problem = result.problem
    return robust_summary(problem, result.x) if isinstance(problem, RobustProblem) else {}


def echo_validation(fields: Mapping[str, Any]) -> None:
    """The training and validation summary of a robust `tune` (text mode)."""
    if not fields:
        return
    costs = fields["training"]["costs"]
    click.echo(
        f"training: {len(costs)} scenarios x roads, winner's cost mean "
        f"{fmt(float(sum(costs) / len(costs)))}, worst {fmt(float(max(costs)))}"
    )
    validation = fields["validation"]
    if validation is None:
        return
    words = [
        f"validation: {validation['failures']}/{validation['n']} draws failed",
        f"pass rate {fmt(validation['pass_rate'])}",
    ]
    if "worst_distance_ratio" in validation:
        words.append(f"worst distance ratio {fmt(validation['worst_distance_ratio'])}")
    if "worst_cost" in validation:
        words.append(f"worst cost {fmt(validation['worst_cost'])}")
    cert = validation["certificate"]
    if cert is not None:
        words.append(
            f"failure probability <= {cert['eps']:.3%} with confidence {1.0 - cert['beta']:.0%}"
        )
    click.echo(", ".join(words))
