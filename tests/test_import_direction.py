"""Imports point one way (design.md 2): every import of every module, lazy ones inside functions
included, is parsed and checked against the layers

    plants, controllers (-> fuzzy), fuzzy, optimizers, benchmarks  <-  sim  <-  scenarios
    <-  tuning  <-  studies  <-  reports, export  <-  papers  <-  cli

plots are imported by reports, papers and cli only; nothing imports cli; matplotlib is imported in
plots only. The shared helpers at the top of the package (errors, params, stats, _registry, ...)
sit below every layer; the package's __init__ (its public API) may import any layer but cli.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "chassistune"

RANK = {
    "plants": 0,
    "controllers": 0,
    "fuzzy": 0,
    "optimizers": 0,
    "benchmarks": 0,
    "sim": 1,
    "scenarios": 2,
    "tuning": 3,
    "simulate": 3,
    "studies": 4,
    "reports": 5,
    "perf": 5,
    "plots": 5,
    "export": 5,
    "papers": 6,
    "results": 6,
    "cli": 7,
}
"""Layer of each subpackage (or top-level module); unlisted top-level modules are helpers."""

ALLOWED_PEERS = {("controllers", "fuzzy")}
"""Imports between different packages of one layer that the design allows."""

PLOT_USERS = {"reports", "papers", "cli", "plots"}


def _modules() -> list[Path]:
    return sorted(SRC.rglob("*.py"))


def _package(path: Path) -> str:
    """`plants` for src/chassistune/plants/x.py, `simulate` for src/chassistune/simulate.py."""
    rel = path.relative_to(SRC)
    return rel.parts[0] if len(rel.parts) > 1 else rel.stem


def _imports(path: Path) -> list[tuple[int, str]]:
    """(line, dotted module) of every import statement, at any depth (lazy imports too)."""
    tree = ast.parse(path.read_text(), str(path))
    rel = path.relative_to(SRC.parent).with_suffix("")
    here = list(rel.parts[:-1])  # the package a relative import starts from
    out: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            out.append((node.lineno, name))
            out += [(node.lineno, f"{name}.{a.name}") for a in node.names if name == "chassistune"]
    return out


def _violation(importer: str, path: Path, target: str) -> str | None:
    """Why importing `target` from a module of package `importer` breaks the direction."""
    if target.split(".")[0] == "matplotlib":
        return None if importer == "plots" else "matplotlib outside plots/"
    parts = target.split(".")
    if parts[0] != "chassistune" or len(parts) < 2:
        return None
    imported = parts[1]
    if imported == importer:
        return None
    if imported == "cli":
        return "nothing imports cli"
    if imported == "plots" and importer not in PLOT_USERS:
        return "plots are used by reports, papers and cli only"
    if path == SRC / "__init__.py" or importer not in RANK or imported not in RANK:
        return None  # the public API, or a shared helper on either side
    if RANK[imported] > RANK[importer]:
        return f"{importer} (layer {RANK[importer]}) imports {imported} (layer {RANK[imported]})"
    if (
        RANK[imported] == RANK[importer]
        and (importer, imported) not in ALLOWED_PEERS
        and imported != "plots"
    ):
        return f"{importer} imports its peer {imported}"
    return None


def test_the_parser_sees_top_level_and_lazy_imports() -> None:
    path = SRC / "plants" / "tire_kernel.py"
    found = {name for _, name in _imports(path)}
    assert "chassistune.plants.tires" in found and "numba" in found
    lazy = SRC / "scenarios" / "abs_wheel.py"
    assert "chassistune.fuzzy.loader" in {name for _, name in _imports(lazy)}  # inside a function


@pytest.mark.parametrize(
    ("importer", "target", "allowed"),
    [
        ("plants", "chassistune.sim.batch", False),
        ("sim", "chassistune.plants.tires", True),
        ("scenarios", "chassistune.tuning.problem", False),
        ("controllers", "chassistune.fuzzy.surface", True),
        ("fuzzy", "chassistune.controllers.specs", False),
        ("tuning", "chassistune.plots.registry", False),
        ("reports", "chassistune.plots.registry", True),
        ("studies", "chassistune.cli.common", False),
        ("sim", "matplotlib.pyplot", False),
        ("export", "chassistune.studies.store", True),
        ("export", "chassistune.reports.outputs", False),
        ("export", "chassistune.cli.common", False),
        ("studies", "chassistune.export.source", False),
    ],
)
def test_the_rules_refuse_what_the_design_forbids(
    importer: str, target: str, allowed: bool
) -> None:
    path = SRC / importer / "x.py"
    assert (_violation(importer, path, target) is None) == allowed


def test_no_module_imports_against_the_direction() -> None:
    problems = []
    for path in _modules():
        importer = _package(path)
        for line, target in _imports(path):
            why = _violation(importer, path, target)
            if why:
                problems.append(f"{path.relative_to(SRC.parent)}:{line}: {target}: {why}")
    assert not problems, "\n".join(problems)
