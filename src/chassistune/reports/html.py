"""The report page: a jinja2 template rendered into one self-contained HTML file.

Figures are embedded as base64 PNG data URIs, the style sheet is inline and every table's data is
embedded as a CSV download (a data URI), so the page alone, emailed, carries its figures and its
tables; the same CSV and PNG files are also written beside it. Every table and figure is listed
in the contents at the top, and each listed item is on the page.
"""

from __future__ import annotations

import base64
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import jinja2
import pandas as pd

from chassistune.reports.versus import BETTER, REFERENCE, SAME, WORSE

FLAG = "⚑"
"""Marks a tuned gain within 1 % of its bound (see reports.gains)."""

_CELL_CLASSES = (
    (BETTER[0], "better"),
    (WORSE[0], "worse"),
    (SAME[0], "same"),
    (REFERENCE, "ref"),
    (FLAG, "flag"),
)
"""A cell holding one of these marks (a verdict symbol, 'reference', the bound flag) is styled
by the class."""


def format_cell(x: Any) -> str:
    """A short rendering of a table value (4 significant digits, blank for missing)."""
    if x is None or (isinstance(x, float) and math.isnan(x)) or x is pd.NA:
        return ""
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, float):
        return f"{x:.4g}"
    return str(x)


def cell_class(text: str) -> str:
    """The CSS class of a cell holding a verdict or a bound flag ('' otherwise)."""
    return next((cls for mark, cls in _CELL_CLASSES if mark in text), "")


def td_class(numeric: bool, text: str) -> str:
    """A cell's classes: 'num' for a numeric column, then its verdict or flag class."""
    return " ".join(c for c in ("num" if numeric else "", cell_class(text)) if c)


@dataclass(frozen=True)
class Download:
    """A CSV file embedded in the page (data URI) under its file name; `folder`: where the file
    itself is, relative to the page."""

    name: str
    uri: str
    folder: str = ""

    @classmethod
    def from_csv(cls, path: Path, page_dir: Path, data: Path | None = None) -> Download:
        """The CSV file `path`, its folder named relative to `page_dir` (the page's folder), with
        the bytes of `data` (default: `path`; a staged copy while `path` is not yet in place)."""
        encoded = base64.b64encode((data or path).read_bytes()).decode("ascii")
        folder = path.parent.resolve().relative_to(page_dir.resolve()).as_posix()
        return cls(path.name, f"data:text/csv;charset=utf-8;base64,{encoded}", f"{folder}/")


@dataclass(frozen=True)
class _View:
    """An item on the page: its anchor id and its title (what every kind of item has first)."""

    id: str
    title: str


@dataclass(frozen=True)
class TableView(_View):
    """A table on the page; `sources` are the CSVs it shows (or a part of), `groups` an
    optional header row above the columns as (title, span) pairs."""

    columns: list[str]
    rows: list[list[str]]
    caption: str = ""
    sources: tuple[Download, ...] = ()
    numeric: list[bool] = field(default_factory=list)
    groups: list[tuple[str, int]] = field(default_factory=list)
    kind: str = "table"

    @classmethod
    def from_frame(
        cls,
        df: pd.DataFrame,
        id: str,
        title: str,
        caption: str = "",
        sources: tuple[Download, ...] = (),
    ) -> TableView:
        """Two-level columns (a MultiIndex) give the header groups."""
        rows = [[format_cell(v) for v in rec] for rec in df.astype(object).itertuples(index=False)]
        numeric = [
            pd.api.types.is_numeric_dtype(df.iloc[:, i])
            and not pd.api.types.is_bool_dtype(df.iloc[:, i])
            for i in range(df.shape[1])
        ]
        groups: list[tuple[str, int]] = []
        columns = [str(c) for c in df.columns]
        if isinstance(df.columns, pd.MultiIndex):
            columns = [str(c[1]) for c in df.columns]
            for top in df.columns.get_level_values(0):
                if groups and groups[-1][0] == top:
                    groups[-1] = (top, groups[-1][1] + 1)
                else:
                    groups.append((str(top), 1))
        return cls(id, title, columns, rows, caption, sources, numeric, groups)


