"""`study report DIR`: read the store, compute the tables, draw the figures, write the page.

Output: DIR/report.html (self-contained: figures and table data embedded), and the same tables
and figures as files, DIR/report/tables/*.csv and DIR/report/figures/*.png. The store is only
read; best responses are re-simulated from the stored specs and gains.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from chassistune._io import file_set
from chassistune.errors import InputError
from chassistune.reports import sections, tables
from chassistune.reports.html import Section
from chassistune.studies.store import open_study, store_path

REPORT_NAME = "report.html"


@dataclass(frozen=True)
class ReportFiles:
    """What a report build wrote."""

    html: Path
    folder: Path
    tables: list[Path]
    figures: list[Path]


@dataclass(frozen=True)
class StudyReport:
    """A study read for reporting: its runs, config and reference optimizer."""

    root: Path
    data: tables.StudyData
    config: dict[str, Any]
    reference: str

    def sections(self, assets: sections.Assets, figures: sections.Figures) -> list[Section]:
        return sections.study_sections(
            self.data, self.config, self.reference, store_path(self.root), assets, figures
        )

    @property
    def summary(self) -> str:
        return sections.summary_line(self.data, self.reference)

    @property
    def description(self) -> str:
        return str(self.config.get("study", {}).get("description", ""))


def read_study(study_dir: str | Path, reference: str | None) -> StudyReport:
    """Read DIR's runs and config (InputError for a bad DIR or an unknown reference)."""
    root = Path(study_dir)
    with open_study(root) as store:
        data = tables.load_study(store)
        config = json.loads(store.meta().get("config", "{}"))
    if not data.records:
        raise InputError("DIR", f"{str(root)!r} holds no finished runs yet")
    return StudyReport(root, data, config, tables.check_reference(data, reference))


def build_report(study_dir: str | Path, reference: str | None = None) -> ReportFiles:
    """Write DIR/report.html, its CSV tables and PNG figures as one set of files (all or none,
    `_io.file_set`); InputError for a bad DIR."""
    from importlib.metadata import version

    from chassistune.reports.figures import PngFigures
    from chassistune.reports.html import render

    study = read_study(study_dir, reference)
    html = study.root / REPORT_NAME
    with file_set() as staged:
        assets = sections.Assets(study.root, staged)
        figures = PngFigures(assets)
        page = render(
            study.data.name,
            study.summary,
            study.description,
            study.sections(assets, figures),
            version("chassistune"),
        )
        staged.write_text(html, page)
    figures.remove_stale()
    return ReportFiles(html, study.root / sections.ASSETS, assets.tables, figures.written)
