"""The package's shape: no import cycles (a module never imports one that imports it back,
at module level or inside a function), the pipeline's direction (``run.py`` is imported by no
suite, the report by no backend), and every registered suite in its own module."""

from __future__ import annotations

import ast
from pathlib import Path

import kinverify
from kinverify.suites.registry import SUITES

PACKAGE = Path(kinverify.__file__).parent


def module_name(path: Path) -> str:
    parts = ["kinverify", *path.relative_to(PACKAGE).with_suffix("").parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {module_name(p): p for p in PACKAGE.rglob("*.py")}


def imports(name: str) -> set[str]:
    """Every kinverify module ``name`` imports, wherever the import statement is."""
    path = MODULES[name]
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                base = ".".join(up + ([base] if base else []))
            targets = [f"{base}.{a.name}" for a in node.names] + [base]
        else:
            continue
        for target in targets:
            while target and target not in MODULES:  # `from pkg import name`: the module is pkg
                target = target.rpartition(".")[0]
            if target and target != name:
                out.add(target)
    return out


GRAPH = {name: imports(name) for name in MODULES}


def cycles() -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on_stack, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in GRAPH[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(GRAPH):
        if v not in index:
            visit(v)
    return out


def test_no_module_imports_one_that_imports_it_back():
    found = cycles()
    detail = ["; ".join(f"{a} -> {b}" for a in c for b in sorted(GRAPH[a] & set(c))) for c in found]
    assert not found, "import cycles:\n" + "\n".join(detail)


def test_the_pipeline_points_one_way():
    importers_of_run = sorted(n for n, deps in GRAPH.items() if "kinverify.run" in deps)
    assert all(
        n.startswith(("kinverify.commands", "kinverify.filemode", "kinverify.testing", "kinverify.cli")) or n == "kinverify"
        for n in importers_of_run
    ), importers_of_run
    for name, deps in GRAPH.items():
        if name.startswith(("kinverify.backends", "kinverify.model", "kinverify.suites")):
            assert not any(d.startswith("kinverify.commands") for d in deps), (name, deps)
        if name.startswith(("kinverify.backends", "kinverify.model", "kinverify.generate")):
            assert not any(d.startswith(("kinverify.report", "kinverify.suites", "kinverify.run")) for d in deps), (name, deps)


def test_each_registered_suite_is_its_own_module_under_suites():
    modules = [s.__module__ for s in SUITES]
    assert len(set(modules)) == len(modules)
    assert all(m.startswith("kinverify.suites.") for m in modules)
    names = [s.name for s in SUITES]
    assert len(set(names)) == len(names)
    props = [p.name for s in SUITES for p in s.properties]
    assert len(set(props)) == len(props), "a property is declared by two suites"
