"""Jing and Xu 2023 (iabc-suspension): quarter-car PID tuned by ABC and IABC (issue 5, item 6).

Tunes the PID (kp, ki, kd; feedback body velocity) of `quarter-car` with `abc` and `iabc` on the
paper's box [0, 500]^3 and on our SI box (the registry bounds), presets `paper-iabc` and `typical`,
objective `rms-ratio-exact` (iabc-suspension eq. 10, exact stationary RMS), 100 food sources, 100
iterations, 30 seeds. Seed i is `SeedSequence(ROOT_ENTROPY, spawn_key=(i,))` (child i of
`SeedSequence(ROOT_ENTROPY).spawn(n)`), the same for both algorithms: a paired comparison.

Both algorithms use the paper's fitness f = 1/Q (eq. 11), phi in [-1, 1] (its "acceleration
coefficient 1") and the default limit SN * D; IABC adds eq. 8's nudge (epsilon 1e-6 of the range)
and eq. 9's selection. "Traditional PID" is our hand-set choice: the paper gives no values, so it is
the centre of the paper's box, kp = ki = kd = 250.

Resumable: each finished run is one JSON file under OUT/runs/, written atomically; existing files
are skipped. Then the reports: convergence figures, summaries, Wilcoxon rank-sum (the statistics
module), scout counts, Table 2 (exact stationary values on ISO class B at 20 m/s, and the mean over
10 s road realizations) beside the paper's values, and `tables.md` with the same in markdown.

    .venv/bin/python paper_scripts/iabc_suspension_study.py [--seeds 30] [--out DIR]
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import sys
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import minimize

from chassistune import _io, stats
from chassistune._rng import child_seed
from chassistune.controllers.catalogue import PAPER_BOX
from chassistune.optimizers.driver import drive
from chassistune.optimizers.registry import make
from chassistune.scenarios.quarter_car import PLANT, QuarterCarScenario
from chassistune.sim import lyapunov
from chassistune.sim import quarter_car_kernel as kernel
from chassistune.tuning.problem import TuningProblem, build_problem

ROOT_ENTROPY = 1_001_2023
"""Root of every run seed (iabc-suspension, published 2023)."""
PRESETS = ("paper-iabc", "typical")
BOXES = ("paper", "si")
"""Boxes tuned with the exact objective."""
TEN_S = "paper-10s"
"""The paper's own protocol: its box, eq. 10 from one 10 s simulated road (realization = seed)."""
TEN_S_CELL = ("paper-iabc", TEN_S)
ALGORITHMS = ("abc", "iabc")
GAINS = ("kp", "ki", "kd")
OBJECTIVE = "rms-ratio-exact"
ROAD = "iso-b"
HYPER: dict[str, Any] = {"fitness": "reciprocal", "phi_range": 1.0}
TRADITIONAL = (250.0, 250.0, 250.0)
"""Hand-set "traditional PID": the centre of the paper's box (the paper gives no values)."""
CHECKPOINTS = (1, 5, 10, 20, 40, 100)
"""Iterations at which ABC and IABC are compared (the paper: IABC converges within 40)."""
TOLERANCES = (1e-3, 1e-6)
"""Gaps Q - Q* for the iterations-to-converge table."""
GRID_POINTS = 61
"""Grid points per gain for the independent optimum check (61^3 = 226,981 evaluations)."""
GAP_FLOOR = 1e-12
RESOLUTION = 1e-9
"""Q rounded to this before the second rank-sum test (differences below are immaterial)."""
PAPER: dict[str, Any] = {  # ../shared/paper_results.toml [iabc_suspension]: Table 2, 4.3
    "controllers": ["traditional PID", "ABC-PID", "IABC-PID"],
    "body_acc_rms_m_s2": [0.8082, 0.7244, 0.6147],
    "susp_travel_rms_m": [0.0026, 0.0019, 0.0014],
    "tire_defl_rms_m": [0.0015, 0.0013, 0.0011],
    "iabc_gains": {"kp": 182.86, "ki": 497.26, "kd": 0.035},
    "iabc_objective": 2.7321,
    "claimed_improvement_iabc_vs_abc_percent": [15.1, 26.3, 15.4],
}
PAPER_CELL = ("paper-iabc", "paper")

Row = dict[str, Any]


@dataclass(frozen=True)
class Config:
    """What one study invocation runs and reports."""

    out: Path
    seeds: int = 30
    pop: int = 100
    iters: int = 100
    realizations: int = 30
    checkpoints: tuple[int, ...] = CHECKPOINTS
    grid_points: int = GRID_POINTS


# -- runs ------------------------------------------------------------------------------------


