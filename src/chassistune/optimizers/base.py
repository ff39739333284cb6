"""The batch ask/tell base shared by every optimizer (optimizers_design.md, "Common contract").

An algorithm is written as a coroutine, `_steps()`, that yields whole batches of candidate points
and receives their costs::

    x = self.uniform(n)          # initial population
    f = yield x
    for t in self.iterations():  # t = 1 .. T, history recorded after each body
        trial = ...
        f_trial = yield trial
        ...                      # selection

The base class drives that coroutine from `ask()` / `tell()` and owns everything the algorithms
share:

- the `numpy.random.Generator` (`self.rng`, from `chassistune._rng.make_rng(seed)`);
- bounds repair: every yielded batch is repaired *in place* (clip by default, or reflect) before it
  is handed out, so the algorithm sees exactly the points that are evaluated (a NaN coordinate,
  which has no nearest bound, is redrawn uniformly: the only draw the base makes after start-up);
- evaluation counting and budgets: `max_iter` and/or `max_evals` (the first reached stops the
  run); `max_evals` is exact: the last batch is cut to the remaining budget and the rows that were
  not evaluated get cost +inf, so they lose every greedy comparison and are never the best;
- cost hygiene: NaN, +inf and -inf costs become +inf;
- the best-so-far point and cost, the convergence history (best-so-far after every iteration)
  and `history_nfev` (evaluations spent at each of those points);
- `diagnostics`, a dict in which an algorithm reports on its run (ABC's scout count), carried
  into the run's result by `optimizers.driver.drive`.

The schedule horizon `T` that the algorithms use (AO's 2T/3 switch, GWO's a, ...) is `max_iter`,
or `floor(max_evals / evals_per_iteration)` when only `max_evals` is given, or the smaller of the
two (optimizers_design.md, "Budgets").
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Generator, Iterator
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from chassistune._rng import SeedLike, make_rng
from chassistune.errors import InputError

FloatArray = NDArray[np.float64]
Steps = Generator[FloatArray, FloatArray, None]
Repair = Literal["clip", "reflect"]


@dataclass(frozen=True)
class Hyperparameters:
    """Base of every algorithm's frozen hyperparameter dataclass.

    Subclasses validate their fields in `__post_init__` by calling `self.check(...)`.
    """

    def check(self, ok: bool, name: str, problem: str) -> None:
        """Raise `InputError(name, problem)` unless `ok`."""
        if not ok:
            raise InputError(name, problem)

    def as_dict(self) -> dict[str, Any]:
        """The hyperparameters as a plain dict (JSON-ready)."""
        return dataclasses.asdict(self)


def as_bounds(bounds: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Validate a sequence of `(lo, hi)` pairs; return the `lo` and `hi` arrays."""
    try:
        b = np.asarray(bounds, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError("bounds", f"expected a sequence of (lo, hi) pairs ({exc})") from None
    if b.ndim != 2 or b.shape[1] != 2 or b.shape[0] < 1:
        raise InputError("bounds", f"expected a sequence of (lo, hi) pairs, got shape {b.shape}")
    lo, hi = b[:, 0].copy(), b[:, 1].copy()
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        raise InputError("bounds", "every bound must be finite")
    bad = np.flatnonzero(~(lo < hi))
    if bad.size:
        j = int(bad[0])
        raise InputError("bounds", f"dimension {j} has lo >= hi ({lo[j]:g} >= {hi[j]:g})")
    if not np.all(np.isfinite(hi - lo)):
        raise InputError("bounds", "the range hi - lo overflows")
    return lo, hi


def _check_budget(name: str, value: int | None) -> int | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise InputError(name, f"expected a positive integer, got {value!r}")
    return int(value)


def check_covers_population(pop_size: int, max_evals: int | None) -> None:
    """Refuse an evaluation budget smaller than one population (for tuning and the CLI, where
    it would run no iteration; the ask/tell contract itself honours any budget exactly)."""
    if max_evals is not None and max_evals < pop_size:
        raise InputError(
            "max_evals",
            f"{max_evals} evaluations do not cover one population "
            f"of {pop_size}: no iteration would run",
        )


class Optimizer:
    """Batch ask/tell optimizer (minimization). Subclasses implement `_steps()`.

    Class attributes of a subclass: `name` (registry name), `description` (one line citing the
    paper), `min_pop` (smallest population it accepts), `defaults` (a frozen `Hyperparameters`).
    """

    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    min_pop: ClassVar[int] = 2
    defaults: ClassVar[Hyperparameters] = Hyperparameters()

    def __init__(
        self,
        bounds: ArrayLike,
        pop_size: int = 30,
        seed: SeedLike = 0,
        max_iter: int | None = None,
        max_evals: int | None = None,
        hyper: Hyperparameters | None = None,
        repair: Repair = "clip",
    ) -> None:
        self.lo, self.hi = as_bounds(bounds)
        self.dim = self.lo.size
        if hyper is None:
            hyper = self.defaults
        if type(hyper) is not type(self.defaults):
            raise InputError(
                "hyper",
                f"{self.name} takes {type(self.defaults).__name__}, got {type(hyper).__name__}",
            )
        self.hyper = hyper
        if isinstance(pop_size, bool) or not isinstance(pop_size, int | np.integer):
            raise InputError("pop_size", f"expected an integer, got {pop_size!r}")
        self.pop_size = int(pop_size)
        need = self.required_pop()
        if pop_size < need:
            raise InputError(
                "pop_size", f"{self.name} needs a population of at least {need}, got {pop_size}"
            )
        self.max_iter = _check_budget("max_iter", max_iter)
        self.max_evals = _check_budget("max_evals", max_evals)
        if self.max_iter is None and self.max_evals is None:
            raise InputError("budget", "give max_iter or max_evals (or both)")
        if repair not in ("clip", "reflect"):
            raise InputError("repair", f"expected 'clip' or 'reflect', got {repair!r}")
        self.repair: Repair = repair
        self.rng = make_rng(seed)

        per_iter = self.evals_per_iteration()
        horizons = []
        if self.max_iter is not None:
            horizons.append(self.max_iter)
        if self.max_evals is not None:
            horizons.append(max(1, self.max_evals // per_iter))
        self.T: int = min(horizons)
        """Schedule horizon (optimizers_design.md, "Budgets")."""

        self.nfev = 0
        self.nit = 0
        self.best_x: FloatArray = np.full(self.dim, np.nan)
        self.best_f = math.inf
        self._history: list[float] = []
        self._history_nfev: list[int] = []
        self._gen: Steps | None = None
        self._pending: FloatArray | None = None
        self._finished = False
        self.diagnostics: dict[str, Any] = {}
        """What the algorithm reports about its run (counters such as IABC's `scouts`)."""

    # -- to be provided by subclasses ------------------------------------------------------------
    def required_pop(self) -> int:
        """Smallest population for these hyperparameters (the class's `min_pop` by default)."""
        return self.min_pop

    def evals_per_iteration(self) -> int:
        """Evaluations of one iteration (never more than the algorithm really spends)."""
        return self.pop_size

    def _steps(self) -> Steps:
        raise NotImplementedError

    # -- helpers for subclasses ------------------------------------------------------------------
    def uniform(self, n: int) -> FloatArray:
        """`n` points drawn uniformly in the bounds (one `rng.random((n, d))` draw)."""
        out: FloatArray = self.lo + self.rng.random((n, self.dim)) * (self.hi - self.lo)
        return out

    def iterations(self) -> Iterator[int]:
        """Yield the schedule time t = 1, 2, ..; after each body record the history.

        The loop ends at `max_iter` or when the evaluation budget is spent. With only `max_evals`
        the last iteration may start after t = T (when the iteration cost does not divide the
        budget): such iterations see t = T, the schedule's final value.
        """
        t = 0
        while not self._budget_spent() and (self.max_iter is None or t < self.max_iter):
            t += 1
            yield min(t, self.T)
            self.nit = t
            self._history.append(self.best_f)
            self._history_nfev.append(self.nfev)

    # -- public ask/tell -------------------------------------------------------------------------
    @property
    def done(self) -> bool:
        """True once the budget is spent or the schedule has ended."""
        if self._gen is None:
            return False
        return self._finished or self._budget_spent()

    def ask(self) -> FloatArray:
        """The next batch to evaluate, shape `(m, d)`, inside the bounds (read-only view).

        Asking twice without telling returns the same batch.
        """
        if self._gen is None:
            self._gen = self._steps()
            self._accept(next(self._gen))
        if self.done or self._pending is None:
            raise RuntimeError(
                f"{self.name}: the run is finished (nfev={self.nfev}, nit={self.nit})"
            )
        view = self._pending[: self._rows_allowed()]
        view.flags.writeable = False
        return view

    def tell(self, x: ArrayLike, f: ArrayLike) -> None:
        """Report the costs `f` (shape `(m,)`) of the batch `x` returned by the last `ask()`."""
        if self._pending is None or self.done:
            raise RuntimeError(f"{self.name}: tell() without a pending ask()")
        m = self._rows_allowed()
        xs = np.shape(x)
        if xs != (m, self.dim):
            raise InputError("x", f"expected the asked batch of shape {(m, self.dim)}, got {xs}")
        try:
            cost = np.asarray(f, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InputError("fun", f"returned values that are not numbers ({exc})") from None
        if cost.shape != (m,):
            raise InputError("fun", f"returned shape {cost.shape}, expected ({m},)")
        cost = np.where(np.isfinite(cost), cost, np.inf)
        batch = self._pending
        self.nfev += m
        if m:
            i = int(np.argmin(cost))
            if cost[i] < self.best_f:
                self.best_f = float(cost[i])
                self.best_x = batch[i].copy()
        if m < batch.shape[0]:
            full = np.full(batch.shape[0], np.inf)
            full[:m] = cost
            cost = full
        self._send(cost)
        # Budget spent mid-iteration: finish that iteration's bookkeeping without evaluating.
        while not self._finished and self._budget_spent() and self._pending is not None:
            self._send(np.full(self._pending.shape[0], np.inf))

    # -- results ---------------------------------------------------------------------------------
    @property
    def history(self) -> FloatArray:
        """Best-so-far cost after each iteration."""
        return np.asarray(self._history, dtype=float)

    @property
    def history_nfev(self) -> NDArray[np.int64]:
        """Evaluations spent at each point of `history`."""
        return np.asarray(self._history_nfev, dtype=np.int64)

    # -- internals -------------------------------------------------------------------------------
    def _budget_spent(self) -> bool:
        return self.max_evals is not None and self.nfev >= self.max_evals

    def _rows_allowed(self) -> int:
        n = 0 if self._pending is None else self._pending.shape[0]
        if self.max_evals is None:
            return n
        return max(0, min(n, self.max_evals - self.nfev))

    def _send(self, cost: FloatArray) -> None:
        if self._gen is None:
            return
        try:
            batch = self._gen.send(cost)
        except StopIteration:
            self._finished = True
            self._pending = None
            return
        self._accept(batch)

    def _accept(self, batch: FloatArray) -> None:
        if self.repair == "reflect":
            width = self.hi - self.lo
            y = np.mod(batch - self.lo, 2.0 * width)
            batch[...] = self.lo + np.where(y > width, 2.0 * width - y, y)
        bad = np.isnan(batch)
        if bad.any():  # a NaN coordinate has no nearest bound: draw it uniformly instead
            fresh = self.uniform(batch.shape[0])
            batch[bad] = fresh[bad]
        np.clip(batch, self.lo, self.hi, out=batch)
        self._pending = batch
