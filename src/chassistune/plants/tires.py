"""Longitudinal tire friction curves mu(S) and their peaks (design.md 3.2).

Three families here, all evaluated from plain arrays (`kernel_data`; compiled:
`sim.abs_wheel_tires`) so that roads are data, not code paths:

* bilinear (derlsp-ao-abs eq. 5): mu = mu_h S / S_T for S <= S_T, else
  (mu_h - mu_g S_T)/(1 - S_T) - (mu_h - mu_g) S / (1 - S_T); stored as the piecewise-linear table
  (0, 0), (S_T, mu_h), (1, mu_g);
* Burckhardt: mu = c1 (1 - exp(-c2 S)) - c3 S;
* a piecewise-linear table (MathWorks' sldemo_absbrake mu-slip table);

and the Magic Formula from a TIR file (`plants.mf_curve`), at the single wheel's constant load.

Every curve has `mu_scale` (default 1, positive), a road parameter multiplying the whole curve
mu(S) (a road slicker or grippier than its nominal curve): bilinear mu_h and mu_g,
Burckhardt c1 and c3, a table's mus. The peak slip stays; the peak friction scales.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from chassistune.errors import InputError
from chassistune.params import nonnegative, positive

KIND_TABLE = 0
KIND_BURCKHARDT = 1
KIND_BILINEAR = 2
KIND_MAGIC_FORMULA = 3
"""The Magic Formula's longitudinal pure-slip curve at one load (`plants.mf_curve`)."""

MAX_TABLE_NODES = 32
"""Most nodes a table tire may have (the kernels copy a table into this many stack slots)."""

PLAUSIBLE_MU_PEAK = (0.05, 1.5)
"""Peak friction of real tires on real roads, from ice to dry asphalt with a sticky tire."""

_MU_SCALE = {"positive": True}
"""mu_scale's metadata (every curve's road parameter; no plausible range declared)."""


