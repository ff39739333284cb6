"""The bench's targets (docs/design.md 8): each figure's bound, so that `chassistune bench` says
of every figure it measured whether this run met it."""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Target:
    """A figure's bound: at least `bound` (`at_least`), else at most."""

    at_least: bool
    bound: float

    def met(self, value: float) -> bool:
        """Whether `value` is within the bound (a NaN never is)."""
        if math.isnan(value):
            return False
        return value >= self.bound if self.at_least else value <= self.bound

    def text(self) -> str:
        """The bound as design.md 8 writes it: '>= 20,000', '<= 1e-3'."""
        op = ">=" if self.at_least else "<="
        b = self.bound
        if b >= 1.0 and b == int(b):
            return f"{op} {int(b):,}"
        decade = math.log10(b)
        if decade == round(decade):
            return f"{op} 1e{round(decade)}"
        return f"{op} {b:g}"


def _at_least(bound: float) -> Target:
    return Target(True, bound)


def _at_most(bound: float) -> Target:
    return Target(False, bound)


TARGETS: dict[str, Target] = {
    "abs_sims_per_s": _at_least(20_000),
    "abs_max_rel_err": _at_most(1e-3),
    "abs_speedup_vs_solve_ivp": _at_least(1_000),
    "abs_max_rel_err_presets": _at_most(1e-3),
    "abs_max_rel_err_box": _at_most(1e-2),
    "abs_max_rel_err_presets_conditioned": _at_most(1e-3),
    "abs_max_rel_err_box_conditioned": _at_most(1e-2),
    "abs_fuzzy_pid_sims_per_s": _at_least(3_000),
    "abs_immune_sims_per_s": _at_least(6_000),
    "vehicle_sims_per_s": _at_least(500),
    "vehicle_speedup_vs_solve_ivp": _at_least(500),
    "vehicle_split_mu_sims_per_s": _at_least(500),
    "vehicle_driver_sims_per_s": _at_least(500),
    "suspension_exact_speedup_vs_sim": _at_least(100),
    "fuzzy_speedup_vs_skfuzzy": _at_least(100_000),
    "optimizer_us_per_eval": _at_most(5),
    "optimizer_speedup_vs_mealpy": _at_least(10),
    "tune_abs_wall_s": _at_most(2),
    "abs_ecu_ratio_to_ideal_cpu": _at_least(0.5),
    "abs_speedup_vs_jax": _at_least(5),
    "tire_magic_formula_over_bilinear": _at_most(2),
    "tire_ecu_magic_formula_over_bilinear": _at_most(2),
    "tire_vehicle_magic_formula_over_bilinear_dry_concrete": _at_most(2),
    "tire_vehicle_magic_formula_over_bilinear_split_mu": _at_most(2),
}
"""Figure -> its target, as in design.md 8's table (a test holds the two together)."""


def verdict(name: str, value: float) -> str:
    """'(target >= 500: met)' for a figure with a target, else ''."""
    target = TARGETS.get(name)
    if target is None:
        return ""
    return f"(target {target.text()}: {'met' if target.met(value) else 'NOT met'})"
