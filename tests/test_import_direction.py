"""Imports point one way (design.md 2): every import of every module, lazy ones inside functions
included, is parsed and checked against the layers

    plants, controllers (-> fuzzy), fuzzy, optimizers, benchmarks  <-  sim  <-  scenarios
    <-  tuning  <-  studies  <-  reports, export  <-  papers, league  <-  transfer  <-  cli

plots are imported by reports, papers, league, transfer and cli only; nothing imports cli;
matplotlib is imported in plots only. The shared helpers at the top of the package (errors, params,
stats, _registry, ...) sit below every layer; the package's __init__ (its public API) may import any
layer but cli, and no module of the package imports it. No import cycle either, inside a package or
across: the same imports (lazy and type-only ones too) may not lead from a module back to itself.
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
    "league": 6,
    "results": 6,
    "transfer": 7,
    "cli": 8,
}
"""Layer of each subpackage (or top-level module); unlisted top-level modules are helpers."""

ALLOWED_PEERS = {("controllers", "fuzzy")}
"""Imports between different packages of one layer that the design allows."""

PLOT_USERS = {"reports", "papers", "league", "transfer", "cli", "plots"}


def _modules() -> list[Path]:
    return sorted(SRC.rglob("*.py"))


def _package(path: Path) -> str:
    """`plants` for src/chassistune/plants/x.py, `simulate` for src/chassistune/simulate.py."""
    rel = path.relative_to(SRC)
    return rel.parts[0] if len(rel.parts) > 1 else rel.stem


def _statements(path: Path, src: Path = SRC) -> list[tuple[int, str, list[str]]]:
    """(line, dotted module, names taken from it) of every import statement of the module at
    `path` in the package folder `src`, at any depth (lazy and type-only imports too); the names
    are empty for `import a.b`."""
    tree = ast.parse(path.read_text(), str(path))
    rel = path.relative_to(src.parent).with_suffix("")
    here = list(rel.parts[:-1])  # the package a relative import starts from
    out: list[tuple[int, str, list[str]]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name, []) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            out.append((node.lineno, name, [a.name for a in node.names]))
    return out


def _imports(path: Path) -> list[tuple[int, str]]:
    """(line, dotted module) of every import statement, at any depth (lazy imports too)."""
    out: list[tuple[int, str]] = []
    for line, name, names in _statements(path):
        out.append((line, name))
        out += [(line, f"{name}.{n}") for n in names if name == "chassistune"]
    return out


def _module_name(path: Path, src: Path) -> str:
    """`pkg.sub.mod` for src/sub/mod.py, `pkg.sub` for src/sub/__init__.py (src is `pkg`)."""
    parts = list(path.relative_to(src.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def import_graph(src: Path) -> dict[str, set[str]]:
    """The modules of the package folder `src`, each with the modules of the package it imports:
    `from a import b` imports the module a.b when there is one, else the module a (a package's
    `__init__`); the parent packages a module's import runs first are not edges."""
    paths = {_module_name(p, src): p for p in sorted(src.rglob("*.py"))}
    graph: dict[str, set[str]] = {}
    for module, path in paths.items():
        graph[module] = set()
        for _, name, names in _statements(path, src):
            subs = {f"{name}.{n}" for n in names} & paths.keys()
            graph[module] |= subs
            if name in paths and len(subs) < len(names or [""]):
                graph[module].add(name)
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import cycles of `graph`: each set of modules that import one another, directly or
    not (a strongly connected component of two modules or more, or one importing itself),
    sorted (Tarjan 1972, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        while work:
            node, todo = work[-1]
            nxt = next(todo, None)
            if nxt is not None:
                if nxt not in index:
                    index[nxt] = low[nxt] = len(index)
                    stack.append(nxt)
                    work.append((nxt, iter(sorted(graph[nxt]))))
                elif nxt in stack:
                    low[node] = min(low[node], index[nxt])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = stack[stack.index(node) :]
                del stack[stack.index(node) :]
                if len(component) > 1 or node in graph[node]:
                    found.append(sorted(component))
    return sorted(found)


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
    path = SRC / "sim" / "abs_wheel_tires.py"
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


def _fake_package(root: Path, files: dict[str, str]) -> Path:
    """A package `fake` in `root` with `files` (path inside the package: source)."""
    src = root / "fake"
    for rel, text in {"__init__.py": "", **files}.items():
        (src / rel).parent.mkdir(parents=True, exist_ok=True)
        (src / rel).write_text(text)
    return src


def test_a_cycle_inside_a_package_is_found_through_lazy_imports(tmp_path: Path) -> None:
    """a -> b at the top, b -> c inside a function, c -> a (relative, from its package): one
    cycle of three; d, which imports into the cycle, is not in it."""
    src = _fake_package(
        tmp_path,
        {
            "tuning/__init__.py": "",
            "tuning/a.py": "from fake.tuning.b import run\n",
            "tuning/b.py": "def run():\n    from fake.tuning import c\n",
            "tuning/c.py": "from .a import x\n",
            "tuning/d.py": "import fake.tuning.a\n",
        },
    )
    assert cycles(import_graph(src)) == [["fake.tuning.a", "fake.tuning.b", "fake.tuning.c"]]


def test_a_module_reading_the_version_from_the_package_init_is_a_cycle(tmp_path: Path) -> None:
    """The package's __init__ imports its API (type-only here); a module of that API takes
    `__version__` from the __init__: a cycle through the __init__."""
    src = _fake_package(
        tmp_path,
        {
            "__init__.py": "from typing import TYPE_CHECKING\n__version__ = '1'\n"
            "if TYPE_CHECKING:\n    from fake.export.json import dump\n",
            "export/__init__.py": "",
            "export/json.py": "from fake import __version__\n",
            "export/c.py": "from fake import export\n",
        },
    )
    assert cycles(import_graph(src)) == [["fake", "fake.export.json"]]


def test_a_module_importing_itself_is_a_cycle() -> None:
    assert cycles({"p.a": {"p.a"}, "p.b": {"p.a"}}) == [["p.a"]]


def test_no_import_cycle() -> None:
    found = cycles(import_graph(SRC))
    assert found == [], "import cycles:\n" + "\n".join(" <-> ".join(c) for c in found)


def test_no_module_imports_the_package_init() -> None:
    """The public API (`chassistune/__init__.py`) sits above every layer: a module of the
    package reads what it needs (`_version.__version__`) from the module that holds it."""
    graph = import_graph(SRC)
    assert sorted(m for m, targets in graph.items() if "chassistune" in targets) == []
