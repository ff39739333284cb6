"""`study report DIR --interactive`: DIR/report_interactive.html, one self-contained page with
the report's tables (sortable) and plotly figures (zoom, hover, legend clicks): convergence
medians with interquartile bands on a log axis, box and strip plots of the final costs, and each
optimizer's best time response over the baseline, panels linked on one time axis.

plotly.js is inlined once in the page; the page fetches nothing. plotly is the optional extra
`chassistune[interactive]`.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from chassistune._io import file_set
from chassistune.errors import InputError
from chassistune.reports import sections
from chassistune.reports.bands import convergence_bands, log_scale_suits
from chassistune.reports.build import ReportFiles, read_study
from chassistune.reports.html import Interactive, PlotView, Section, render
from chassistune.reports.responses import ResponseSet
from chassistune.studies.store import RunRecord

INTERACTIVE_NAME = "report_interactive.html"
PALETTE = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#17becf",
    "#bcbd22",
)
BASELINE_COLOR = "#777777"
PLOT_CONFIG = {"displaylogo": False, "responsive": True, "scrollZoom": False}


def require_plotly() -> Any:
    """plotly.graph_objects, or InputError naming the extra that installs it."""
    try:
        import plotly.graph_objects as go
    except ImportError:
        raise InputError(
            "--interactive", "needs plotly: pip install 'chassistune[interactive]'"
        ) from None
    return go


def _rgba(color: str, alpha: float) -> str:
    r, g, b = (int(color[i : i + 2], 16) for i in (1, 3, 5))
    return f"rgba({r},{g},{b},{alpha})"


def _steps(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The corners of a step-after curve (each value held until the next x) as a polyline."""
    return np.repeat(x, 2)[1:], np.repeat(y, 2)[:-1]


def _layout(title: str, height: int, **extra: Any) -> dict[str, Any]:
    return {
        "title": {"text": title, "font": {"size": 14}},
        "height": height,
        "template": "plotly_white",
        "margin": {"l": 70, "r": 20, "t": 60, "b": 50},
        "hovermode": "x unified" if extra.pop("unified", False) else "closest",
        "legend": {"orientation": "h", "y": -0.18},
        **extra,
    }


class Ids(Protocol):
    """Hands out the page's item ids (`sections.Assets` does)."""

    def next_id(self, kind: str) -> str: ...


class PlotlyFigures:
    """The interactive `sections.Figures`: plotly figures kept as JSON for the page."""

    def __init__(self, ids: Ids) -> None:
        self.ids = ids
        self.go = require_plotly()

    def _view(self, fig: Any, title: str, caption: str) -> PlotView:
        compact = json.dumps(json.loads(fig.to_json()), separators=(",", ":"))
        return PlotView(self.ids.next_id("plot"), title, compact, len(fig.data), caption)

    def convergence(
        self, scenario: str, runs: Mapping[str, Sequence[RunRecord]], name: str
    ) -> PlotView:
        go = self.go
        fig = go.Figure()
        drawn = []
        for k, (label, (n, band)) in enumerate(convergence_bands(runs).items()):
            color = PALETTE[k % len(PALETTE)]
            x = band["nfev"]
            xs, hi = _steps(x, band["q75"])
            _, lo = _steps(x, band["q25"])
            fig.add_trace(
                go.Scatter(
                    x=np.concatenate([xs, xs[::-1]]),
                    y=np.concatenate([hi, lo[::-1]]),
                    mode="lines",
                    fill="toself",
                    fillcolor=_rgba(color, 0.18),
                    line={"width": 0},
                    hoverinfo="skip",
                    legendgroup=label,
                    showlegend=False,
                    name=f"{label} interquartile band",
                )
            )
            fig.add_trace(
                go.Scatter(
                    x=x,
                    y=band["median"],
                    mode="lines",
                    line={"color": color, "shape": "hv"},
                    legendgroup=label,
                    name=f"{label} (median of {n})",
                )
            )
            drawn += [band["q25"], band["q75"]]
        fig.update_layout(**_layout(f"Convergence, {scenario}", 420))
        fig.update_xaxes(title_text="evaluations")
        fig.update_yaxes(
            title_text="best cost so far", type="log" if log_scale_suits(drawn) else "linear"
        )
        return self._view(
            fig,
            f"Convergence, {scenario}",
            "Best cost so far against evaluations: median over seeds (line) and "
            "interquartile band (shaded). Click a legend entry to hide an "
            "optimizer; drag to zoom, double-click to reset.",
        )

    def final_costs(self, scenario: str, costs: Mapping[str, np.ndarray], name: str) -> PlotView:
        go = self.go
        fig = go.Figure()
        for k, (label, v) in enumerate(costs.items()):
            fig.add_trace(
                go.Box(
                    y=np.asarray(v, dtype=float),
                    name=label,
                    boxpoints="all",
                    jitter=0.35,
                    pointpos=0,
                    marker={"color": PALETTE[k % len(PALETTE)], "size": 6, "opacity": 0.7},
                    hovertemplate=f"{label}<br>final cost %{{y:.6g}}<extra></extra>",
                )
            )
        fig.update_layout(**_layout(f"Final cost, {scenario}", 400, showlegend=False))
        fig.update_yaxes(
            title_text="final best cost",
            type="log" if log_scale_suits(list(costs.values())) else "linear",
        )
        return self._view(
            fig,
            f"Final cost distribution, {scenario}",
            "Box and strip plot of the final best cost per optimizer: every point "
            "is a run (hover for its value).",
        )

    def responses(self, rs: ResponseSet, name: str) -> PlotView:
        from plotly.subplots import make_subplots

        go = self.go
        fig = make_subplots(rows=len(rs.panels), cols=1, shared_xaxes=True, vertical_spacing=0.035)
        k = 0
        for curve in rs.curves:
            if curve.baseline:
                line = {"color": BASELINE_COLOR, "dash": "dash", "width": 1.5}
            else:
                line = {"color": PALETTE[k % len(PALETTE)], "width": 1.5}
                k += 1
            for row, panel in enumerate(rs.panels, start=1):
                fig.add_trace(
                    go.Scatter(  # float32: half the page, ample for a plot
                        x=curve.time_s.astype(np.float32),
                        y=curve.values[panel.signal].astype(np.float32),
                        mode="lines",
                        line=line,
                        name=curve.label,
                        legendgroup=curve.label,
                        showlegend=row == 1,
                    ),
                    row=row,
                    col=1,
                )
        for row, panel in enumerate(rs.panels, start=1):
            fig.update_yaxes(title_text=panel.label, row=row, col=1)
        fig.update_xaxes(title_text="time [s]", row=len(rs.panels), col=1)
        base = next((c.label for c in rs.curves if c.baseline), "")
        fig.update_layout(
            **_layout(
                f"{rs.scenario} on {rs.road}: best runs against {base}",
                190 * len(rs.panels) + 140,
                unified=True,
            )
        )
        fig.update_layout(legend={"orientation": "h", "y": 1.0, "yanchor": "bottom", "x": 0.0})
        return self._view(
            fig,
            f"Best controllers against {base}, {rs.scenario}, on {rs.road}",
            f"Each optimizer's lowest-cost gains (label: the seed that found them) "
            f"re-simulated on {rs.road}, all on the road realization of seed "
            f"{rs.seed}, over the {base} baseline (grey, dashed). The panels share "
            "the time axis: zoom one and all follow.",
        )