@dataclass(frozen=True)
class FigureView(_View):
    """A figure on the page, embedded from its PNG file (`file` names the copy beside it)."""

    png_base64: str
    caption: str = ""
    file: str = ""
    kind: str = "figure"

    @classmethod
    def from_png(
        cls, path: Path, id: str, title: str, caption: str = "", file: str = ""
    ) -> FigureView:
        data = base64.b64encode(path.read_bytes()).decode("ascii")
        return cls(id, title, data, caption, file)


@dataclass(frozen=True)
class CodeView(_View):
    """Preformatted text on the page (the study config)."""

    text: str
    caption: str = ""
    kind: str = "code"


@dataclass(frozen=True)
class PlotView(_View):
    """A plotly figure on the interactive page: its JSON (data, layout) and trace count."""

    figure_json: str
    traces: int
    caption: str = ""
    kind: str = "plot"


Item = TableView | FigureView | CodeView | PlotView


@dataclass
class Section:
    """A titled group of tables and figures."""

    title: str
    intro: str = ""
    items: list[Item] = field(default_factory=list)
    id: str = ""


STYLE = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto;
       max-width: 1150px; padding: 0 1em; color: #222; line-height: 1.4; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 2em; }
h3 { font-size: 1.05em; margin-bottom: 0.3em; }
.meta { color: #555; }
nav ol { font-size: 0.9em; padding-left: 1.5em; }
nav li { margin: 0.15em 0; }
nav .items { color: #555; font-size: 0.95em; }
.wrap { overflow-x: auto; }
table { border-collapse: collapse; margin: 0.5em 0 0.3em; font-size: 0.85em; }
caption { caption-side: bottom; text-align: left; color: #555; padding-top: 0.3em;
          max-width: 60em; }
th, td { border: 1px solid #ddd; padding: 0.25em 0.6em; text-align: left; }
th { background: #f2f2f2; overflow-wrap: anywhere; }
th.group { text-align: center; background: #e8eef5; }
.num { text-align: right; font-variant-numeric: tabular-nums; }
tbody tr:nth-child(even) { background: #fafafa; }
td.better { background: #e3f4e1; color: #1d6b22; font-weight: 600; }
td.worse { background: #fbe4e1; color: #9b2318; font-weight: 600; }
td.same { color: #555; }
td.ref { color: #555; font-style: italic; }
td.flag { background: #fff1d6; color: #8a5300; }
figure { margin: 0.5em 0 2em; }
figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { color: #555; font-size: 0.9em; max-width: 60em; }
pre { background: #f6f8fa; border: 1px solid #e1e4e8; padding: 0.8em; font-size: 0.8em;
      overflow-x: auto; }
.source { font-size: 0.8em; color: #777; margin: 0 0 1.5em; }
.legend-key span { padding: 0 0.4em; margin-right: 0.6em; }
"""

TABLE_MACRO = """
{% macro table(item, sortable=False) %}
<h3>{{ labels[item.id] }}: {{ item.title }}</h3>
<div class="wrap">
<table id="{{ item.id }}"{% if sortable %} class="sortable"{% endif %}>
{% if item.caption %}<caption>{{ item.caption }}</caption>{% endif %}
<thead>
{% if item.groups %}<tr>{% for g, span in item.groups %}<th colspan="{{ span }}"
{% if g %} class="group"{% endif %}>{{ g }}</th>{% endfor %}</tr>{% endif %}
<tr>{% for c in item.columns %}<th scope="col"{% if item.numeric[loop.index0] %}
 class="num"{% endif %}>{{ c }}</th>{% endfor %}</tr></thead>
<tbody>
{% for row in item.rows %}<tr>{% for v in row %}{% set cls = td_class(
item.numeric[loop.index0], v) %}<td{% if cls %} class="{{ cls }}"{% endif %}>{{ v }}</td>
{% endfor %}</tr>
{% endfor %}</tbody>
</table>
</div>
{% if item.sources %}<p class="source">data: {% for s in item.sources %}<a
download="{{ s.name }}" href="{{ s.uri }}">{{ s.name }}</a>{{ ", " if not loop.last }}
{% endfor %} (embedded in this page; also in {{ item.sources | map(attribute="folder") | unique
| join(", ") }} beside it)</p>{% endif %}
{% endmacro %}
{% macro code(item) %}
<h3>{{ labels[item.id] }}: {{ item.title }}</h3>
<pre id="{{ item.id }}">{{ item.text }}</pre>
{% if item.caption %}<p class="source">{{ item.caption }}</p>{% endif %}
{% endmacro %}
{% macro contents(sections) %}
<nav id="contents">
<h2>Contents</h2>
<ol>
{% for section in sections %}
<li><a href="#{{ section.id }}">{{ section.title }}</a><br><span class="items">
{% for item in section.items %}<a href="#{{ item.id }}" data-kind="{{ item.kind }}"
title="{{ item.title }}">{{ labels[item.id] }}</a>{{ ", " if not loop.last }}{% endfor %}
</span></li>
{% endfor %}
</ol>
</nav>
{% endmacro %}
"""

TEMPLATE = (
    TABLE_MACRO
    + """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="chassistune {{ version }}">
<title>{{ kind }} {{ name }}: chassistune {{ "interactive " if interactive else "" }}report</title>
<style>{{ style | safe }}{{ extra_style | safe }}</style>
{% if interactive %}<script>{{ interactive.plotly_js | safe }}</script>{% endif %}
</head>
<body>
<h1>{{ kind }} {{ name }}</h1>
<p class="meta">{{ summary }}{% if interactive %} Interactive version: sort a table by clicking
its header; zoom, hover and hide curves in the figures.{% endif %}</p>
{% if description %}<p>{{ description }}</p>{% endif %}
{{ contents(sections) }}
{% for section in sections %}
<section id="{{ section.id }}">
<h2>{{ section.title }}</h2>
{% if section.intro %}<p>{{ section.intro }}</p>{% endif %}
{% for item in section.items %}
{% if item.kind == "table" %}{{ table(item, sortable=interactive is not none) }}
{% elif item.kind == "code" %}{{ code(item) }}
{% elif item.kind == "plot" %}
<figure>
<h3>{{ labels[item.id] }}: {{ item.title }}</h3>
<div id="{{ item.id }}" class="plot" data-traces="{{ item.traces }}"></div>
<figcaption>{{ item.caption }}</figcaption>
</figure>
{% else %}
<figure id="{{ item.id }}">
<h3>{{ labels[item.id] }}: {{ item.title }}</h3>
<img alt="{{ item.title }}" src="data:image/png;base64,{{ item.png_base64 }}">
<figcaption>{{ item.caption }}{% if item.file %} <span class="source">({{ item.file }})</span>
{% endif %}</figcaption>
</figure>
{% endif %}
{% endfor %}
</section>
{% endfor %}
{% if interactive %}
<script type="application/json" id="figure-data">{{ interactive.figures | safe }}</script>
<script>{{ interactive.script | safe }}</script>
{% endif %}
</body>
</html>
"""
)


@dataclass(frozen=True)
class Interactive:
    """What makes the page interactive: plotly.js, the figures' JSON (an object by plot id,
    safe inside <script>), the script drawing them and sorting tables, extra style."""

    plotly_js: str
    figures: str
    script: str
    style: str


def number(sections: list[Section]) -> dict[str, str]:
    """'Table 3', 'Figure 2', 'Listing 1' by item id, in page order; gives sections ids."""
    labels: dict[str, str] = {}
    names = {"table": "Table", "figure": "Figure", "plot": "Figure", "code": "Listing"}
    counts = dict.fromkeys(names.values(), 0)
    for i, section in enumerate(sections, start=1):
        section.id = section.id or f"section-{i}"
        for item in section.items:
            name = names[item.kind]
            counts[name] += 1
            labels[item.id] = f"{name} {counts[name]}"
    return labels


def environment() -> jinja2.Environment:
    env = jinja2.Environment(
        autoescape=True, undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True
    )
    env.globals.update(td_class=td_class, style=STYLE)
    return env


def render(
    name: str,
    summary: str,
    description: str,
    sections: list[Section],
    version: str,
    interactive: Interactive | None = None,
    kind: str = "Study",
) -> str:
    """The page's HTML text (autoescaped); tables and figures numbered in page order. The
    heading and title read '{kind} {name}'."""
    return (
        environment()
        .from_string(TEMPLATE)
        .render(
            kind=kind,
            name=name,
            summary=summary,
            description=description,
            sections=sections,
            version=version,
            labels=number(sections),
            interactive=interactive,
            extra_style=interactive.style if interactive else "",
        )
    )