def seed_sequence(index: int) -> np.random.SeedSequence:
    """Run seed `index`: child `index` of SeedSequence(ROOT_ENTROPY)."""
    return child_seed(ROOT_ENTROPY, index)


def box_bounds(box: str) -> dict[str, tuple[float, float]] | None:
    """The gain box: the paper's [0, 500]^3, or None for the registry's SI bounds."""
    return None if box == "si" else dict(zip(GAINS, PAPER_BOX, strict=True))


@cache
def problem(preset: str, box: str, road_seed: int = 0) -> TuningProblem:
    """Eq. 10 for the PID on class B: exact, or from the 10 s road `road_seed` (box TEN_S)."""
    objective = "rms-ratio" if box == TEN_S else OBJECTIVE
    return build_problem("quarter-car", "pid", preset, [ROAD], objective, bounds=box_bounds(box),
                         seed=road_seed if box == TEN_S else 0)


def run_path(out: Path, preset: str, box: str, algorithm: str, seed: int) -> Path:
    """Where one run's JSON lives."""
    return out / "runs" / preset / box / algorithm / f"seed_{seed:03d}.json"


def tune_once(prob: TuningProblem, algorithm: str, pop: int, iters: int, seed: int,
              road_seed: int = 0) -> Row:
    """One run through the package's ask/tell driver (its diagnostics hold the scout count)."""
    run = drive(make(algorithm, prob.bounds, pop, seed_sequence(seed), max_iter=iters, **HYPER),
                prob)
    return {
        "algorithm": algorithm,
        "seed_index": seed,
        "seed_entropy": ROOT_ENTROPY,
        "spawn_key": [seed],
        "pop_size": pop,
        "max_iter": iters,
        "objective": prob.objective,
        "road_seed": road_seed,
        "bounds": [list(b) for b in prob.bounds],
        "hyperparameters": run.hyperparameters,
        "best_gains": dict(zip(GAINS, run.x.tolist(), strict=True)),
        "best_cost": run.fun,
        "nfev": run.nfev,
        "nit": run.nit,
        "scouts": int(run.diagnostics["scouts"]),
        "wall_time_s": run.wall_time_s,
        "history": run.history.tolist(),
        "history_nfev": run.history_nfev.tolist(),
    }


