"""No import circles anywhere in ``simcore`` or ``app``, lazy imports included.

Every ``import`` and ``from … import`` of every module (at the top or inside a function)
is an edge of the graph; a strongly connected component of more than one module is a
circle. A package's ``__init__`` importing its own submodules (and a submodule importing
its package) is how a package is assembled, not a circle between modules.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def module_graph(root: Path, packages: tuple[str, ...] = ("simcore", "app")
                 ) -> dict[str, set[str]]:
    """Module → the modules of ``packages`` it imports (anywhere in its body)."""
    files: dict[str, Path] = {}
    for pkg in packages:
        for path in (root / pkg).rglob("*.py"):
            parts = path.relative_to(root).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            files[name] = path
    graph: dict[str, set[str]] = {name: set() for name in files}
    for name, path in files.items():
        is_package = path.name == "__init__.py"
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = name.split(".") if is_package else name.split(".")[:-1]
                    base = base[:len(base) - (node.level - 1)]
                    module = ".".join(base + ([node.module] if node.module else []))
                else:
                    module = node.module or ""
                targets = [module, *(f"{module}.{alias.name}" for alias in node.names)]
            else:
                continue
            for target in targets:
                while target and target not in files:
                    target = target.rpartition(".")[0]
                if target and target != name and not name.startswith(target + "."):
                    graph[name].add(target)
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    found: list[list[str]] = []
    counter = 0
    for start in graph:
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is None:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
            elif child not in index:
                index[child] = low[child] = counter
                counter += 1
                stack.append(child)
                on_stack.add(child)
                work.append((child, iter(sorted(graph[child]))))
            elif child in on_stack:
                low[node] = min(low[node], index[child])
    return found


def test_the_circle_finder_finds_a_lazy_circle(tmp_path):
    pkg = tmp_path / "simcore"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from simcore.b import f\n")
    (pkg / "b.py").write_text("def f():\n    from simcore import c\n")
    (pkg / "c.py").write_text("import simcore.a\n")
    (pkg / "d.py").write_text("from simcore import a\n")
    assert circles(module_graph(tmp_path, ("simcore",))) == [
        ["simcore.a", "simcore.b", "simcore.c"]]


def test_no_import_circles_in_simcore_or_app():
    assert circles(module_graph(ROOT)) == []


def imported_names(path: Path) -> set[str]:
    """Every module name that ``path`` imports, at the top or inside a function."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return names


def widget_imports(path: Path) -> set[str]:
    """The widget toolkits among the imports of ``path``."""
    widget = ("PyQt6.QtWidgets", "pyqtgraph", "pyvistaqt")
    return {name for name in imported_names(path)
            if any(name == w or name.startswith(w + ".") for w in widget)}


def test_the_widget_finder_finds_a_lazy_widget_import(tmp_path):
    module = tmp_path / "m.py"
    module.write_text("from PyQt6.QtGui import QUndoStack\n"
                      "def f():\n    from PyQt6 import QtWidgets\n    import pyqtgraph as pg\n")
    assert widget_imports(module) == {"PyQt6.QtWidgets", "pyqtgraph"}


def test_the_document_never_imports_a_widget():
    """The import-linter cannot forbid ``PyQt6.QtWidgets`` (a submodule of an external
    package), so this test keeps the document free of widgets, lazy imports included."""
    modules = sorted((ROOT / "app" / "document").rglob("*.py"))
    assert len(modules) >= 5
    assert {path.name: widget_imports(path) for path in modules} == {
        path.name: set() for path in modules}
