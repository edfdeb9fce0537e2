"""No import circles inside a package of rotaflex.

Every module under ``src/rotaflex`` is parsed with :mod:`ast`; every ``import`` and
``from ... import`` statement counts, also those inside functions (a function-level import
hides a circle from the interpreter at import time but not from the design).  An edge
``a -> b`` joins two modules of the same top-level package (``rotaflex.gear``,
``rotaflex.rotor``, ...).  Tarjan's strongly connected components over that graph must all
be single modules without a self-edge.  The graph builder is checked on a hand-made
package with a known circle so that a broken parser cannot pass silently.
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src"


def _module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    """Absolute module a ``from`` import names (relative levels resolved)."""
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    if node.level > 1:
        base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def import_graph(root: Path, top: str) -> dict[str, set[str]]:
    """Edges between the modules of package ``top`` found under ``root``.

    Parameters
    ----------
    root : Path
        Directory holding the top package (``src``).
    top : str
        Name of the top package (``rotaflex``).

    Returns
    -------
    dict
        Module name -> set of imported module names (only modules found under ``root``).
    """
    files = {}
    for path in sorted((root / top).rglob("*.py")):
        files[_module_name(path, root)] = path
    modules = set(files)
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for mod, path in files.items():
        is_package = path.name == "__init__.py"
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in ast.walk(tree):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = _resolve(mod, is_package, node)
                # ``from pkg import sub`` depends on the submodule when one exists, on
                # ``pkg`` itself otherwise (a name defined in its ``__init__``).  Running a
                # parent's ``__init__`` on the way down is not counted, as for ``import a.b``.
                targets = [
                    f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base for alias in node.names
                ]
            for target in targets:
                # ``import a.b.c`` also runs a and a.b; the deepest existing module
                # is the dependency that matters for a circle.
                while target and target not in modules:
                    target = target.rpartition(".")[0]
                if target and target != mod:
                    graph[mod].add(target)
    return graph


def _package(module: str) -> str:
    """The package a module belongs to for the circle rule (``rotaflex.gear`` ...)."""
    return ".".join(module.split(".")[:2])


def cycles_inside_packages(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module within one package.

    Parameters
    ----------
    graph : dict
        Module -> imported modules.

    Returns
    -------
    list of list of str
        Each circle's modules, sorted.
    """
    inner = {m: {t for t in ts if _package(t) == _package(m)} for m, ts in graph.items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    counter = [0]

    def visit(start: str) -> None:
        # Iterative Tarjan (recursion depth would follow the import chain length).
        work = [(start, iter(sorted(inner[start])))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            advanced = False
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter[0]
                    counter[0] += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(inner[child]))))
                    advanced = True
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            if advanced:
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
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

    for module in sorted(inner):
        if module not in index:
            visit(module)
    return found


def test_graph_finds_a_known_circle(tmp_path):
    pkg = tmp_path / "toy" / "sub"
    pkg.mkdir(parents=True)
    (tmp_path / "toy" / "__init__.py").write_text("")
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from .b import f\n")
    (pkg / "b.py").write_text("def f():\n    from toy.sub import c\n")
    (pkg / "c.py").write_text("import toy.sub.a\n")
    (pkg / "d.py").write_text("from . import a\n")
    graph = import_graph(tmp_path, "toy")
    assert graph["toy.sub.d"] == {"toy.sub.a"}
    assert cycles_inside_packages(graph) == [["toy.sub.a", "toy.sub.b", "toy.sub.c"]]


def test_no_import_circle_inside_a_package():
    graph = import_graph(SRC, "rotaflex")
    assert len(graph) > 100  # the whole source tree was read
    circles = cycles_inside_packages(graph)
    assert circles == [], "import circles:\n" + "\n".join(" <-> ".join(c) for c in circles)
