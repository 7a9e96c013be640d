"""The house rules that a reader of the code relies on: no import circles
among vstpetsc's modules (module-level and function-level imports both),
no function over 60 lines, no class over 200."""

import ast
import os

from conftest import ROOT

PACKAGE = os.path.join(ROOT, "vstpetsc")
LONGEST_FUNCTION, LONGEST_CLASS = 60, 200


def modules():
    """{dotted name: parsed tree} of every module of the package."""
    out = {}
    for folder, _, files in os.walk(PACKAGE):
        for name in files:
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                dotted = os.path.relpath(path, ROOT)[:-3].replace(os.sep, ".")
                dotted = dotted[:-len(".__init__")] if dotted.endswith(".__init__") else dotted
                with open(path) as f:
                    out[dotted] = ast.parse(f.read(), path)
    return out


def imports(name, tree, known):
    """The package's modules that module ``name`` imports, anywhere in it."""
    found = set()
    package = name if name in known and _is_package(name) else name.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([base] if base else []))
            found.add(base)
            found.update(f"{base}.{a.name}" for a in node.names)
    return {m for m in found if m in known and m != name}


def _is_package(name):
    return os.path.isdir(os.path.join(ROOT, *name.split(".")))


def cycles(graph):
    """The strongly connected components of more than one module."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            part = set()
            while True:
                w = stack.pop()
                on.discard(w)
                part.add(w)
                if w == v:
                    break
            if len(part) > 1:
                out.append(sorted(part))

    for v in graph:
        if v not in index:
            visit(v)
    return out


def test_no_import_circles():
    trees = modules()
    # a package's __init__ that only re-exports on demand (PEP 562) imports
    # nothing at module level; its submodules importing the package itself
    # is how Python loads them, not a circle
    graph = {n: {m for m in imports(n, t, trees) if not n.startswith(m + ".")}
             for n, t in trees.items()}
    assert cycles(graph) == []


def test_functions_and_classes_within_the_size_rules():
    long = []
    for name, tree in modules().items():
        for node in ast.walk(tree):
            limit = {ast.FunctionDef: LONGEST_FUNCTION, ast.AsyncFunctionDef: LONGEST_FUNCTION,
                     ast.ClassDef: LONGEST_CLASS}.get(type(node))
            if limit and node.end_lineno - node.lineno + 1 > limit:
                long.append(f"{name}.{node.name}: {node.end_lineno - node.lineno + 1} lines")
    assert long == []