def write_json(path: Path, obj: Any) -> None:
    """Atomic JSON file (its folder created if missing)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    _io.write_json(path, obj)


def check_manifest(cfg: Config) -> None:
    """Refuse to mix budgets in one folder; record the budget on first use."""
    path = cfg.out / "study.json"
    budget = {"pop_size": cfg.pop, "max_iter": cfg.iters, "objective": OBJECTIVE,
              "seed_entropy": ROOT_ENTROPY, "hyperparameters": HYPER}
    if path.exists():
        old = json.loads(path.read_text())
        if old != budget:
            raise SystemExit(f"--out: {cfg.out} holds a study with {old}; choose another folder")
        return
    write_json(path, budget)


def pairs() -> list[tuple[str, str]]:
    """(preset, box) in run order: exact cells, paper-iabc first; the 10 s protocol last."""
    return [(p, b) for p in PRESETS for b in BOXES] + [TEN_S_CELL]


def exact_pairs() -> list[tuple[str, str]]:
    """The (preset, box) cells tuned with the exact objective."""
    return [c for c in pairs() if c[1] != TEN_S]


def cells() -> list[tuple[str, str, str]]:
    """(preset, box, algorithm) in run order."""
    return [(p, b, a) for p, b in pairs() for a in ALGORITHMS]


def run_all(cfg: Config, log: Callable[[str], None] = print) -> int:
    """Run every missing (cell, seed); return how many runs were done now."""
    check_manifest(cfg)
    done = 0
    for preset, box, algorithm in cells():
        todo = [s for s in range(cfg.seeds)
                if not run_path(cfg.out, preset, box, algorithm, s).exists()]
        for s in todo:
            road = s if box == TEN_S else 0
            row = tune_once(problem(preset, box, road), algorithm, cfg.pop, cfg.iters, s, road)
            write_json(run_path(cfg.out, preset, box, algorithm, s), {"preset": preset,
                                                                       "box": box, **row})
        done += len(todo)
        log(f"{preset:10s} {box:9s} {algorithm:4s}: {len(todo)} run(s) now, "
            f"{cfg.seeds - len(todo)} already there")
    return done


def load_runs(cfg: Config) -> dict[tuple[str, str, str], list[Row]]:
    """The runs of seeds 0 .. seeds-1 by cell, in seed order."""
    return {c: [json.loads(run_path(cfg.out, *c, s).read_text()) for s in range(cfg.seeds)]
            for c in cells()}


# -- statistics ------------------------------------------------------------------------------


def finals(runs: Sequence[Row]) -> np.ndarray:
    """Final best Q of each run."""
    return np.array([r["best_cost"] for r in runs])


def at_iteration(runs: Sequence[Row], it: int) -> np.ndarray:
    """Best-so-far Q of each run after iteration `it` (its last one if it ran fewer)."""
    return np.array([r["history"][min(it, len(r["history"])) - 1] for r in runs])


def best_known(runs: Mapping[tuple[str, str, str], list[Row]], preset: str, box: str) -> float:
    """Lowest Q any run of either algorithm reached in this preset and box."""
    return float(min(finals(runs[(preset, box, a)]).min() for a in ALGORITHMS))


def summary_rows(runs: Mapping[tuple[str, str, str], list[Row]]) -> list[Row]:
    """mean/std/best/worst/median of the final Q, scouts and wall time per cell."""
    rows = []
    for (preset, box, algorithm), rs in runs.items():
        scouts = np.array([r["scouts"] for r in rs])
        rows.append({"preset": preset, "box": box, "algorithm": algorithm,
                     **stats.summary(finals(rs)),
                     "scouts_total": int(scouts.sum()), "scouts_max": int(scouts.max()),
                     "runs_with_scout": int((scouts > 0).sum()),
                     "nfev": int(rs[0]["nfev"]),
                     "wall_s_mean": float(np.mean([r["wall_time_s"] for r in rs]))})
    return rows


def rank_sum_row(abc: np.ndarray, iabc: np.ndarray) -> Row:
    """Rank-sum of IABC (reference) against ABC, raw and at RESOLUTION."""
    raw = stats.rank_sum(iabc, abc)
    coarse = stats.rank_sum(np.round(iabc / RESOLUTION), np.round(abc / RESOLUTION))
    return {"median_abc": float(np.median(abc)), "median_iabc": float(np.median(iabc)),
            "p_value": raw.p_value, "sign": raw.sign,
            "p_value_1e-9": coarse.p_value, "sign_1e-9": coarse.sign}


def wilcoxon_rows(runs: Mapping[tuple[str, str, str], list[Row]],
                  checkpoints: Iterable[int]) -> list[Row]:
    """IABC vs ABC at each checkpoint iteration, per preset and box (sign from IABC's side)."""
    rows = []
    for preset, box in pairs():
        a, b = runs[(preset, box, "abc")], runs[(preset, box, "iabc")]
        for it in checkpoints:
            if it > a[0]["max_iter"]:
                continue
            rows.append({"preset": preset, "box": box, "iteration": it,
                         "nfev_abc": int(np.median(at_nfev(a, it))),
                         **rank_sum_row(at_iteration(a, it), at_iteration(b, it))})
    return rows


def at_nfev(runs: Sequence[Row], it: int) -> np.ndarray:
    """Evaluations spent by each run after iteration `it`."""
    return np.array([r["history_nfev"][min(it, len(r["history_nfev"])) - 1] for r in runs])


def iterations_to(runs: Sequence[Row], target: float) -> np.ndarray:
    """First iteration whose best-so-far is <= target, per run (NaN: never)."""
    h = np.array([r["history"] for r in runs])
    hit = h <= target
    return np.where(hit.any(axis=1), hit.argmax(axis=1) + 1.0, np.nan)


def convergence_rows(runs: Mapping[tuple[str, str, str], list[Row]]) -> list[Row]:
    """Median and quartiles of the iterations needed to come within each tolerance of Q*."""
    rows = []
    for preset, box, algorithm in ((p, b, a) for p, b in exact_pairs() for a in ALGORITHMS):
        q_star = best_known(runs, preset, box)
        for tol in TOLERANCES:
            its = iterations_to(runs[(preset, box, algorithm)], q_star + tol)
            reached = its[~np.isnan(its)]
            q25, med, q75 = (np.percentile(reached, [25, 50, 75]) if reached.size
                             else (np.nan,) * 3)
            rows.append({"preset": preset, "box": box, "algorithm": algorithm, "tolerance": tol,
                         "runs_reached": int(reached.size), "median_iterations": float(med),
                         "q25": float(q25), "q75": float(q75)})
    return rows


# -- exact optimum -----------------------------------------------------------------------------


def grid_optimum(preset: str, box: str, points: int = GRID_POINTS) -> Row:
    """Independent check of the box optimum: a full grid, then bounded Nelder-Mead from its best."""
    prob = problem(preset, box)
    axes = [np.linspace(lo, hi, points) for lo, hi in prob.bounds]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
    q_grid = prob(grid)
    start = grid[int(np.argmin(q_grid))]

    def q(g: np.ndarray) -> float:
        return float(prob(g.reshape(1, -1))[0])

    res = minimize(q, start, method="Nelder-Mead", bounds=prob.bounds,
                   options={"xatol": 1e-6, "fatol": 1e-15, "maxiter": 5000})
    return {"grid_points": points, "q_grid": float(q_grid.min()), "q_polished": float(res.fun),
            "gains_polished": [float(v) for v in res.x]}


def optimum_rows(runs: Mapping[tuple[str, str, str], list[Row]],
                 grid_points: int = GRID_POINTS) -> list[Row]:
    """Best Q found per preset and box, its gains, and the independent grid + simplex check."""
    rows = []
    for preset, box in exact_pairs():
        pool = [r for a in ALGORITHMS for r in runs[(preset, box, a)]]
        best = min(pool, key=lambda r: r["best_cost"])
        gains = [best["best_gains"][g] for g in GAINS]
        rows.append({"preset": preset, "box": box, "q_best": best["best_cost"],
                     "gains": gains, "found_by": best["algorithm"],
                     **grid_optimum(preset, box, grid_points)})
    return rows


# -- Table 2 -----------------------------------------------------------------------------------


def scenario(preset: str, seed: int = 0) -> QuarterCarScenario:
    """PID on class B at the preset's 20 m/s; `seed` picks the 10 s road realization."""
    return PLANT.scenario(preset, ROAD, "pid", {}, seed)


def median_run(rs: Sequence[Row]) -> Row:
    """The run whose final Q is the (lower) median: the representative of its algorithm."""
    order = np.argsort(finals(rs), kind="stable")
    return rs[int(order[(len(rs) - 1) // 2])]


def table2_controllers(runs: Mapping[tuple[str, str, str], list[Row]], preset: str, box: str,
                       paper_gains: Sequence[float]) -> dict[str, np.ndarray]:
    """Gain rows of the Table 2 controllers (passive = zero gains)."""
    pick = {a: [median_run(runs[(preset, box, a)])["best_gains"][g] for g in GAINS]
            for a in ALGORITHMS}
    return {"passive": np.zeros(3), "traditional PID": np.array(TRADITIONAL),
            "paper's IABC gains": np.asarray(paper_gains, dtype=float),
            "ABC-PID": np.array(pick["abc"]), "IABC-PID": np.array(pick["iabc"])}


def exact_table(preset: str, gains: np.ndarray) -> np.ndarray:
    """(n, 4): exact stationary acc, travel, tire RMS and Q of each gain row."""
    sc = scenario(preset)
    ex = sc.exact(gains)
    q = lyapunov.rms_ratio(ex, sc.passive_exact, ex[:, lyapunov.E_STABLE] == 1.0, 1e9)
    return np.column_stack([ex[:, :3], q])


def on_realization(preset: str, seed: int, gains: np.ndarray) -> np.ndarray:
    """(n, 4): 10 s simulated acc, travel, tire RMS and Q on road realization `seed`."""
    sc = scenario(preset, seed)
    sim = sc.simulate(gains)[:, : kernel.R_FORCE]
    return np.column_stack([sim, (sim / sc.passive_sim).sum(axis=1)])


def simulated_table(preset: str, gains: np.ndarray, realizations: int) -> np.ndarray:
    """(realizations, n, 4): `on_realization` for the roads 0 .. realizations-1."""
    return np.stack([on_realization(preset, s, gains) for s in range(realizations)])


def table2_rows(runs: Mapping[tuple[str, str, str], list[Row]], preset: str, box: str,
                paper: Mapping[str, Any], realizations: int) -> list[Row]:
    """Exact and 10 s (mean, std, min, max over realizations) values of each controller."""
    ctrls = table2_controllers(runs, preset, box, [paper["iabc_gains"][g] for g in GAINS])
    gains = np.vstack(list(ctrls.values()))
    ex = exact_table(preset, gains)
    sim = simulated_table(preset, gains, realizations)
    names = ("body_acc", "susp_travel", "tire_defl", "q")
    rows = []
    for i, name in enumerate(ctrls):
        row: Row = {"preset": preset, "box": box, "controller": name,
                    **dict(zip(GAINS, gains[i].tolist(), strict=True))}
        for j, m in enumerate(names):
            row[f"{m}_exact"] = float(ex[i, j])
            row[f"{m}_sim_mean"] = float(sim[:, i, j].mean())
            row[f"{m}_sim_std"] = float(sim[:, i, j].std(ddof=1)) if realizations > 1 else 0.0
            row[f"{m}_sim_min"] = float(sim[:, i, j].min())
            row[f"{m}_sim_max"] = float(sim[:, i, j].max())
        rows.append(row)
    return rows


def improvement(abc: ArrayLike, iabc: ArrayLike) -> list[float]:
    """Percent reduction of each metric from ABC to IABC (the paper's "optimized by")."""
    a, b = np.asarray(abc, dtype=float), np.asarray(iabc, dtype=float)
    return (100.0 * (a - b) / a).tolist()


def improvement_rows(t2: Sequence[Row], paper: Mapping[str, Any]) -> list[Row]:
    """IABC vs ABC improvement per metric: paper, ours exact, ours 10 s mean."""
    metrics = ("body_acc", "susp_travel", "tire_defl")
    by = {(r["preset"], r["box"], r["controller"]): r for r in t2}
    rows = []
    for preset, box in exact_pairs():
        a, b = by[(preset, box, "ABC-PID")], by[(preset, box, "IABC-PID")]
        for kind in ("exact", "sim_mean"):
            pct = improvement([a[f"{m}_{kind}"] for m in metrics],
                              [b[f"{m}_{kind}"] for m in metrics])
            rows.append({"preset": preset, "box": box, "source": f"ours ({kind})",
                         **dict(zip(metrics, pct, strict=True))})
    rows.append({"preset": "paper", "box": "paper", "source": "paper, Table 2",
                 **dict(zip(metrics, improvement(*paper_rows(paper)[1:]), strict=True))})
    return rows


def paper_rows(paper: Mapping[str, Any]) -> list[list[float]]:
    """The paper's Table 2 by controller: [acc, travel, tire] for traditional, ABC, IABC."""
    cols = (paper["body_acc_rms_m_s2"], paper["susp_travel_rms_m"], paper["tire_defl_rms_m"])
    return [list(v) for v in zip(*cols, strict=True)]


def paper_consistency(paper: Mapping[str, Any]) -> Row:
    """Lower bounds on the paper's own Q for ABC-PID and traditional PID from its Table 2.

    Q = sum of ratios to passive; if every metric of controller X is at least c times IABC's,
    then Q_X >= c Q_IABC with c the smallest metric ratio.
    """
    trad, abc, iabc = (np.array(r) for r in paper_rows(paper))
    q = float(paper["iabc_objective"])
    return {"q_iabc_paper": q,
            "abc_over_iabc_min_ratio": float((abc / iabc).min()),
            "q_abc_implied_at_least": q * float((abc / iabc).min()),
            "trad_over_iabc_min_ratio": float((trad / iabc).min()),
            "q_traditional_implied_at_least": q * float((trad / iabc).min())}


def realization_check(preset: str, gains: Sequence[float], target: float,
                      realizations: int) -> Row:
    """How often a 10 s realization scores Q <= target for `gains` (the paper's 2.7321)."""
    q = simulated_table(preset, np.asarray(gains, dtype=float).reshape(1, 3), realizations)[:, 0, 3]
    return {"preset": preset, "gains": list(gains), "target": target,
            "fraction_at_or_below": float(np.mean(q <= target)),
            "q_min": float(q.min()), "q_median": float(np.median(q)), "q_max": float(q.max())}


# -- the paper's protocol: one 10 s road -------------------------------------------------------

METRICS = ("body_acc", "susp_travel", "tire_defl")


def ten_s_rows(runs: Mapping[tuple[str, str, str], list[Row]], preset: str) -> list[Row]:
    """Per seed: ABC's and IABC's best 10 s Q on road `seed`, the exact Q of their gains, and the
    IABC vs ABC improvement (%) of the three RMS values on that road (the paper's Table 2 recipe).
    """
    rows = []
    for a, b in zip(runs[(preset, TEN_S, "abc")], runs[(preset, TEN_S, "iabc")], strict=True):
        gains = np.array([[r["best_gains"][g] for g in GAINS] for r in (a, b)])
        sim = on_realization(preset, a["road_seed"], gains)
        exact = exact_table(preset, gains)[:, 3]
        rows.append({"seed": a["seed_index"], "q10_abc": a["best_cost"], "q10_iabc": b["best_cost"],
                     "q_exact_abc": float(exact[0]), "q_exact_iabc": float(exact[1]),
                     **{f"{m}_pct": v for m, v in zip(METRICS, improvement(sim[0, :3], sim[1, :3]),
                                                       strict=True)}})
    return rows


def ten_s_summary(rows: Sequence[Row], target: float, claimed: Sequence[float]) -> list[Row]:
    """Summary of each column of `ten_s_rows`; Q columns count runs at or below `target`,
    improvement columns runs at or above the paper's claimed value."""
    out = []
    for key in rows[0]:
        if key == "seed":
            continue
        v = np.array([r[key] for r in rows])
        if key.endswith("_pct"):
            hits = int(np.sum(v >= claimed[METRICS.index(key[:-4])]))
        else:
            hits = int(np.sum(v <= target))
        out.append({"quantity": key, **stats.summary(v), "hits": hits})
    every = np.all([[r[f"{m}_pct"] >= c for m, c in zip(METRICS, claimed, strict=True)]
                    for r in rows], axis=1)
    out.append({"quantity": "all three pct >= claimed", "hits": int(every.sum()), "n": len(rows)})
    return out


def realization_pairs(preset: str, gains: Sequence[float], realizations: int,
                      claimed: Sequence[float]) -> Row:
    """One controller, two different 10 s roads (all ordered pairs): how often the second road
    makes it look better than the first by the paper's claimed percentages."""
    sim = simulated_table(preset, np.asarray(gains, dtype=float).reshape(1, 3),
                          realizations)[:, 0, :3]
    i, j = np.nonzero(~np.eye(realizations, dtype=bool))
    pct = 100.0 * (sim[i] - sim[j]) / sim[i]
    each = pct >= np.asarray(claimed)
    return {"preset": preset, "gains": list(gains), "pairs": int(i.size),
            "fraction_each_at_least_claimed": each.mean(axis=0).tolist() if i.size else [],
            "fraction_all_three": float(each.all(axis=1).mean()) if i.size else 0.0,
            "pct_p95": np.percentile(pct, 95, axis=0).tolist() if i.size else [],
            "pct_max": pct.max(axis=0).tolist() if i.size else []}


# -- figures -----------------------------------------------------------------------------------


def curves(rs: Sequence[Row], shift: float = 0.0) -> list[tuple[np.ndarray, np.ndarray]]:
    """(history_nfev, history - shift) per run, the gap floored at GAP_FLOOR when shifted."""
    out = []
    for r in rs:
        h = np.asarray(r["history"], dtype=float) - shift
        out.append((np.asarray(r["history_nfev"], dtype=float),
                    np.maximum(h, GAP_FLOOR) if shift else h))
    return out


def plot_cells(runs: Mapping[tuple[str, str, str], list[Row]], out: Path) -> list[Path]:
    """Per preset and box: Q and the gap Q - Q* against evaluations, ABC vs IABC."""
    from chassistune.plots.convergence import plot_convergence

    paths = []
    for preset, box in pairs():
        q_star = best_known(runs, preset, box)
        kinds = (("q", 0.0),) if box == TEN_S else (("q", 0.0), ("gap", q_star))
        for kind, shift in kinds:
            path = out / f"convergence_{kind}_{preset}_{box}.png"
            what = ("Q (eq. 10)" if kind == "q"
                    else f"gap Q - Q* (floored at {GAP_FLOOR:g}), Q* = {q_star:.6f}")
            plot_convergence({a.upper(): curves(runs[(preset, box, a)], shift)
                              for a in ALGORITHMS}, str(path),
                             title=f"{preset}, {box} box: {what}")
            paths.append(path)
    return paths


# -- files -------------------------------------------------------------------------------------


def write_csv(path: Path, rows: Sequence[Row]) -> None:
    """Atomic CSV of dict rows (lists joined by spaces)."""
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    for r in rows:
        writer.writerow({k: " ".join(f"{x:.10g}" for x in v) if isinstance(v, list) else v
                         for k, v in r.items()})
    _io.write_text(path, buf.getvalue())


# -- markdown ----------------------------------------------------------------------------------


def md_table(header: Sequence[str], rows: Iterable[Sequence[object]]) -> str:
    """A markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def pm(row: Row, m: str, scale: float, digits: int) -> list[str]:
    """[exact, 'mean ± sd'] of metric m of a Table 2 row, scaled."""
    return [f"{row[f'{m}_exact'] * scale:.{digits}f}",
            f"{row[f'{m}_sim_mean'] * scale:.{digits}f} ± {row[f'{m}_sim_std'] * scale:.{digits}f}"]


def md_table2(t2: Sequence[Row], preset: str, box: str, paper: Mapping[str, Any]) -> str:
    """Table 2 of one cell: ours (exact; 10 s mean +- sd) and the paper's where it has one."""
    papers = dict(zip(paper["controllers"], paper_rows(paper), strict=True))
    show_paper = (preset, box) == PAPER_CELL
    head = ["controller", "kp, ki, kd", "acc exact", "acc 10 s", "travel exact (mm)",
            "travel 10 s (mm)", "tire exact (mm)", "tire 10 s (mm)", "Q exact", "Q 10 s"]
    if show_paper:
        head += ["paper acc", "paper travel (mm)", "paper tire (mm)"]
    rows = []
    for r in (r for r in t2 if (r["preset"], r["box"]) == (preset, box)):
        line = [r["controller"], ", ".join(f"{r[g]:.4g}" for g in GAINS),
                *pm(r, "body_acc", 1, 4), *pm(r, "susp_travel", 1e3, 3),
                *pm(r, "tire_defl", 1e3, 3), *pm(r, "q", 1, 4)]
        if show_paper:
            p = papers.get(r["controller"])
            line += ([f"{p[0]:.4f}", f"{p[1] * 1e3:.1f}", f"{p[2] * 1e3:.1f}"] if p
                     else ["-", "-", "-"])
        rows.append(line)
    return md_table(head, rows)


def percent(x: float) -> str:
    """A percentage: two decimals, or scientific below 0.005 in magnitude (no '-0.00')."""
    return f"{x:.2f}" if abs(x) >= 0.005 else f"{x:.1e}"


def number(x: float) -> str:
    """Four decimals, or scientific for small non-zero magnitudes (no '-0.0000')."""
    return f"{x:.4f}" if x == 0 or abs(x) >= 5e-5 else f"{x:.1e}"


def md_report(res: Mapping[str, Any], paper: Mapping[str, Any]) -> str:
    """tables.md: every table of the study in markdown."""
    parts = ["# Jing and Xu 2023 (iabc-suspension) study: tables (generated by "
             "paper_scripts/iabc_suspension_study.py)\n"]
    for preset, box in exact_pairs():
        parts.append(f"\n## Table 2, {preset}, {box} box\n\n"
                     + md_table2(res["table2"], preset, box, paper))
    parts.append("\n## IABC vs ABC improvement (%)\n\n" + md_table(
        ["preset", "box", "source", "body acc", "travel", "tire"],
        ([r["preset"], r["box"], r["source"], *(percent(r[m]) for m in
          ("body_acc", "susp_travel", "tire_defl"))] for r in res["improvement"])))
    parts.append(f"\n## Final Q, {res['seeds']} runs per cell\n\n" + md_table(
        ["preset", "box", "algorithm", "mean", "std", "best", "worst", "median", "scouts",
         "nfev"],
        ([r["preset"], r["box"], r["algorithm"], f"{r['mean']:.8f}", f"{r['std']:.2e}",
          f"{r['best']:.10f}", f"{r['worst']:.10f}", f"{r['median']:.10f}",
          f"{r['scouts_total']} ({r['runs_with_scout']} runs)", r["nfev"]]
         for r in res["summary"])))
    parts.append("\n## Wilcoxon rank-sum, IABC vs ABC (sign from IABC's side)\n\n" + md_table(
        ["preset", "box", "iteration", "nfev", "median ABC", "median IABC", "p", "+/=/-",
         "p (Q to 1e-9)", "+/=/- (1e-9)"],
        ([r["preset"], r["box"], r["iteration"], r["nfev_abc"], f"{r['median_abc']:.10f}",
          f"{r['median_iabc']:.10f}", f"{r['p_value']:.3g}", r["sign"],
          f"{r['p_value_1e-9']:.3g}", r["sign_1e-9"]] for r in res["wilcoxon"])))
    parts.append("\n## Iterations to come within a tolerance of Q*\n\n" + md_table(
        ["preset", "box", "algorithm", "tolerance", "runs reached", "median [IQR]"],
        ([r["preset"], r["box"], r["algorithm"], f"{r['tolerance']:g}", r["runs_reached"],
          f"{r['median_iterations']:.0f} [{r['q25']:.0f}, {r['q75']:.0f}]"]
         for r in res["convergence"])))
    parts.append("\n## The paper's protocol: tuned on one 10 s road (seed = road)\n\n" + md_table(
        ["quantity", "mean", "std", "min", "max", "median", "hits (Q <= 2.7321 or pct >= claim)"],
        ([r["quantity"], *(number(r[k]) if k in r else "-"
                           for k in ("mean", "std", "best", "worst", "median")),
          f"{r['hits']} of {r['n']}"] for r in res["ten_s_summary"])))
    rp = res["road_pairs"]
    parts.append(
        f"\nSame gains (the exact optimum), two different 10 s roads, {rp['pairs']} ordered pairs: "
        "fraction of pairs in which the second road's RMS values are lower by at least the "
        "paper's 15.1 / 26.3 / 15.4 %: "
        + " / ".join(f"{x:.3f}" for x in rp["fraction_each_at_least_claimed"])
        + f" (all three at once: {rp['fraction_all_three']:.3f}); 95th percentiles of the "
        "differences: " + " / ".join(f"{x:.1f} %" for x in rp["pct_p95"]) + ".\n")
    parts.append("\n## Exact optimum per box\n\n" + md_table(
        ["preset", "box", "Q* (best run)", "kp, ki, kd", "found by",
         "grid min", "grid + Nelder-Mead", "its kp, ki, kd"],
        ([r["preset"], r["box"], f"{r['q_best']:.10f}", ", ".join(f"{g:.2f}" for g in r["gains"]),
          r["found_by"], f"{r['q_grid']:.6f} ({r['grid_points']}^3)", f"{r['q_polished']:.10f}",
          ", ".join(f"{g:.2f}" for g in r["gains_polished"])] for r in res["optimum"])))
    return "".join(parts)


# -- driver ------------------------------------------------------------------------------------


def report(cfg: Config, log: Callable[[str], None] = print) -> dict[str, Any]:
    """Every report of the finished runs, written under cfg.out; returns them."""
    runs = load_runs(cfg)
    paper = PAPER
    t2 = [row for p, b in exact_pairs()
          for row in table2_rows(runs, p, b, paper, cfg.realizations)]
    opt = optimum_rows(runs, cfg.grid_points)
    q_opt = next(r for r in opt if (r["preset"], r["box"]) == PAPER_CELL)
    claimed = paper["claimed_improvement_iabc_vs_abc_percent"]
    ten_s = ten_s_rows(runs, TEN_S_CELL[0])
    res: dict[str, Any] = {
        "seeds": cfg.seeds,
        "summary": summary_rows(runs),
        "wilcoxon": wilcoxon_rows(runs, cfg.checkpoints),
        "convergence": convergence_rows(runs),
        "optimum": opt,
        "table2": t2,
        "improvement": improvement_rows(t2, paper),
        "paper_consistency": paper_consistency(paper),
        "q_2_7321_check": [
            realization_check("paper-iabc", q_opt["gains"], paper["iabc_objective"],
                              cfg.realizations),
            realization_check("paper-iabc", [paper["iabc_gains"][g] for g in GAINS],
                              paper["iabc_objective"], cfg.realizations)],
        "ten_s": ten_s,
        "ten_s_summary": ten_s_summary(ten_s, paper["iabc_objective"], claimed),
        "road_pairs": realization_pairs(PAPER_CELL[0], q_opt["gains"], cfg.realizations, claimed),
        "after_first_iteration_worst": {
            f"{p}/{b}/{a}": float(at_iteration(runs[(p, b, a)], 1).max())
            for p, b, a in cells()},
    }
    for name in ("summary", "wilcoxon", "convergence", "optimum", "table2", "improvement", "ten_s",
                 "ten_s_summary"):
        write_csv(cfg.out / f"{name}.csv", res[name])
    write_json(cfg.out / "results.json", res)
    _io.write_text(cfg.out / "tables.md", md_report(res, paper))
    for path in plot_cells(runs, cfg.out):
        log(f"wrote {path}")
    return res


def run_study(cfg: Config, log: Callable[[str], None] = print) -> dict[str, Any]:
    """Run what is missing, then write every report. `results["new_runs"]`: runs done now."""
    new = run_all(cfg, log)
    res = report(cfg, log)
    res["new_runs"] = new
    return res


def parse(argv: Sequence[str] | None) -> Config:
    """Command-line options."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=30, help="runs per cell (default 30)")
    ap.add_argument("--out", type=Path, default=Path("docs/results/iabc_suspension"),
                    help="output folder (default docs/results/iabc_suspension)")
    ap.add_argument("--pop", type=int, default=100, help="food sources (default 100)")
    ap.add_argument("--iters", type=int, default=100, help="iterations (default 100)")
    ap.add_argument("--realizations", type=int, default=30,
                    help="10 s road realizations for the simulated Table 2 (default 30)")
    a = ap.parse_args(argv)
    for name in ("seeds", "pop", "iters", "realizations"):
        if getattr(a, name) < 1:
            ap.error(f"--{name} must be at least 1")
    return Config(out=a.out, seeds=a.seeds, pop=a.pop, iters=a.iters,
                  realizations=a.realizations)


def main(argv: Sequence[str] | None = None) -> int:
    cfg = parse(argv)
    t0 = time.perf_counter()
    res = run_study(cfg)
    print(f"{res['new_runs']} new run(s); reports in {cfg.out} ({time.perf_counter() - t0:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
