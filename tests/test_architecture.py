"""The house rules of ``docs/architecture.md``, measured on the source (issue 25).

* no source file over 600 lines outside ``geometry/``, ``contact/`` and ``fe/`` (where a
  file is one mathematical object);
* no module imports an underscore name from another module;
* imports form no circle, the deliberate lazy ones aside: a result's ``plot()`` method
  importing its figure module from inside the function (python-control's pattern), and
  a module-level ``__getattr__`` (PEP 562) that keeps a moved public name importable
  from its old module;
* the engine (``dynamics/``) stands on ``model/``, ``errors`` and ``units`` only;
* layers import downward: nothing below ``cli/`` imports it, nothing below
  ``pipeline/`` (the whole chain, ``run``) imports it, and nothing below ``reporting/``
  imports the report.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "src" / "reducerlab"
LONG_OK = ("geometry", "contact", "fe")
MAX_LINES = 600


def _modules() -> dict[str, Path]:
    out = {}
    for p in sorted(ROOT.rglob("*.py")):
        parts = p.relative_to(ROOT.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


MODULES = _modules()


def _imports(name: str, path: Path) -> list[tuple[str, str | None, str | None, int]]:
    """(module, imported name or None, the function importing it or None at module
    level, line) per import."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = []

    def visit(node: ast.AST, local: str | None) -> None:
        for child in ast.iter_child_nodes(node):
            inner = local
            if local is None and isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                inner = child.name
            if isinstance(child, ast.ImportFrom):
                if child.level:
                    base = package.split(".")[: len(package.split(".")) - child.level + 1]
                    target = ".".join(base + ([child.module] if child.module else []))
                else:
                    target = child.module or ""
                for alias in child.names:
                    sub = f"{target}.{alias.name}"
                    if sub in MODULES:
                        out.append((sub, None, inner, child.lineno))
                    elif target in MODULES:
                        out.append((target, alias.name, inner, child.lineno))
            elif isinstance(child, ast.Import):
                for alias in child.names:
                    if alias.name in MODULES:
                        out.append((alias.name, None, inner, child.lineno))
            visit(child, inner)

    visit(tree, None)
    return out


IMPORTS = {name: _imports(name, path) for name, path in MODULES.items()}


def _rel(path: Path) -> str:
    return str(path.relative_to(ROOT.parent))


def test_no_long_files_outside_the_mathematical_objects():
    long = [
        f"{_rel(p)}: {n} lines"
        for name, p in MODULES.items()
        if name.split(".")[1:2] and name.split(".")[1] not in LONG_OK
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_LINES
    ]
    assert not long, "files over 600 lines:\n" + "\n".join(long)


def test_no_underscore_name_imported_across_modules():
    found = [
        f"{_rel(MODULES[name])}:{line} imports {imp} from {target}"
        for name, items in IMPORTS.items()
        for target, imp, _, line in items
        if imp and imp.startswith("_") and not imp.startswith("__")
    ]
    assert not found, "\n".join(found)


def _graph(skip_lazy_plot: bool) -> dict[str, set[str]]:
    graph: dict[str, set[str]] = defaultdict(set)
    for name, items in IMPORTS.items():
        for target, _, local, _ in items:
            lazy_figure = local is not None and target.startswith("reducerlab.plot.")
            forwarder = local == "__getattr__"
            if target != name and not (skip_lazy_plot and (lazy_figure or forwarder)):
                graph[name].add(target)
    return graph


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    found: list[list[str]] = []

    def connect(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in sorted(MODULES):
        if v not in index:
            connect(v)
    return found


def test_import_circles_only_the_lazy_result_to_figure_ones():
    circles = _circles(_graph(skip_lazy_plot=True))
    assert not circles, "import circles:\n" + "\n".join(" <-> ".join(c) for c in circles)


def test_the_circle_check_sees_circles():
    # the check above is not vacuous: the lazy result -> figure imports do close circles
    assert _circles(_graph(skip_lazy_plot=False))


@pytest.mark.parametrize(
    "package, allowed",
    [
        ("dynamics", ("dynamics", "model", "errors", "units", "budget")),
        ("model", ("model", "errors", "units", "budget")),
        ("kinematics", ("kinematics", "errors", "units")),
        ("rating", ("rating", "geometry", "contact", "errors", "units", "budget")),
    ],
)
def test_lower_floors_import_only_below(package, allowed):
    bad = [
        f"{name} imports {target}"
        for name, items in IMPORTS.items()
        if name.split(".")[1:2] == [package]
        for target, _, _, _ in items
        if target != "reducerlab" and target.split(".")[1] not in allowed
    ]
    assert not bad, "\n".join(bad)


def test_nothing_below_the_surface_imports_it():
    bad = [
        f"{name} imports {target}"
        for name, items in IMPORTS.items()
        for target, _, _, _ in items
        for top in ("cli", "pipeline", "reporting")
        if target.split(".")[1:2] == [top]
        and name.split(".")[1:2] != [top]
        and not (top == "reporting" and name.split(".")[1:2] in (["cli"], ["pipeline"]))
        and not (top == "pipeline" and name.split(".")[1:2] == ["cli"])
        and name not in ("reducerlab", "reducerlab.__main__")
    ]
    assert not bad, "\n".join(bad)
