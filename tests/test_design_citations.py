"""The design the code cites is in the repository, and comments say what the code does.

Every citation `design.md x.y` (or the older `DESIGN x.y`) in src/, tests/, docs/ and the README
must name a section heading of docs/design.md; the algorithms are cited from
docs/optimizers_design.md, not from a file outside the repository; and no comment or docstring
under src/ or tests/ cites an issue number (the why belongs in the text, the history in commit
messages).
"""

from __future__ import annotations

import ast
import io
import re
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DESIGN = ROOT / "docs" / "design.md"

SECTION = r"\d+(?:\.\d+)?"
CITATION = re.compile(rf"(?:\bDESIGN|\bdesign\.md) ({SECTION}(?:(?:, | and ){SECTION})*)")
"""A citation and its list of sections: `design.md 3.4, 5` cites 3.4 and 5."""
HEADING = re.compile(rf"^#{{2,3}} ({SECTION})\.? ", re.MULTILINE)
ISSUE = re.compile(r"\bissues? #?\d+|\(issue\b|#\d+\b item", re.IGNORECASE)


def _cited_files() -> list[Path]:
    files = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    for top in ("src", "tests"):
        files += sorted(p for ext in ("py", "toml", "md") for p in (ROOT / top).rglob(f"*.{ext}"))
    return files


def _python_files() -> list[Path]:
    return sorted(p for top in ("src", "tests") for p in (ROOT / top).rglob("*.py"))


def _sections() -> set[str]:
    return set(HEADING.findall(DESIGN.read_text(encoding="utf-8"))) if DESIGN.is_file() else set()


def _prose(source: str) -> list[tuple[int, str]]:
    """(line, text) of every comment and docstring (any string statement) of a module."""
    found = [
        (tok.start[0], tok.string)
        for tok in tokenize.generate_tokens(io.StringIO(source).readline)
        if tok.type == tokenize.COMMENT
    ]
    found += [
        (node.lineno, node.value.value)
        for node in ast.walk(ast.parse(source))
        if isinstance(node, ast.Expr)
        and isinstance(node.value, ast.Constant)
        and isinstance(node.value.value, str)
    ]
    return found


def _where(path: Path, text: str, pos: int) -> str:
    return f"{path.relative_to(ROOT)}:{text.count(chr(10), 0, pos) + 1}"


def test_design_is_in_the_repository_with_numbered_sections() -> None:
    assert DESIGN.is_file()
    assert (ROOT / "docs" / "optimizers_design.md").is_file()
    sections = _sections()
    assert {"2", "3.1", "3.2", "3.3", "3.4", "4", "5", "7", "8"} <= sections


def test_every_design_citation_names_an_existing_section() -> None:
    sections = _sections()
    bad = []
    for path in _cited_files():
        text = path.read_text(encoding="utf-8")
        for m in CITATION.finditer(text):
            missing = [s for s in re.split(r", | and ", m.group(1)) if s not in sections]
            if missing:
                bad.append(f"{_where(path, text, m.start())}: {m.group(0)!r} (no {missing})")
    assert not bad, "\n".join(bad)


def test_no_citation_of_the_design_outside_the_repository() -> None:
    bad = []
    for path in _cited_files():
        text = path.read_text(encoding="utf-8")
        for m in re.finditer(r"OPTIMIZERS\.md|shared[/]DESIGN", text):
            bad.append(f"{_where(path, text, m.start())}: {m.group(0)!r}")
    assert not bad, "\n".join(bad)


def test_no_comment_or_docstring_cites_an_issue_number() -> None:
    bad = []
    for path in _python_files():
        for line, text in _prose(path.read_text(encoding="utf-8")):
            bad += [
                f"{path.relative_to(ROOT)}:{line}: {m.group(0)!r}" for m in ISSUE.finditer(text)
            ]
    assert not bad, "\n".join(bad)


def test_the_issue_check_reads_comments_and_docstrings_only() -> None:
    source = '''"""Module (issue 3)."""\nx = "issue 4"  # issue 5\n'''
    hits = [(line, m.group(0)) for line, text in _prose(source) for m in ISSUE.finditer(text)]
    assert sorted(hits) == [(1, "(issue"), (2, "issue 5")]
