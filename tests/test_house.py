"""House rules of the package (issue 35), read from its source with ast:
no import cycle among vstpetsc's modules, no function over 60 lines, no
class over 200.

    .venv/bin/python tests/test_house.py      # prints every cycle and every long one

Imports count wherever they are, at the top of a module or inside a
function: an import moved into a function to dodge a cycle leaves the
modules as entangled as before, only the failure later.  An import names
the module it loads (``from vstpetsc.results import layout`` the module
layout, ``from vstpetsc import Case`` the package's ``__init__``); the
parent packages that Python runs first are left out, else every module
of a package whose ``__init__`` imports one of its modules would be in
a cycle with it.
"""

import ast
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PACKAGE = "vstpetsc"
FUNCTION_LINES = 60
CLASS_LINES = 200
LONG_AS_YET = set()            # none: every class and function within the rules


def modules(root=ROOT):
    """{module name: path} of every .py file of the package."""
    out = {}
    for folder, _, files in os.walk(os.path.join(root, PACKAGE)):
        for name in files:
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                dotted = os.path.relpath(path, root)[:-3].replace(os.sep, ".")
                out[dotted.removesuffix(".__init__")] = path
    return out


def imported(module, node, known, is_package):
    """The package's modules that the import statement ``node`` in
    ``module`` names."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names if alias.name in known]
    base = node.module or ""
    if node.level:                     # relative: from its package, up level - 1
        parts = module.split(".")[:None if is_package else -1]
        parts = parts[:len(parts) - node.level + 1]
        base = ".".join(parts + ([base] if base else []))
    if base not in known:
        return []
    return [f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base
            for alias in node.names]


def import_graph(root=ROOT):
    """{module: {module it imports: [line numbers]}}, imports anywhere."""
    known = modules(root)
    graph = {}
    for module, path in known.items():
        with open(path) as f:
            tree = ast.parse(f.read(), path)
        is_package = path.endswith("__init__.py")
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for target in set(imported(module, node, known, is_package)) - {module}:
                    graph.setdefault(module, {}).setdefault(target, []).append(node.lineno)
    return graph


def cycles(graph):
    """The strongly connected components of more than one module (every
    cycle lies in one), each sorted (Tarjan's algorithm, iterative)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph.get(start, {}))))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, targets = work[-1]
            target = next(targets, None)
            if target is not None:
                if target not in index:
                    index[target] = low[target] = len(index)
                    stack.append(target)
                    on_stack.add(target)
                    work.append((target, iter(sorted(graph.get(target, {})))))
                elif target in on_stack:
                    low[node] = min(low[node], index[target])
                continue
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
    return found


def long_definitions(root=ROOT):
    """{"path:name": lines} of the functions over FUNCTION_LINES and the
    classes over CLASS_LINES, counted from ``def``/``class`` to the last
    line (docstring included, decorators not)."""
    out = {}
    for path in sorted(modules(root).values()):
        with open(path) as f:
            tree = ast.parse(f.read(), path)
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                limit = FUNCTION_LINES
            elif isinstance(node, ast.ClassDef):
                limit = CLASS_LINES
            else:
                continue
            lines = node.end_lineno - node.lineno + 1
            if lines > limit:
                out[f"{os.path.relpath(path, root)}:{node.name}"] = lines
    return out


def describe(graph, component):
    """The imports inside one cycle, a line each."""
    return "\n".join(f"  {a} -> {b} (line {', '.join(map(str, graph[a][b]))})"
                     for a in component for b in sorted(graph.get(a, {})) if b in component)


def test_the_graph_sees_every_kind_of_import(tmp_path):
    """Module level, inside a function, relative, and a name of a package's
    __init__: the checker finds the cycle each makes."""
    package = tmp_path / PACKAGE
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("from vstpetsc.a import x\n")
    (package / "a.py").write_text("def f():\n    from vstpetsc.sub import b\nx = 1\n")
    (package / "sub" / "__init__.py").write_text("")
    (package / "sub" / "b.py").write_text("from ..a import x\nfrom . import c\n")
    (package / "sub" / "c.py").write_text("import vstpetsc.sub.b\nfrom vstpetsc import x\n")
    graph = import_graph(str(tmp_path))
    assert cycles(graph) == [["vstpetsc", "vstpetsc.a", "vstpetsc.sub.b", "vstpetsc.sub.c"]]
    assert graph["vstpetsc.sub.b"] == {"vstpetsc.a": [1], "vstpetsc.sub.c": [2]}


def test_no_import_cycle():
    graph = import_graph()
    found = cycles(graph)
    assert not found, "import cycles:\n" + "\n".join(describe(graph, c) for c in found)


def test_no_long_function_or_class():
    long = long_definitions()
    assert set(long) <= LONG_AS_YET, {k: v for k, v in long.items() if k not in LONG_AS_YET}


if __name__ == "__main__":
    graph = import_graph()
    for component in cycles(graph):
        print("cycle:", " ".join(component))
        print(describe(graph, component))
    for name, lines in long_definitions().items():
        print(f"{lines} lines: {name}" + (" (listed)" if name in LONG_AS_YET else ""))
    sys.exit(0)
