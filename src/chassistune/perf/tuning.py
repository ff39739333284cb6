"""`tune_abs_wall_s` (design.md 8): DERLSP-AO tuning of the single-wheel ABS PID on dry concrete,
N = 50, 500 iterations (about 50,000 evaluations with its DE and opposition trials), both cores."""

from __future__ import annotations

from chassistune.tuning.tune import tune


def figures(quick: bool = False) -> dict[str, float]:
    """Wall time of the tuning run (the quick variant runs 100 iterations and scales nothing)."""
    iters = 100 if quick else 500
    tune("abs-wheel", "pid", "derlsp-ao", roads="dry-concrete", pop_size=50, max_iter=2, seed=0)
    res = tune(
        "abs-wheel", "pid", "derlsp-ao", roads="dry-concrete", pop_size=50, max_iter=iters, seed=0
    )
    key = "tune_abs_wall_s" if not quick else "tune_abs_wall_s_100_iters"
    return {
        key: res.wall_time_s,
        "tune_abs_nfev": float(res.nfev),
        "tune_abs_distance_ratio": float(res.metrics["dry-concrete"]["distance_ratio"]),
    }
