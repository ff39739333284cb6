"""fuzzy-immune-abs (Ding 2023): the fuzzy immune PID of the single-wheel ABS against PID, fuzzy PID
and the threshold ABS on asphalt (mu 0.8) and dirt (mu 0.2), Figs. 4-5, from the shipped study
`fuzzy-immune-abs` (each PID structure tuned alike by DERLSP-AO; the threshold ABS untuned)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from chassistune.papers import claims, common, keys, published
from chassistune.papers.claims import Claim
from chassistune.papers.derlsp_ao_abs import abs_trace, run_gains
from chassistune.papers.notation import NOT_PRINTED
from chassistune.scenarios.abs_wheel import AbsWheelScenario
from chassistune.scenarios.base import Trace

KEY = keys.FUZZY_IMMUNE_ABS
STUDY = KEY
PRESET = "paper-fuzzy-immune"
ROADS = (("asphalt-0.8", "Fig. 4"), ("dirt-0.2", "Fig. 5"))
TUNED = (("PID", "pid"), ("fuzzy PID", "fuzzy-pid"), ("fuzzy immune PID", "fuzzy-immune-pid"))
CLAIMED = "fuzzy immune PID"
METRICS = {"stop_time_s": "braking time", "stop_distance_m": "braking distance"}
STAND_INS = (
    "the paper compares against the methods of its refs. [1] (hybrid control) and [2] (dynamic "
    "programming), too vaguely described to rebuild: ours are stand-ins (PID and fuzzy PID tuned "
    "alike, the threshold ABS)"
)
SIGNIFICANCE = (
    "tuned runs against tuned runs: rank-sum; against the fixed threshold ABS: signed-rank; "
    "alpha 0.05; undecided where the seeds cannot reach significance"
)
SETTLE_RULE = (
    "settled: within 0.05 of the target slip at every sample above 2 m/s, on every run; the "
    "fuzzy immune PID's settling times lowest against each stand-in's (" + SIGNIFICANCE + ") "
    "and their median by the stated time (else holds in ranking only); "
)
CLAIMS: tuple[Claim, ...] = (
    Claim(
        KEY,
        "asphalt-settle",
        "由图4可知,在沥青路面行驶时,本文方法在1.5s时滑移率达到平稳,即最佳状态,其他方法的滑移率"
        "在2.5s左右才逐渐平稳,且仍有上下波动的趋势",
        "on asphalt the fuzzy immune PID's slip settles by 1.5 s, while the others need about "
        "2.5 s and still fluctuate",
        "section 4.2, Fig. 4",
        "fuzzy immune PID against our stand-ins; slip settling time; asphalt (mu 0.8)",
        SETTLE_RULE + "the others' 2.5 s describes the paper's comparators, not ours: not "
        "judged. " + STAND_INS,
    ),
    Claim(
        KEY,
        "asphalt-shortest",
        "模糊免疫PID控制算法的制动时间为3s,制动时间最短,制动距离大约为4.8m。由此可知,在高附着路面"
        "上本文方法的响应速度更快,可以确保车辆刹车距离更短",
        "on asphalt the fuzzy immune PID brakes in the shortest time (3 s) and distance "
        "(about 4.8 m)",
        "section 4.2, Fig. 4",
        "fuzzy immune PID against our stand-ins; braking time and distance; asphalt",
        "lowest time and lowest distance against each stand-in; " + SIGNIFICANCE + ". The "
        "printed 3 s and 4.8 m are judged by the 'physical' claim. " + STAND_INS,
    ),
    Claim(
        KEY,
        "dirt-settle",
        "在低附着的泥土路面上,本文方法在1s左右时滑移率达到最佳,之后滑移率没有出现明显波动,其他两种"
        "控制方法滑移率波动较大,2.5s左右才趋于平稳",
        "on dirt the fuzzy immune PID's slip settles by about 1 s without obvious fluctuation; "
        "the other two fluctuate and settle at about 2.5 s",
        "section 4.2, Fig. 5(a)",
        "fuzzy immune PID against our stand-ins; slip settling time; dirt (mu 0.2)",
        SETTLE_RULE + "'about 1 s' read as by 1 s. " + STAND_INS,
    ),
    Claim(
        KEY,
        "dirt-shortest",
        "图5(b)显示,本文方法的制动距离依然最短,刹车所需时间最短",
        "on dirt the fuzzy immune PID's braking distance and time are still the shortest",
        "section 4.2, Fig. 5(b)",
        "fuzzy immune PID against our stand-ins; braking time and distance; dirt",
        "lowest time and lowest distance against each stand-in; " + SIGNIFICANCE + ". " + STAND_INS,
    ),
    Claim(
        KEY,
        "no-lock",
        "避免制动器抱死现象发生",
        "the fuzzy immune PID avoids wheel lock",
        "section 4.2 (on Fig. 5); conclusion",
        "every tuned fuzzy immune PID run; time locked; asphalt and dirt",
        "holds when no run spends any time locked (metric locked_time_s = 0) on either road",
    ),
    Claim(
        KEY,
        "physical",
        "模糊免疫PID控制算法的制动时间为3s,制动时间最短,制动距离大约为4.8m",
        "the published braking time (3 s) and distance (about 4.8 m) on asphalt are physically "
        "possible",
        "section 4.2, Fig. 4",
        "the printed time and distance against the adhesion bound of 30 m/s on mu 0.8",
        "distance >= (v0^2 - v_stop^2)/(2 mu_peak g), time >= (v0 - v_stop)/(mu_peak g); read "
        "as the time to rest a shorter time is impossible; read as the wheel's time to 0 it "
        "is a wheel lock, against the paper's own no-lock claim",
    ),
)

SETTING = [
    (
        "plant",
        "abs-wheel, preset paper-fuzzy-immune: v0 30 m/s, R 0.28 m, J 25 kg m^2 (about "
        "twenty times a car wheel's: kept, as printed), brake 25 N m/kPa with q_max 800 kPa "
        "(26 kPa already locks the wheel: the brake is about 30 x oversized), actuator K 100, "
        "T 0.01 s; quarter mass not given: 300 kg, our assumption. Roads: asphalt mu 0.8 -> "
        "bilinear (0.2, 0.8, 0.6), dirt mu 0.2 -> (0.15, 0.2, 0.15), our assumption.",
    ),
    (
        "controller",
        "Fuzzy immune PID (eqs. 6-11): kp1 = k_immune (1 - eta f) with f from the "
        "5x5 immune rule table, incremental PID at 1 ms; eq. 10 printed 'ki e(t) + kd e(t)' read "
        "as the incremental integral and derivative terms; eq. 11 (an area) read as the centroid.",
    ),
    (
        "comparison",
        "The paper's two comparison methods are described too vaguely to rebuild "
        "(no gains, rules or thresholds); we compare against our PID, fuzzy PID (each tuned by the "
        "same optimizer, budget and objective as the fuzzy immune PID) and the rule-based "
        "threshold ABS.",
    ),
    ("settling", "Settled: the slip stays within 0.05 of its target above 2 m/s."),
    (
        "defects",
        "The printed stopping distance, 4.8 m from 30 m/s on asphalt, needs a mean "
        "deceleration of 93.75 m/s^2, about 9.6 g (v0^2 / (2 d)); the adhesion bound is 57.3 m. "
        "The printed 3 s needs 10 m/s^2, about 1.02 g, above the 0.8 g the road allows: the "
        "time bound is 3.8 s.",
    ),
]


def studies() -> tuple[str, ...]:
    """The shipped study configs this paper runs."""
    return (STUDY,)


def build(ctx: common.Context) -> common.PaperSection:
    """The section of fuzzy-immune-abs."""
    from chassistune.plots.abs_wheel import plot_comparison

    data = ctx.studies[STUDY]
    sec = common.PaperSection(KEY, published.paper(KEY).citation, [*SETTING, common.ORACLE_SETTING])
    sec.tables += common.budget_tables(ctx, (STUDY,))
    verdicts, checks, locked = [], [], []
    for road, fig in ROADS:
        settle_pub = published.lookup(KEY, "slip_settles_at_s", road).as_printed()
        traces: dict[str, tuple[AbsWheelScenario, Trace]] = {
            "threshold ABS": abs_trace(PRESET, road, "threshold", None, {})
        }
        values: dict[str, dict[str, np.ndarray]] = {
            m: {"threshold ABS": np.array([traces["threshold ABS"][1].metrics[m]])} for m in METRICS
        }
        settles = {"threshold ABS": np.array([common.settle_time_s(traces["threshold ABS"][1])])}
        rows = []
        for label, ctrl in TUNED:
            runs = data.runs(f"{ctrl}/{road}", "DERLSP-AO")
            for m in METRICS:
                values[m][label] = np.array([r.metrics[road][m] for r in runs])
            if label == CLAIMED:
                locked += [(road, float(r.metrics[road]["locked_time_s"])) for r in runs]
            settles[label] = np.array(
                [
                    common.settle_time_s(abs_trace(PRESET, road, ctrl, run_gains(r), {})[1])
                    for r in runs
                ]
            )
            traces[label] = abs_trace(PRESET, road, ctrl, run_gains(common.median_run(runs)), {})
            default = abs_trace(PRESET, road, ctrl, None, {})[1]
            rows.append(_row(f"{label} (defaults)", default, settle_pub))
        for label, (_, tr) in traces.items():
            rows.append(
                _row(label + ("" if label == "threshold ABS" else " (tuned)"), tr, settle_pub)
            )
        sc = traces[CLAIMED][0]
        bound, time_bound = sc.bound_distance_m, sc.bound_time_s
        for r in rows:
            r["bound (m)"] = bound
            r["ours / bound"] = float(r["ours distance (m)"]) / bound  # type: ignore[arg-type]
            r["time bound (s)"] = time_bound
            r["ours time / time bound"] = float(r["ours stop time (s)"]) / time_bound  # type: ignore[arg-type]
        if road == "asphalt-0.8":
            d_pub = published.lookup(KEY, "stop_distance_m", road).as_printed()[CLAIMED]
            t_pub = published.lookup(KEY, "stop_time_s", road).as_printed()[CLAIMED]
            for r in rows:
                if r["controller"] == f"{CLAIMED} (tuned)":
                    r["paper distance (m)"], r["paper stop time (s)"] = d_pub, t_pub
                    r["paper / bound"] = float(d_pub) / bound
                    r["paper time / time bound"] = float(t_pub) / time_bound
            checks += [
                common.BoundCheck(
                    KEY, road, CLAIMED, "braking distance", "m", float(d_pub), d_pub, bound
                ),
                common.BoundCheck(
                    KEY,
                    road,
                    CLAIMED,
                    "braking time",
                    "s",
                    float(t_pub),
                    t_pub,
                    time_bound,
                    reading=f"{common.TIME_AS_REST}; or {common.TIME_AS_WHEEL_STOP}",
                ),
            ]
        sec.tables.append(
            common.Table(
                f"{fig.replace('. ', '')}_{road}",
                f"{fig} ({road}): settling, stop time and distance, paper beside ours",
                pd.DataFrame(rows),
                "Tuned rows: the median run of the tuning seeds; the paper reads its settling "
                f"times off its figures (section 4.2, {fig}). The paper's 'others' are the "
                "methods of its refs. [1] and [2]; ours beside them are stand-ins. Bound: "
                "(v0^2 - v_stop^2)/(2 mu_peak g); time bound: (v0 - v_stop)/(mu_peak g). The "
                "paper's 3 s is below it whether read as the time to rest (impossible) or as the "
                "wheel's time to 0 (a lock, against its own no-lock claim).",
                quoted=("paper settle (s)", "paper stop time (s)", "paper distance (m)"),
                missing={
                    "ours settle (s)": common.NEVER_SETTLES,
                    "paper / bound": NOT_PRINTED,
                    "paper time / time bound": NOT_PRINTED,
                },
            )
        )
        path = ctx.figure(KEY, f"{fig.replace('. ', '').lower()}_{road}")
        plot_comparison(
            sc,
            [(k, t) for k, (_, t) in traces.items()],
            str(path),
            title=f"{fig} redrawn: {road}",
        )
        sec.figures.append(
            common.Figure(
                path.stem,
                f"{fig} redrawn ({road})",
                path,
                "Threshold ABS: untuned; PID, fuzzy PID and fuzzy immune PID: tuned alike by "
                "DERLSP-AO, each its median run (the defaults' numbers are in the table above).",
            )
        )
        surface = road.split("-")[0]
        word, ev = common.settle_verdict(
            settles, CLAIMED, float(settle_pub[CLAIMED]), fixed=("threshold ABS",)
        )
        verdicts.append(
            common.Verdict(
                claims.declared(CLAIMS, f"{surface}-settle"),
                word,
                f"{ev} (paper: others about {settle_pub['others']} s; ours are stand-ins)",
            )
        )
        parts = []
        for m, what in METRICS.items():
            word, ev = common.order_verdict(values[m], CLAIMED, fixed=("threshold ABS",))
            parts.append((word, f"{what}: {ev}"))
        verdicts.append(common.judged(claims.declared(CLAIMS, f"{surface}-shortest"), parts))
    verdicts.append(_no_lock(locked))
    verdicts.append(common.bound_verdict(claims.declared(CLAIMS, "physical"), checks))
    sec.verdicts += verdicts
    sec.bounds = checks
    return sec


def _no_lock(locked: list[tuple[str, float]]) -> common.Verdict:
    worst = max(t for _, t in locked)
    n = sum(t > 0.0 for _, t in locked)
    return common.Verdict(
        claims.declared(CLAIMS, "no-lock"),
        common.HOLDS if n == 0 else common.FAILS,
        f"{n} of {len(locked)} tuned fuzzy immune PID runs lock the wheel (longest locked "
        f"{worst:.3g} s)",
    )


def _row(label: str, tr: Trace, settle_pub: dict[str, str]) -> dict[str, object]:
    m = tr.metrics
    paper_settle = settle_pub[CLAIMED] if label.startswith(CLAIMED) else settle_pub["others"]
    return {
        "controller": label,
        "paper settle (s)": paper_settle,
        "ours settle (s)": common.settle_time_s(tr),
        "ours stop time (s)": m["stop_time_s"],
        "ours distance (m)": m["stop_distance_m"],
        "paper stop time (s)": None,
        "paper distance (m)": None,
        "paper / bound": None,
        "paper time / time bound": None,
    }