@dataclass(frozen=True)
class TireCurve:
    """Base: a curve mu(S) on S in [0, 1], with its kernel representation."""

    def kernel_data(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        """(kind, coef, xs, ys) as `sim.abs_wheel_tires` takes them."""
        raise NotImplementedError

    def mu(self, slip: np.ndarray | float) -> np.ndarray:
        """Vectorized mu(S) (for plots, peaks and tests)."""
        kind, coef, xs, ys = self.kernel_data()
        s = np.clip(np.asarray(slip, dtype=np.float64), 0.0, 1.0)
        if kind == KIND_BURCKHARDT:
            return np.asarray(coef[0] * (1.0 - np.exp(-coef[1] * s)) - coef[2] * s)
        return np.interp(s, xs, ys)  # tables and bilinear curves (their xs, ys are the corners)

    def peak(self) -> tuple[float, float, float]:
        """(mu_peak, slip at the peak, target slip).

        The target is the slip of the peak when the curve has an interior peak, else the smallest
        slip reaching 98 % of mu_peak (a curve rising up to S = 1, such as Burckhardt ice, must not
        ask the controller for a locked wheel). Computed once per curve (curves are frozen
        values; a Burckhardt peak is a search over a million points).
        """
        return _peak(self)

    def _search_peak(self) -> tuple[float, float, float]:
        kind, _, xs, ys = self.kernel_data()
        if kind in (KIND_TABLE, KIND_BILINEAR):  # a piecewise-linear curve peaks at a node
            i = int(np.argmax(ys))
            mu_peak, s_peak = float(ys[i]), float(xs[i])
        else:
            s = np.linspace(0.0, 1.0, 200_001)
            i = int(np.argmax(self.mu(s)))
            lo, hi = s[max(i - 1, 0)], s[min(i + 1, s.size - 1)]
            for _ in range(60):  # golden-section refinement around the grid peak
                a = hi - (hi - lo) * 0.6180339887498949
                b = lo + (hi - lo) * 0.6180339887498949
                if self.mu(a) >= self.mu(b):
                    hi = b
                else:
                    lo = a
            s_peak = 0.5 * (lo + hi)
            mu_peak = float(self.mu(s_peak))
        mu_end = float(self.mu(1.0))
        if mu_end < mu_peak * (1.0 - 1e-9):
            return mu_peak, float(s_peak), float(s_peak)
        # no interior peak: the curve rises (or saturates) up to a locked wheel
        mu_peak = max(mu_peak, mu_end)
        s = np.linspace(0.0, 1.0, 1_000_001)
        target = float(s[np.argmax(self.mu(s) >= 0.98 * mu_peak)])
        return mu_peak, 1.0, target


@functools.lru_cache(maxsize=256)
def _peak(curve: TireCurve) -> tuple[float, float, float]:
    return curve._search_peak()


@dataclass(frozen=True)
class BilinearTire(TireCurve):
    """Tian et al. (derlsp-ao-abs) eq. 5 with Table 1's (S_T, mu_h, mu_g)."""

    slip_opt: float = field(metadata=positive(0.03, 0.5, open_interval=(0.0, 1.0)))
    mu_peak: float = field(metadata=positive(*PLAUSIBLE_MU_PEAK))
    mu_lock: float = field(metadata=nonnegative(0.03, 1.5))
    mu_scale: float = field(default=1.0, metadata=_MU_SCALE)

    def __post_init__(self) -> None:
        if not 0.0 < self.slip_opt < 1.0:
            raise InputError("params.slip_opt", f"must be in (0, 1), got {self.slip_opt:g}")
        if self.mu_lock > self.mu_peak:
            raise InputError(
                "params.mu_lock",
                f"must not exceed mu_peak = {self.mu_peak:g} "
                f"(the peak is the curve's maximum), got {self.mu_lock:g}",
            )

    def kernel_data(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        st, h, g = self.slip_opt, self.mu_peak * self.mu_scale, self.mu_lock * self.mu_scale
        xs = np.array([0.0, st, 1.0])
        ys = np.array([0.0, h, g])
        coef = np.array([st, h / st, (h - g * st) / (1.0 - st), (h - g) / (1.0 - st)])
        return KIND_BILINEAR, coef, xs, ys


@dataclass(frozen=True)
class BurckhardtTire(TireCurve):
    """Burckhardt's curve mu = c1 (1 - exp(-c2 S)) - c3 S."""

    c1: float = field(metadata=positive(0.02, 2.0))
    c2: float = field(metadata=positive(1.0, 500.0))
    c3: float = field(metadata=nonnegative(0.0, 1.0))
    mu_scale: float = field(default=1.0, metadata=_MU_SCALE)

    def kernel_data(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        coef = np.array([self.c1 * self.mu_scale, self.c2, self.c3 * self.mu_scale])
        return KIND_BURCKHARDT, coef, np.zeros(2), np.zeros(2)


@dataclass(frozen=True)
class TableTire(TireCurve):
    """A piecewise-linear mu-slip table on increasing slips from 0 to 1 (2 to MAX_TABLE_NODES
    nodes; mu is 0 at slip 0, where the tire transmits no force, and never negative)."""

    slips: tuple[float, ...]
    mus: tuple[float, ...]
    mu_scale: float = field(default=1.0, metadata=_MU_SCALE)

    def __post_init__(self) -> None:
        problem = table_problem(self.slips, self.mus)
        if problem is not None:
            node, column, text = problem
            where = "" if node is None else f"node {node + 1} ({column}): "
            raise InputError("road", f"mu-slip table: {where}{text}")

    def kernel_data(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        return KIND_TABLE, np.zeros(3), np.array(self.slips), np.array(self.mus) * self.mu_scale


def table_problem(
    slips: tuple[float, ...], mus: tuple[float, ...]
) -> tuple[int | None, str, str] | None:
    """What is wrong with a mu-slip table, or None: (the index of the offending node or None
    for the whole table, its column `slip` or `mu`, the problem). The table needs 2 to
    MAX_TABLE_NODES nodes with slips strictly increasing from 0 to 1, finite mus >= 0 and
    mu = 0 at slip 0 (no slip, no force)."""
    n = len(slips)
    if n != len(mus) or not 2 <= n <= MAX_TABLE_NODES:
        got = f"{n}" if n == len(mus) else f"{n} slips and {len(mus)} mus"
        return None, "slip", f"needs 2 to {MAX_TABLE_NODES} (slip, mu) nodes, got {got}"
    for i, (s, mu) in enumerate(zip(slips, mus, strict=True)):
        if not math.isfinite(s):
            return i, "slip", f"must be a finite number, got {s!r}"
        if i == 0 and s != 0.0:
            return i, "slip", f"the first slip must be 0, got {s:g}"
        if i > 0 and not s > slips[i - 1]:
            return i, "slip", (f"slips must increase strictly, got {s:g} after {slips[i - 1]:g}")
        if not (math.isfinite(mu) and mu >= 0.0):
            return i, "mu", f"must be a finite number >= 0, got {mu!r}"
        if i == 0 and mu != 0.0:
            return i, "mu", f"mu at slip 0 must be 0 (no slip, no force), got {mu:g}"
    if slips[-1] != 1.0:
        return n - 1, "slip", f"the last slip must be 1 (a locked wheel), got {slips[-1]:g}"
    return None


SLDEMO_TABLE = TableTire(
    slips=tuple(np.round(np.arange(21) * 0.05, 10)),
    mus=(
        0.0,
        0.4,
        0.8,
        0.97,
        1.0,
        0.98,
        0.96,
        0.94,
        0.92,
        0.9,
        0.88,
        0.855,
        0.83,
        0.81,
        0.79,
        0.77,
        0.75,
        0.73,
        0.72,
        0.71,
        0.7,
    ),
)
"""MathWorks sldemo_absbrake's mu-slip table (slip 0:0.05:1)."""

BURCKHARDT_SURFACES: dict[str, tuple[float, float, float]] = {
    "dry-asphalt": (1.2801, 23.99, 0.52),
    "wet-asphalt": (0.857, 33.822, 0.347),
    "dry-concrete": (1.1973, 25.168, 0.5373),
    "cobblestone-dry": (1.3713, 6.4565, 0.6691),
    "cobblestone-wet": (0.4004, 33.708, 0.1204),
    "snow": (0.1946, 94.129, 0.0646),
    "ice": (0.05, 306.39, 0.0),
}
"""Burckhardt's (c1, c2, c3) for his seven surfaces."""
