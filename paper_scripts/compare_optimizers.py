"""Compare the optimizers on F1-F23 and check the papers' claims (issue 3, item 7).

Outside the test run: the whole grid takes hours on this machine. It is resumable and runnable in
parts: a *cell* is (protocol, function, method) with its runs; each finished cell is written
atomically (temporary file + rename) as one JSON file under `--out`, and a rerun skips finished
cells. Select parts with `--protocols`, `--functions`, `--methods` and `--part K/N` (every N-th
cell from the K-th), then build the tables from whatever cells exist with `--report`.

Protocols (population 30, usual dimensions, 30 runs, run r seeded with SeedSequence(ROOT, r)):
  evals    equal evaluation budget, 15,000 evaluations (= AO's cost of 500 iterations)
  iters    the papers' equal-iteration protocol, 500 iterations (evaluations differ: POA 2N, ...)
  seed000  derlsp-ao-abs's setting for its claims (population 50, 500 iterations), F4 F5 F6 F14

Methods: our twelve (`ao`, ..., `dbo`), `ao+2` (DERLSP-AO without its DE step: the ablation of
derlsp-ao-abs's Fig. 6), mealpy 3.0.3's peers `mealpy:ao|gwo|mfo|abc|de|pso|ga|poa` (with our
hyperparameters where mealpy has them) and `scipy:de` (scipy's differential_evolution,
rand1bin, F 0.5, CR 0.9, the same 30 initial points, no polishing, no early stop).

    python paper_scripts/compare_optimizers.py --protocols evals --functions F1,F16 --runs 5
    python paper_scripts/compare_optimizers.py --part 0/4          # a quarter of the grid
    python paper_scripts/compare_optimizers.py --report            # docs/optimizer_comparison.md
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from chassistune import _io, benchmarks, stats
from chassistune._rng import child_seed, int_seed, make_rng
from chassistune.optimizers import registry
from chassistune.optimizers.minimize import minimize

ROOT = 20260301
POP = 30
EVALS = 15_000
ITERS = 500
OURS = registry.names()
MEALPY = ["ao", "gwo", "mfo", "abc", "de", "pso", "ga", "poa"]
SEED000_FUNCS = ["F4", "F5", "F6", "F14"]
SEED000_METHODS = ["ao", "ao+2", "derlsp-ao", "mfo", "gwo"]
TABLE4 = {  # deffao-vehicle-abs Table 4 (../shared/paper_results.toml): MFO, POA, DBO, AO, DEFFAO
    "F2": [60.087, 6.0243e-32, 0.0497, 6.212e-47, 3.846e-52],
    "F3": [25007.2, 9.935e-60, 2835.44, 3.809e-80, 8.05e-96],
    "F5": [661.167, 28.8163, 43.8941, 0.0095, 7.801e-14],
    "F8": [-7921.77, -9026.67, -5417.67, -5189.61, -12562.8],
    "F21": [-2.68268, -10.1516, -4.66256, -10.1275, -10.1532],
}
TABLE4_METHODS = ["mfo", "poa", "dbo", "ao", "deffao"]
DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "compare_optimizers"
DOCS = Path(__file__).resolve().parents[1] / "docs"
GRID = np.unique(np.geomspace(POP, EVALS, 40).astype(int))


# --- one run of one method ------------------------------------------------------------------------


def _objective(
    fn: benchmarks.BenchmarkFunction, seed: np.random.SeedSequence
) -> Callable[..., Any]:
    noise = make_rng(child_seed(seed, 0)) if fn.noisy else None
    return lambda x: fn(x, noise)


def _budget(protocol: str) -> dict[str, int]:
    if protocol == "evals":
        return {"max_evals": EVALS}
    return {"max_iter": ITERS}


def _pop(protocol: str) -> int:
    return 50 if protocol == "seed000" else POP


def run_ours(
    method: str, fn: benchmarks.BenchmarkFunction, protocol: str, seed: np.random.SeedSequence
) -> dict[str, Any]:
    name, hyper = ("derlsp-ao", {"de_step": False}) if method == "ao+2" else (method, {})
    res = minimize(
        _objective(fn, seed),
        fn.bounds(),
        method=name,
        pop_size=_pop(protocol),
        seed=seed,
        **_budget(protocol),
        **hyper,
    )
    return {
        "best_f": res.fun,
        "nfev": res.nfev,
        "nit": res.nit,
        "wall_s": res.wall_time_s,
        "history": res.history.tolist(),
        "history_nfev": res.history_nfev.tolist(),
    }


def run_mealpy(
    method: str, fn: benchmarks.BenchmarkFunction, protocol: str, seed: np.random.SeedSequence
) -> dict[str, Any]:
    from mealpy import FloatVar
    from mealpy.evolutionary_based import DE, GA
    from mealpy.swarm_based import ABC, AO, GWO, MFO, POA, PSO

    d, pop = fn.dim, _pop(protocol)
    per_epoch = 2 * pop if method in ("abc", "poa") else pop
    # equal budget: the schedule horizon from the budget, as ours (mealpy's T is its epoch count)
    epochs = ITERS if protocol != "evals" else (EVALS - pop) // per_epoch
    classes: dict[str, Callable[[], Any]] = {
        "ao": lambda: AO.OriginalAO(epoch=epochs, pop_size=pop),
        "gwo": lambda: GWO.OriginalGWO(epoch=epochs, pop_size=pop),
        "mfo": lambda: MFO.OriginalMFO(epoch=epochs, pop_size=pop),
        "abc": lambda: ABC.OriginalABC(epoch=epochs, pop_size=pop, n_limits=pop * d),
        "de": lambda: DE.OriginalDE(epoch=epochs, pop_size=pop, wf=0.5, cr=0.9, strategy=0),
        "pso": lambda: PSO.OriginalPSO(epoch=epochs, pop_size=pop, c1=1.49445, c2=1.49445, w=0.729),
        "ga": lambda: GA.BaseGA(epoch=epochs, pop_size=pop, pc=0.9, pm=1.0 / d),
        "poa": lambda: POA.OriginalPOA(epoch=epochs, pop_size=pop),
    }
    objective = _objective(fn, seed)
    calls = [0]

    def one(x: np.ndarray) -> float:
        calls[0] += 1
        return float(objective(x[None, :])[0])

    lo, hi = fn.bounds().T
    problem = {
        "obj_func": one,
        "bounds": FloatVar(lb=lo.tolist(), ub=hi.tolist()),
        "minmax": "min",
        "log_to": None,
    }
    term = {"max_fe": EVALS} if protocol == "evals" else None
    model = classes[method]()
    t0 = time.perf_counter()
    best = model.solve(problem, termination=term, seed=int_seed(seed))
    wall = time.perf_counter() - t0
    return {
        "best_f": float(best.target.fitness),
        "nfev": calls[0],
        "nit": len(model.history.list_global_best_fit),
        "wall_s": wall,
    }


def run_scipy_de(
    fn: benchmarks.BenchmarkFunction, protocol: str, seed: np.random.SeedSequence
) -> dict[str, Any]:
    from scipy.optimize import differential_evolution

    b = fn.bounds()
    rng = make_rng(seed)
    init = b[:, 0] + rng.random((POP, b.shape[0])) * (b[:, 1] - b[:, 0])
    maxiter = (EVALS - POP) // POP if protocol == "evals" else ITERS
    objective = _objective(fn, seed)
    rows = [0]

    def batch(x: np.ndarray) -> np.ndarray:  # scipy passes (d, S) and counts calls, not rows
        pts = np.atleast_2d(x.T)
        rows[0] += pts.shape[0]
        return objective(pts)  # type: ignore[no-any-return]

    t0 = time.perf_counter()
    res = differential_evolution(
        batch,
        b,
        strategy="rand1bin",
        maxiter=maxiter,
        mutation=0.5,
        recombination=0.9,
        rng=rng,
        polish=False,
        init=init,
        tol=0.0,
        atol=0.0,
        vectorized=True,
        updating="deferred",
    )
    wall = time.perf_counter() - t0
    return {"best_f": float(res.fun), "nfev": rows[0], "nit": int(res.nit), "wall_s": wall}


def run_one(
    method: str, fn: benchmarks.BenchmarkFunction, protocol: str, seed: np.random.SeedSequence
) -> dict[str, Any]:
    if method.startswith("mealpy:"):
        return run_mealpy(method.split(":", 1)[1], fn, protocol, seed)
    if method == "scipy:de":
        return run_scipy_de(fn, protocol, seed)
    return run_ours(method, fn, protocol, seed)


# --- cells ----------------------------------------------------------------------------------------


def all_cells() -> list[tuple[str, str, str]]:
    methods = [*OURS, *(f"mealpy:{m}" for m in MEALPY), "scipy:de"]
    cells = [(p, f, m) for p in ("evals", "iters") for f in benchmarks.names() for m in methods]
    cells += [("seed000", f, m) for f in SEED000_FUNCS for m in SEED000_METHODS]
    return cells


def cell_path(out: Path, protocol: str, function: str, method: str) -> Path:
    return out / protocol / function / f"{method.replace(':', '_')}.json"


def load_cell(path: Path) -> dict[str, Any] | None:
    try:
        with open(path) as fh:
            data: dict[str, Any] = json.load(fh)
            return data
    except (OSError, ValueError):
        return None


def run_cell(out: Path, protocol: str, function: str, method: str, runs: int) -> bool:
    """Run one cell unless it is finished with at least `runs` runs; True if it ran."""
    path = cell_path(out, protocol, function, method)
    done = load_cell(path)
    if done is not None and len(done["runs"]) >= runs:
        return False
    fn = benchmarks.get(function)
    results = []
    for r in range(runs):
        res = run_one(method, fn, protocol, child_seed(ROOT, r))
        results.append(res)
    data: dict[str, Any] = {
        "protocol": protocol,
        "function": function,
        "method": method,
        "dim": fn.dim,
        "pop": _pop(protocol),
        **_budget(protocol),
        "runs": [
            {k: v for k, v in res.items() if k not in ("history", "history_nfev")}
            for res in results
        ],
    }
    if all("history" in res for res in results):
        band = stats.convergence_band(
            [res["history"] for res in results], [res["history_nfev"] for res in results], GRID
        )
        data["convergence"] = {
            k: [None if not math.isfinite(v) else float(v) for v in vals]
            for k, vals in band.items()
        }
    path.parent.mkdir(parents=True, exist_ok=True)
    _io.write_json(path, data, indent=None)
    return True


# --- report ---------------------------------------------------------------------------------------


def _finals(out: Path, protocol: str, function: str, method: str) -> np.ndarray | None:
    cell = load_cell(cell_path(out, protocol, function, method))
    if cell is None:
        return None
    return np.array([r["best_f"] for r in cell["runs"]], dtype=float)


def _g(x: float) -> str:
    return "-" if not math.isfinite(x) else f"{x:.3g}"


def report(out: Path) -> str:
    lines = [
        "# Optimizer comparison (generated by paper_scripts/compare_optimizers.py)",
        "",
        f"Population {POP} (the derlsp-ao-abs paper's checks: 50), usual dimensions, runs per cell "
        "as listed; "
        f"protocol `evals`: {EVALS} evaluations; `iters`: {ITERS} iterations. "
        "Cells not run yet are shown as blank.",
        "",
    ]
    for protocol in ("evals", "iters"):
        lines += [f"## Our twelve, protocol `{protocol}`: mean (std) of the final best cost", ""]
        lines += ["| function | " + " | ".join(OURS) + " |", "|---" * (len(OURS) + 1) + "|"]
        scores: list[list[float]] = []
        per_method: dict[str, dict[str, np.ndarray]] = {m: {} for m in OURS}
        for f in benchmarks.names():
            row, vals = [], []
            for m in OURS:
                v = _finals(out, protocol, f, m)
                if v is None:
                    row.append("")
                    vals.append(math.nan)
                    continue
                per_method[m][f] = v
                s = stats.summary(v)
                row.append(f"{_g(s['mean'])} ({_g(s['std'])})")
                vals.append(s["mean"])
            lines.append(f"| {f} | " + " | ".join(row) + " |")
            if all(math.isfinite(v) for v in vals):
                scores.append(vals)
        lines.append("")
        if len(scores) >= 2:
            fr = stats.friedman(scores, OURS)
            ranks = ", ".join(
                f"{m} {r:.2f}"
                for m, r in sorted(zip(OURS, fr.mean_ranks, strict=True), key=lambda t: t[1])
            )
            lines += [
                f"Friedman mean ranks over {fr.n_problems} functions (1 = best): {ranks}; "
                f"chi2 = {_g(fr.statistic)}, p = {_g(fr.p_value)}.",
                "",
            ]
            for control in ("derlsp-ao", "deffao"):
                comps = stats.posthoc(scores, OURS, control=control)
                sig = [
                    f"{c.b} ({'better' if c.rank_difference > 0 else 'worse'})"
                    for c in comps
                    if c.reject
                ]
                lines += [
                    f"Holm post-hoc against {control}: significant for "
                    f"{', '.join(sig) if sig else 'none'}.",
                    "",
                ]
        for ref in ("derlsp-ao", "deffao"):
            counts = {
                m: stats.rank_sum_counts(per_method[ref], per_method[m]) for m in OURS if m != ref
            }
            lines += [
                f"Wilcoxon rank-sum, {ref} against each (+ {ref} better / = / -): "
                + "; ".join(f"{m} {c['+']}/{c['=']}/{c['-']}" for m, c in counts.items()),
                "",
            ]
        lines += [
            f"## Ours against mealpy 3.0.3 and scipy, protocol `{protocol}`",
            "",
            "Mean final cost (ours / peer), rank-sum sign from our side, and mean wall time "
            "per run (ours / peer, objective included).",
            "",
            "| function | method | ours | peer | sign | time ours / peer (s) |",
            "|---|---|---|---|---|---|",
        ]
        peers = [(m, f"mealpy:{m}") for m in MEALPY] + [("de", "scipy:de")]
        for f in benchmarks.names():
            for ours, peer in peers:
                a, b = _finals(out, protocol, f, ours), _finals(out, protocol, f, peer)
                if a is None or b is None:
                    continue
                ca = load_cell(cell_path(out, protocol, f, ours))
                cb = load_cell(cell_path(out, protocol, f, peer))
                ta = np.mean([r["wall_s"] for r in ca["runs"]]) if ca else math.nan
                tb = np.mean([r["wall_s"] for r in cb["runs"]]) if cb else math.nan
                sign = stats.rank_sum(a, b).sign
                lines.append(
                    f"| {f} | {peer} | {_g(a.mean())} | {_g(b.mean())} | {sign} | "
                    f"{_g(float(ta))} / {_g(float(tb))} |"
                )
        lines.append("")
    lines += claims(out)
    return "\n".join(lines) + "\n"


def claims(out: Path) -> list[str]:
    lines = [
        "## The papers' claims",
        "",
        "Tian et al. (derlsp-ao-abs), Figs. 6-7: DERLSP-AO reaches lower costs than AO, MFO and "
        "GWO (population "
        "50, 500 iterations), and AO with the first two strategies (`ao+2`) beats AO. "
        "A claim holds on a function when the rank-sum sign is + (significantly lower).",
        "",
        "| function | claim | sign | medians (claimed winner / other) | holds |",
        "|---|---|---|---|---|",
    ]
    pairs = [("derlsp-ao", "ao"), ("derlsp-ao", "mfo"), ("derlsp-ao", "gwo"), ("ao+2", "ao")]
    for f in SEED000_FUNCS:
        for a_name, b_name in pairs:
            a, b = _finals(out, "seed000", f, a_name), _finals(out, "seed000", f, b_name)
            if a is None or b is None:
                continue
            sign = stats.rank_sum(a, b).sign
            lines.append(
                f"| {f} | {a_name} < {b_name} | {sign} | {_g(float(np.median(a)))} / "
                f"{_g(float(np.median(b)))} | {'yes' if sign == '+' else 'no'} |"
            )
    lines += [
        "",
        "Tian, Huang et al. 2025 (deffao-vehicle-abs), Table 4 (best fitness; the protocol is not "
        "stated: we use `iters`, "
        "population 30, 500 iterations): published value and our best (median) for each "
        "method, and whether DEFFAO is significantly lower than each rival (rank-sum +).",
        "",
        "| function | " + " | ".join(TABLE4_METHODS) + " | DEFFAO best? |",
        "|---" * (len(TABLE4_METHODS) + 2) + "|",
    ]
    for f, published in TABLE4.items():
        row, finals = [], {}
        for m, pub in zip(TABLE4_METHODS, published, strict=True):
            v = _finals(out, "iters", f, m)
            if v is None:
                row.append(f"{_g(pub)} / ")
                continue
            finals[m] = v
            row.append(f"{_g(pub)} / {_g(float(v.min()))} ({_g(float(np.median(v)))})")
        verdict = ""
        if len(finals) == len(TABLE4_METHODS):
            signs = [stats.rank_sum(finals["deffao"], finals[m]).sign for m in TABLE4_METHODS[:-1]]
            verdict = "yes" if all(s == "+" for s in signs) else "no (" + "".join(signs) + ")"
        lines.append(f"| {f} | " + " | ".join(row) + f" | {verdict} |")
    return [*lines, ""]


# --- command line ---------------------------------------------------------------------------------


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="folder of the cell files")
    ap.add_argument("--protocols", default="evals,iters,seed000")
    ap.add_argument("--functions", default=",".join(benchmarks.names()))
    ap.add_argument("--methods", default=None, help="comma-separated (default: all)")
    ap.add_argument("--runs", type=int, default=30)
    ap.add_argument("--part", default="0/1", help="K/N: run every N-th cell from the K-th")
    ap.add_argument("--report", action="store_true", help="write docs/optimizer_comparison.md")
    ap.add_argument("--report-to", type=Path, default=DOCS / "optimizer_comparison.md")
    args = ap.parse_args(argv)
    if args.report:
        text = report(args.out)
        args.report_to.parent.mkdir(parents=True, exist_ok=True)
        _io.write_text(args.report_to, text)
        print(f"wrote {args.report_to}")
        return 0
    k, n = (int(v) for v in args.part.split("/"))
    protocols = set(args.protocols.split(","))
    functions = {benchmarks.get(f).name for f in args.functions.split(",")}
    methods = set(args.methods.split(",")) if args.methods else None
    cells = [
        c
        for c in all_cells()
        if c[0] in protocols and c[1] in functions and (methods is None or c[2] in methods)
    ][k::n]
    for i, (p, f, m) in enumerate(cells, 1):
        t0 = time.perf_counter()
        ran = run_cell(args.out, p, f, m, args.runs)
        state = f"{time.perf_counter() - t0:.1f} s" if ran else "done before"
        print(f"[{i}/{len(cells)}] {p} {f} {m}: {state}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
