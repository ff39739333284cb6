"""The reproduction's reports (the session's quick `reproduce all --interactive`) in headless
chromium. The static page: loads with no request outside file:, no page or console error, every
embedded figure decoded, a first section holding the verdict table, every table within the
page's width. The interactive page (opened
once for this module: 60-odd plots take seconds to draw): the same offline and error checks,
plotly inlined once, the static page's sections and tables, one section per paper with its
studies' plots, every trace drawn, a legend click, a sortable table, a screenshot."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pandas as pd
import pytest
from test_browser import WIDTH, Offline, _Links

from chassistune.papers.keys import PAPER_KEYS


def test_reproduction_report_renders_without_errors(page, reproduced, screenshot) -> None:
    page.set_viewport_size({"width": WIDTH, "height": 900})
    net = Offline(page)
    page.goto((reproduced.out / "report.html").as_uri(), wait_until="load")
    assert net.outside == [] and net.errors == []
    images = page.evaluate("Array.from(document.images).map(i => [i.complete, i.naturalWidth])")
    assert len(images) == len(list((reproduced.out / "figures").glob("*.png"))) > 0
    assert all(done and width > 300 for done, width in images)
    rows = page.locator("#verdicts table").nth(1).locator("tbody tr").count()
    assert rows == len(pd.read_csv(reproduced.out / "verdicts.csv"))
    assert page.title() == "Reproduction of 4 paper(s): chassistune report"
    pixels = screenshot(page, "reproduce_report")
    assert pixels.std() > 10


def test_every_reproduction_table_fits_the_page_width(page, reproduced) -> None:
    page.set_viewport_size({"width": WIDTH, "height": 900})
    page.goto((reproduced.out / "report.html").as_uri(), wait_until="load")
    wide = page.evaluate(
        "Array.from(document.querySelectorAll('div.wrap'))"
        ".filter(d => d.scrollWidth > d.clientWidth + 1).map(d => d.firstElementChild.id)"
    )
    assert wide == []
    assert page.evaluate("document.documentElement.scrollWidth") <= WIDTH


@pytest.fixture(scope="module")
def live(browser, reproduced) -> Iterator[tuple[Any, Offline]]:
    """The interactive reproduction page, loaded once with every plot drawn."""
    context = browser.new_context(viewport={"width": WIDTH, "height": 900})
    page = context.new_page()
    net = Offline(page)
    page.goto((reproduced.out / "report_interactive.html").as_uri(), wait_until="load")
    page.wait_for_function(
        "Array.from(document.querySelectorAll('div.plot')).every("
        "d => d.querySelector('.main-svg'))",
        timeout=120_000,
    )
    yield page, net
    context.close()


def test_interactive_reproduction_loads_offline_with_plotly_inlined_once(live, reproduced) -> None:
    page, net = live
    assert net.outside == [] and net.errors == []
    text = (reproduced.out / "report_interactive.html").read_text(encoding="utf-8")
    parser = _Links()
    parser.feed(text)
    assert not parser.script_src
    assert all(link.startswith(("#", "data:")) for link in parser.links)
    assert text.count("plotly.js v") == 1  # the library's banner: inlined once
    assert page.title() == "Reproduction of 4 paper(s): chassistune interactive report"


def test_interactive_reproduction_has_the_static_sections_one_per_paper(
    live, page, reproduced
) -> None:
    live_page, _ = live
    sections = "Array.from(document.querySelectorAll('section')).map(s => s.id)"
    tables = (
        "Array.from(document.querySelectorAll('section h3')).filter(h => "
        "h.nextElementSibling && h.nextElementSibling.querySelector('table'))"
        ".map(h => h.textContent.replace(/^Table \\d+: /, ''))"
    )
    page.goto((reproduced.out / "report.html").as_uri(), wait_until="domcontentloaded")
    assert (
        live_page.evaluate(sections)
        == page.evaluate(sections)
        == ["verdicts", *PAPER_KEYS, "standard"]
    )
    assert live_page.evaluate(tables) == page.evaluate(tables)  # the same tables, in order
    static_images = page.evaluate("document.images.length")
    assert live_page.evaluate("document.images.length") == static_images > 0
    assert live_page.locator("table.sortable").count() == len(live_page.evaluate(tables))


def test_every_paper_section_draws_its_studies_and_every_trace(live) -> None:
    page, _ = live
    per_paper = page.evaluate(f"""{list(PAPER_KEYS)}.map(k => Array.from(
        document.getElementById(k).querySelectorAll('div.plot')).map(d => [
            d.data.length, Number(d.dataset.traces),
            d.querySelectorAll('.scatterlayer .trace, .boxlayer .trace').length]))""")
    for key, plots in zip(PAPER_KEYS, per_paper, strict=True):
        assert len(plots) >= 2, key  # at least a convergence and a final-cost figure
        for drawn, declared, shown in plots:
            assert drawn == declared == shown > 0, key
    logs = page.evaluate("""Array.from(document.querySelectorAll('div.plot'))
        .filter(d => d.layout.yaxis && d.layout.yaxis.type === 'log').length""")
    assert logs >= 5  # the benchmark functions' costs span decades
    linked = page.evaluate("""Array.from(document.querySelectorAll('div.plot'))
        .filter(d => d.layout.yaxis4 && ['xaxis', 'xaxis2', 'xaxis3'].every(
            a => d.layout[a].matches === 'x4')).length""")
    responses = page.evaluate("""Array.from(document.querySelectorAll('div.plot'))
        .filter(d => d.layout.yaxis4).length""")
    assert responses >= 6 and linked == responses  # abs responses: 4 panels, one time axis


def test_a_legend_click_hides_an_optimizer_in_a_paper_plot(live) -> None:
    page, _ = live
    conv = (
        page.locator("#derlsp-ao-abs-functions div.plot, #derlsp-ao-abs div.plot")
        .filter(has=page.locator(".legend"))
        .first
    )
    conv.scroll_into_view_if_needed()
    names = conv.evaluate("d => d.data.map(t => t.legendgroup || t.name)")
    conv.locator(".legend .traces").first.click()
    page.wait_for_function(
        "d => d.data.some(t => t.visible === 'legendonly')", arg=conv.element_handle()
    )
    hidden = conv.evaluate("d => d.data.map(t => t.visible === 'legendonly')")
    assert any(hidden) and not all(hidden)
    assert {n for n, h in zip(names, hidden, strict=True) if h} == {names[hidden.index(True)]}


def test_a_papers_table_sorts_by_a_clicked_header(live) -> None:
    page, _ = live
    table = page.locator(
        "#deffao-vehicle-abs table.sortable", has=page.locator("th", has_text="ours median")
    ).first
    heads = table.locator("thead tr").last.locator("th")
    col = heads.all_inner_texts().index("ours median")

    def column() -> list[float]:
        return [
            float(t) for t in table.locator(f"tbody tr td:nth-child({col + 1})").all_inner_texts()
        ]

    original = column()
    assert original != sorted(original)
    heads.nth(col).click()
    assert column() == sorted(original)
    heads.nth(col).click()
    assert column() == sorted(original, reverse=True)


def test_interactive_reproduction_screenshot_is_a_page(live, screenshot) -> None:
    page, _ = live
    pixels = screenshot(page, "reproduce_report_interactive")
    height = page.evaluate("document.documentElement.scrollHeight")
    assert pixels.shape == (height, WIDTH) and height > 20000
    ink = pixels < 200
    assert pixels.std() > 10 and 0.02 < ink.mean() < 0.6
