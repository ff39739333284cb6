"""The reproduction's report (the session's quick `reproduce all`) in headless chromium: it loads
with no request outside file:, no page or console error, every embedded figure decoded, and a
first section holding the verdict table."""

from __future__ import annotations

import pandas as pd
from test_browser import WIDTH, Offline


def test_reproduction_report_renders_without_errors(page, reproduced, screenshot) -> None:
    page.set_viewport_size({"width": WIDTH, "height": 900})
    net = Offline(page)
    page.goto((reproduced.out / "report.html").as_uri(), wait_until="load")
    assert net.outside == [] and net.errors == []
    images = page.evaluate("Array.from(document.images).map(i => [i.complete, i.naturalWidth])")
    assert len(images) == len(list((reproduced.out / "figures").glob("*.png"))) > 0
    assert all(done and width > 300 for done, width in images)
    rows = page.locator("#verdicts table").first.locator("tbody tr").count()
    assert rows == len(pd.read_csv(reproduced.out / "verdicts.csv"))
    pixels = screenshot(page, "reproduce_report")
    assert pixels.std() > 10
