"""The report page: a jinja2 template rendered into one self-contained HTML file.

Figures are embedded as base64 PNG data URIs and the style sheet is inline, so the page needs no
other file; the CSV tables and PNG figures beside it are linked for convenience. Every table and
figure is listed in the contents at the top, and each listed item is on the page.
"""

from __future__ import annotations

import base64
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import jinja2
import pandas as pd


def format_cell(x: Any) -> str:
    """A short rendering of a table value (4 significant digits, blank for missing)."""
    if x is None or (isinstance(x, float) and math.isnan(x)) or x is pd.NA:
        return ""
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, float):
        return f"{x:.4g}"
    return str(x)


@dataclass(frozen=True)
class TableView:
    """A table on the page; `source` names the CSV file it shows (or a part of)."""

    id: str
    title: str
    columns: list[str]
    rows: list[list[str]]
    caption: str = ""
    source: str = ""
    numeric: list[bool] = field(default_factory=list)
    kind: str = "table"

    @classmethod
    def from_frame(cls, df: pd.DataFrame, id: str, title: str, caption: str = "",
                   source: str = "") -> TableView:
        rows = [[format_cell(v) for v in rec] for rec in df.astype(object).itertuples(index=False)]
        numeric = [pd.api.types.is_numeric_dtype(df[c]) and not pd.api.types.is_bool_dtype(df[c])
                   for c in df.columns]
        return cls(id, title, [str(c) for c in df.columns], rows, caption, source, numeric)


@dataclass(frozen=True)
class FigureView:
    """A figure on the page, embedded from its PNG file."""

    id: str
    title: str
    png_base64: str
    caption: str = ""
    source: str = ""
    kind: str = "figure"

    @classmethod
    def from_png(cls, path: Path, id: str, title: str, caption: str = "",
                 source: str = "") -> FigureView:
        data = base64.b64encode(path.read_bytes()).decode("ascii")
        return cls(id, title, data, caption, source)


@dataclass
class Section:
    """A titled group of tables and figures."""

    title: str
    intro: str = ""
    items: list[TableView | FigureView] = field(default_factory=list)


TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="chassistune {{ version }}">
<title>Study {{ name }}: chassistune report</title>
<style>
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto;
       max-width: 1100px; padding: 0 1em; color: #222; line-height: 1.4; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 2em; }
h3 { font-size: 1.05em; margin-bottom: 0.3em; }
.meta { color: #555; }
nav ol { columns: 2; font-size: 0.9em; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 0.85em; }
caption { caption-side: bottom; text-align: left; color: #555; padding-top: 0.3em; }
th, td { border: 1px solid #ddd; padding: 0.25em 0.6em; text-align: left; }
th { background: #f2f2f2; }
.num { text-align: right; font-variant-numeric: tabular-nums; }
tbody tr:nth-child(even) { background: #fafafa; }
figure { margin: 0.5em 0 2em; }
figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { color: #555; font-size: 0.9em; }
.source { font-size: 0.8em; color: #777; }
</style>
</head>
<body>
<h1>Study {{ name }}</h1>
<p class="meta">{{ summary }}</p>
{% if description %}<p>{{ description }}</p>{% endif %}
<nav id="contents">
<h2>Contents</h2>
<ol>
{% for section in sections %}{% for item in section.items %}
<li><a href="#{{ item.id }}" data-kind="{{ item.kind }}">{{ labels[item.id] }}:
{{ item.title }}</a></li>
{% endfor %}{% endfor %}
</ol>
</nav>
{% for section in sections %}
<section>
<h2>{{ section.title }}</h2>
{% if section.intro %}<p>{{ section.intro }}</p>{% endif %}
{% for item in section.items %}
{% if item.kind == "table" %}
<h3>{{ labels[item.id] }}: {{ item.title }}</h3>
<table id="{{ item.id }}">
{% if item.caption %}<caption>{{ item.caption }}</caption>{% endif %}
<thead><tr>{% for c in item.columns %}<th scope="col"{% if item.numeric[loop.index0] %}
 class="num"{% endif %}>{{ c }}</th>{% endfor %}</tr></thead>
<tbody>
{% for row in item.rows %}<tr>{% for v in row %}<td{% if item.numeric[loop.index0] %} class="num"
{% endif %}>{{ v }}</td>{% endfor %}</tr>
{% endfor %}</tbody>
</table>
{% if item.source %}<p class="source">data: <a href="{{ item.source }}">{{ item.source }}</a></p>
{% endif %}
{% else %}
<figure id="{{ item.id }}">
<h3>{{ labels[item.id] }}: {{ item.title }}</h3>
<img alt="{{ item.title }}" src="data:image/png;base64,{{ item.png_base64 }}">
<figcaption>{{ item.caption }}{% if item.source %} <span class="source">(<a
href="{{ item.source }}">{{ item.source }}</a>)</span>{% endif %}</figcaption>
</figure>
{% endif %}
{% endfor %}
</section>
{% endfor %}
</body>
</html>
"""


def render(name: str, summary: str, description: str, sections: list[Section],
           version: str) -> str:
    """The page's HTML text (autoescaped); tables and figures numbered in page order."""
    labels: dict[str, str] = {}
    counts = {"table": 0, "figure": 0}
    for section in sections:
        for item in section.items:
            counts[item.kind] += 1
            labels[item.id] = f"{item.kind.capitalize()} {counts[item.kind]}"
    env = jinja2.Environment(autoescape=True, undefined=jinja2.StrictUndefined,
                             trim_blocks=True, lstrip_blocks=True)
    return env.from_string(TEMPLATE).render(name=name, summary=summary, description=description,
                                            sections=sections, version=version, labels=labels)