SORT_SCRIPT = """
document.querySelectorAll("table.sortable").forEach(function (table) {
  var heads = table.tHead.rows[table.tHead.rows.length - 1].cells;
  Array.prototype.forEach.call(heads, function (th, col) {
    th.title = "click to sort";
    th.addEventListener("click", function () {
      var up = th.getAttribute("aria-sort") !== "ascending";
      Array.prototype.forEach.call(heads, function (h) { h.removeAttribute("aria-sort"); });
      th.setAttribute("aria-sort", up ? "ascending" : "descending");
      var body = table.tBodies[0];
      var rows = Array.prototype.slice.call(body.rows);
      var key = function (r) { return r.cells[col].textContent.trim(); };
      var numeric = rows.every(function (r) {
        return key(r) === "" || !isNaN(parseFloat(key(r)));
      });
      rows.sort(function (a, b) {
        var x = key(a), y = key(b), d;
        if (numeric) {
          if (x === "" || y === "") { d = (x === "") - (y === ""); return d; }
          d = parseFloat(x) - parseFloat(y);
        } else { d = x.localeCompare(y); }
        return up ? d : -d;
      });
      rows.forEach(function (r) { body.appendChild(r); });
    });
  });
});
"""

PLOT_SCRIPT = """
var FIGURES = JSON.parse(document.getElementById("figure-data").textContent);
Object.keys(FIGURES).forEach(function (id) {
  var f = FIGURES[id];
  Plotly.newPlot(id, f.data, f.layout, PLOT_CONFIG);
});
"""

STYLE = """
th[title] { cursor: pointer; }
th[aria-sort=ascending]::after { content: " \\25B2"; }
th[aria-sort=descending]::after { content: " \\25BC"; }
.plot { width: 100%; border: 1px solid #eee; margin: 0.3em 0; }
"""


def _safe(text: str) -> str:
    """JSON text safe inside a <script> element: no '</' can close it ('<\\/' is valid JSON)."""
    return text.replace("</", "<\\/")


def interactive_page(
    name: str, summary: str, description: str, page_sections: list[Section], kind: str = "Study"
) -> str:
    """The interactive page's HTML: `render` with plotly.js inlined once, every PlotView's
    figure JSON in one data element, and the scripts drawing them and sorting the tables."""
    from importlib.metadata import version

    require_plotly()
    from plotly.offline import get_plotlyjs

    plots = [item for s in page_sections for item in s.items if isinstance(item, PlotView)]
    figures = "{" + ",".join(f"{json.dumps(p.id)}:{_safe(p.figure_json)}" for p in plots) + "}"
    script = f"var PLOT_CONFIG = {json.dumps(PLOT_CONFIG)};\n{PLOT_SCRIPT}\n{SORT_SCRIPT}"
    return render(
        name,
        summary,
        description,
        page_sections,
        version("chassistune"),
        Interactive(get_plotlyjs().replace("</script", "<\\/script"), figures, script, STYLE),
        kind,
    )


def build_interactive(study_dir: str | Path, reference: str | None = None) -> ReportFiles:
    """Write DIR/report_interactive.html (and refresh the CSV tables beside it)."""
    require_plotly()
    study = read_study(study_dir, reference)
    html = study.root / INTERACTIVE_NAME
    with file_set() as staged:
        assets = sections.Assets(study.root, staged)
        page = interactive_page(
            study.data.name,
            study.summary,
            study.description,
            study.sections(assets, PlotlyFigures(assets)),
        )
        staged.write_text(html, page)
    return ReportFiles(html, study.root / sections.ASSETS, assets.tables, [])
