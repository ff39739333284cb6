"""`chassistune.tune(...)`: tune a controller's gains with any registered optimizer."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, overload

from chassistune.tuning.problem import TuningProblem, build_problem
from chassistune.tuning.run import Progress, TuneResult, run_optimizer

if TYPE_CHECKING:
    from chassistune.tuning.robust.run import RobustTuneResult
    from chassistune.tuning.robust.spec import UncertaintySpec


@overload
def tune(
    plant: str,
    controller: str,
    optimizer: str = ...,
    preset: str | None = ...,
    roads: Sequence[str] | str | None = ...,
    objective: str | None = ...,
    aggregate: str = ...,
    pop_size: int = ...,
    max_iter: int | None = ...,
    max_evals: int | None = ...,
    seed: int = ...,
    params: Mapping[str, object] | None = ...,
    bounds: Mapping[str, tuple[float, float]] | None = ...,
    progress: Progress | None = ...,
    uncertainty: None = ...,
    **hyper: Any,
) -> TuneResult: ...


@overload
def tune(
    plant: str,
    controller: str,
    optimizer: str = ...,
    preset: str | None = ...,
    roads: Sequence[str] | str | None = ...,
    objective: str | None = ...,
    aggregate: str = ...,
    pop_size: int = ...,
    max_iter: int | None = ...,
    max_evals: int | None = ...,
    seed: int = ...,
    params: Mapping[str, object] | None = ...,
    bounds: Mapping[str, tuple[float, float]] | None = ...,
    progress: Progress | None = ...,
    *,
    uncertainty: UncertaintySpec | Mapping[str, Any],
    **hyper: Any,
) -> RobustTuneResult: ...


def tune(
    plant: str,
    controller: str,
    optimizer: str = "derlsp-ao",
    preset: str | None = None,
    roads: Sequence[str] | str | None = None,
    objective: str | None = None,
    aggregate: str = "mean",
    pop_size: int = 30,
    max_iter: int | None = None,
    max_evals: int | None = None,
    seed: int = 0,
    params: Mapping[str, object] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    progress: Callable[[int, int, float], None] | None = None,
    uncertainty: UncertaintySpec | Mapping[str, Any] | None = None,
    **hyper: Any,
) -> TuneResult | RobustTuneResult:
    """Tune `controller` of `plant` on `roads` with `optimizer` (defaults of design.md 7).

    Without a budget, 100 iterations. The same seed gives the same result. With `uncertainty`
    (an `UncertaintySpec`, or the study's `[uncertainty]` table as a dict: {"vary": {"mass_kg":
    "80:120"}, "scenarios": 16, "aggregate": "max", "validate": 300}) the controller is tuned
    over the K training scenarios drawn from `seed` and validated, like `tune --vary`: the
    result is a `RobustTuneResult` (`.result` the tuning, `.validation`, `.as_dict()`).
    """
    if max_iter is None and max_evals is None:
        max_iter = 100
    road_list = [roads] if isinstance(roads, str) else roads
    problem = build_problem(
        plant, controller, preset, road_list, objective, aggregate, params, bounds, seed
    )
    if uncertainty is not None:
        from chassistune.tuning.robust.run import tune_robust

        return tune_robust(
            problem,
            robust_spec(problem, uncertainty),
            optimizer,
            pop_size,
            max_iter,
            max_evals,
            seed,
            params,
            progress,
            **hyper,
        )
    return run_optimizer(problem, optimizer, pop_size, max_iter, max_evals, seed, progress, **hyper)


def robust_spec(
    nominal: TuningProblem, uncertainty: UncertaintySpec | Mapping[str, Any]
) -> UncertaintySpec:
    """An `UncertaintySpec` as given, or parsed from an `[uncertainty]` table against the
    parameters every scenario of `nominal` may vary."""
    from chassistune.tuning.robust.problem import known_for
    from chassistune.tuning.robust.spec import UncertaintySpec, parse_table

    if isinstance(uncertainty, UncertaintySpec):
        return uncertainty
    return parse_table(uncertainty, known_for(nominal))
