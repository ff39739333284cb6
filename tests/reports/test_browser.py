"""Both report pages in a real browser (Debian's chromium driven by pytest-playwright): they load
with every request outside file: aborted and none attempted, raise no page error, draw what they
should, and a full-page screenshot of each is a page, not a blank."""

from __future__ import annotations

from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import numpy as np
import pytest

WIDTH = 1280


class Offline:
    """Routes every request of a page: file: goes through, anything else is aborted and kept."""

    def __init__(self, page: Any) -> None:
        self.outside: list[str] = []
        self.errors: list[str] = []
        page.route("**/*", self._route)
        page.on("pageerror", lambda exc: self.errors.append(str(exc)))
        page.on(
            "console", lambda msg: self.errors.append(msg.text) if msg.type == "error" else None
        )

    def _route(self, route: Any) -> None:
        if route.request.url.startswith("file:"):
            route.continue_()
        else:
            self.outside.append(route.request.url)
            route.abort()


def _open(page: Any, html: Path) -> Offline:
    page.set_viewport_size({"width": WIDTH, "height": 900})
    net = Offline(page)
    page.goto(html.as_uri(), wait_until="load")
    return net


def _check_screenshot(pixels: np.ndarray, page: Any) -> None:
    height = page.evaluate("document.documentElement.scrollHeight")
    assert pixels.shape == (height, WIDTH)
    assert height > 4000  # every section, not a stub
    ink = pixels < 200
    assert pixels.std() > 10 and 0.02 < ink.mean() < 0.6  # text, tables and plots; not blank
    top = ink[:300]
    assert top.any(axis=1).sum() > 20  # the title and summary are drawn at the top


def test_static_report_in_chromium(page, reported, screenshot) -> None:
    net = _open(page, reported.static)
    assert net.outside == [] and net.errors == []
    images = page.evaluate("Array.from(document.images).map(i => [i.complete, i.naturalWidth])")
    figures = len(list((reported.dir / "report" / "figures").glob("*.png")))
    assert len(images) == figures > 0
    assert all(done and width > 300 for done, width in images)  # every embedded PNG decoded
    assert page.title() == f"Study {reported.data.name}: chassistune report"
    _check_screenshot(screenshot(page, "report"), page)


def _expected_traces(reported: Any) -> list[int]:
    """Per plot in page order: responses (panels x (optimizers + baseline)) per tuned road,
    convergence (band and median per optimizer), final costs (a box per optimizer)."""
    n_opt = len(reported.data.optimizers)
    panels = 4  # abs-wheel: slip, speed, brake torque, distance
    out = []
    for sc in reported.data.scenarios:
        roads = reported.data.runs(sc)[0].spec.roads
        out += [panels * (n_opt + 1)] * len(roads) + [2 * n_opt, n_opt]
    return out


def test_interactive_report_loads_offline_and_draws_every_trace(page, reported, screenshot) -> None:
    net = _open(page, reported.interactive)
    page.wait_for_function("document.querySelectorAll('.plot .main-svg').length > 0")
    assert net.outside == [] and net.errors == []
    counts = page.evaluate("""Array.from(document.querySelectorAll('div.plot')).map(
        d => [d.data.length, Number(d.dataset.traces), d.querySelectorAll('.main-svg').length,
              d.querySelectorAll('.scatterlayer .trace, .boxlayer .trace').length])""")
    assert [c[0] for c in counts] == _expected_traces(reported)
    for drawn, declared, svgs, shown in counts:
        assert drawn == declared and svgs > 0 and shown == drawn  # every trace is drawn
    logs = page.evaluate("""Array.from(document.querySelectorAll('div.plot'))
        .filter(d => d.layout.yaxis && d.layout.yaxis.type === 'log').length""")
    assert logs >= 1  # convergence on a log axis (costs span decades here)
    _check_screenshot(screenshot(page, "report_interactive"), page)


def test_a_legend_click_hides_an_optimizer(page, reported) -> None:
    _open(page, reported.interactive)
    conv = page.locator("div.plot").nth(
        _expected_traces(reported).index(2 * len(reported.data.optimizers))
    )
    conv.scroll_into_view_if_needed()
    shown = "d => d.querySelectorAll('.scatterlayer .trace').length"
    before = conv.evaluate(shown)
    conv.locator(".legend .traces").first.click()
    page.wait_for_function(
        "d => d.data.some(t => t.visible === 'legendonly')", arg=conv.element_handle()
    )
    visible = conv.evaluate("d => d.data.map(t => t.visible === undefined ? true : t.visible)")
    first = reported.data.optimizers[0]
    names = conv.evaluate("d => d.data.map(t => t.legendgroup)")
    assert [v == "legendonly" for v in visible] == [n == first for n in names]
    assert conv.evaluate(shown) == before - 2  # its median and its band are gone


def test_a_table_sorts_by_a_clicked_header(page, reported) -> None:
    _open(page, reported.interactive)
    table = page.locator("table.sortable", has=page.locator("th", has_text="kp")).first
    header = table.locator("thead tr").last.locator("th", has_text="cost")
    col = table.locator("thead tr").last.locator("th").all_inner_texts().index("cost")

    def column() -> list[float]:
        return [
            float(t) for t in table.locator(f"tbody tr td:nth-child({col + 1})").all_inner_texts()
        ]

    original = column()
    assert original != sorted(original)  # grouped by optimizer, not by cost
    header.click()
    assert column() == sorted(original)
    assert header.get_attribute("aria-sort") == "ascending"
    header.click()
    assert column() == sorted(original, reverse=True)


class _Links(HTMLParser):
    """Every src and href of a page, and whether a <script> has a src."""

    def __init__(self) -> None:
        super().__init__()
        self.links: list[str] = []
        self.script_src = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        self.links += [str(a[k]) for k in ("src", "href") if a.get(k)]
        self.script_src |= tag == "script" and "src" in a


@pytest.mark.parametrize("name", ["report.html", "report_interactive.html"])
def test_pages_link_nothing_outside_and_embed_their_tables(reported, name: str) -> None:
    parser = _Links()
    parser.feed((reported.dir / name).read_text(encoding="utf-8"))
    assert not parser.script_src
    assert all(link.startswith(("#", "data:")) for link in parser.links)
    csvs = [link for link in parser.links if link.startswith("data:text/csv")]
    assert len(set(csvs)) == len(list((reported.dir / "report" / "tables").glob("*.csv")))
