"""House rules of the package (issues 35 and 45), read from its source with
ast: no import cycle among vstpetsc's modules, no function over 60 lines,
no class over 200; the rooms of docs/architecture.md: the 1-D room
(vstpetsc.line) and the 2-D room (vstpetsc.plane) never import each
other, the shared rooms import neither but through vstpetsc.geometry, and
petsc4py is imported only in vstpetsc.petsc and the rooms' solvers.

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


# The rooms (docs/architecture.md): two geometry rooms, and the shared
# rooms and modules that serve both.
GEOMETRY_ROOMS = ("vstpetsc.line", "vstpetsc.plane")
GEOMETRY_PICKER = "vstpetsc.geometry"          # the one shared module that knows both
PETSC_ROOMS = ("vstpetsc.petsc", "vstpetsc.line.solver", "vstpetsc.plane.solver")


def room(module):
    """The geometry room a module lies in, or None for a shared one."""
    for name in GEOMETRY_ROOMS:
        if module == name or module.startswith(name + "."):
            return name
    return None


def inside(module, rooms):
    return any(module == r or module.startswith(r + ".") for r in rooms)


def room_breaches(graph):
    """Every import that crosses the rooms' walls, a line each: one
    geometry room importing the other, or a shared module (but the
    geometry picker) importing a geometry room."""
    out = []
    for module, targets in sorted(graph.items()):
        home = room(module)
        for target, lines in sorted(targets.items()):
            there = room(target)
            if there is None or there == home or module == GEOMETRY_PICKER:
                continue
            what = "the other geometry room" if home else "a geometry room from a shared one"
            out.append(f"{module} -> {target} (line {', '.join(map(str, lines))}): {what}")
    return out


def external_importers(name, root=ROOT):
    """{module: [line numbers]} of the package's modules importing the
    outside package ``name`` (anywhere in them)."""
    out = {}
    for module, path in modules(root).items():
        with open(path) as f:
            tree = ast.parse(f.read(), path)
        for node in ast.walk(tree):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level
                     else [])
            if any(n == name or n.startswith(name + ".") for n in names):
                out.setdefault(module, []).append(node.lineno)
    return out


def petsc_breaches(root=ROOT):
    """Modules importing petsc4py outside the rooms allowed to."""
    return sorted(f"{m} (line {', '.join(map(str, lines))})"
                  for m, lines in external_importers("petsc4py", root).items()
                  if not inside(m, PETSC_ROOMS))


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


def test_the_rooms_checker_sees_every_breach(tmp_path):
    """A geometry room importing the other, a shared module importing a
    room (inside a function too), the geometry picker allowed, and
    petsc4py outside a solver: each found once."""
    package = tmp_path / PACKAGE
    for folder in ("line", "plane/solver", "runner"):
        (package / folder).mkdir(parents=True)
    for init in ("", "line", "plane", "plane/solver", "runner"):
        (package / init / "__init__.py").write_text("")
    (package / "line" / "model.py").write_text("from vstpetsc.plane import mesh\n")
    (package / "plane" / "mesh.py").write_text("import numpy\n")
    (package / "plane" / "solver" / "slab.py").write_text("from petsc4py import PETSc\n")
    (package / "runner" / "loop.py").write_text(
        "def f():\n    from vstpetsc.line import model\n    import petsc4py.PETSc\n")
    (package / "geometry.py").write_text("from vstpetsc.line import model\nfrom vstpetsc.plane import mesh\n")
    graph = import_graph(str(tmp_path))
    assert room_breaches(graph) == [
        "vstpetsc.line.model -> vstpetsc.plane.mesh (line 1): the other geometry room",
        "vstpetsc.runner.loop -> vstpetsc.line.model (line 2): a geometry room from a shared one"]
    assert petsc_breaches(str(tmp_path)) == ["vstpetsc.runner.loop (line 3)"]


def test_the_rooms_keep_their_walls():
    breaches = room_breaches(import_graph()) + petsc_breaches()
    assert not breaches, "imports across the rooms' walls:\n" + "\n".join(breaches)


def test_every_room_is_where_the_architecture_says():
    """The package's folders are the rooms docs/architecture.md draws, and
    each geometry room has the modules vstpetsc.geometry asks of it."""
    package = os.path.join(ROOT, PACKAGE)
    rooms = {name for name in os.listdir(package)
             if os.path.isfile(os.path.join(package, name, "__init__.py"))}
    assert rooms == {"input", "spacetime", "kernels", "materials", "native", "petsc", "runner",
                     "results", "line", "plane"}
    with open(os.path.join(ROOT, "docs", "architecture.md")) as f:
        text = f.read()
    assert all(f"**{room}/**" in text for room in rooms)
    for geometry in GEOMETRY_ROOMS:
        folder = os.path.join(ROOT, *geometry.split("."))
        assert {"parts.py", "schema.py", "layout.py"} <= set(os.listdir(folder))
        assert os.path.isdir(os.path.join(folder, "solver"))


def test_a_run_loads_only_its_own_room(tmp_path):
    """A 1-D run loads no module of the 2-D room but its schema (which
    tells a document's room), and a 2-D run none of the 1-D room: the
    rooms' modules load through vstpetsc.geometry when asked for."""
    import subprocess

    script = """
import sys, vstpetsc
from vstpetsc import bundled
name, other = sys.argv[1:3]
before = set(sys.modules)
case = vstpetsc.Case.from_toml(bundled.path(name))
vstpetsc.run(case.with_value("time.end", 2 * case.dt), output=sys.argv[3], quiet=True)
print(sorted(m for m in set(sys.modules) - before if m.startswith(other)))
"""
    plane_schema = "['vstpetsc.plane', 'vstpetsc.plane.schema']"
    for name, other, expected in (("bar-wall", "vstpetsc.plane", plane_schema),
                                  ("plane-column", "vstpetsc.line", "[]")):
        p = subprocess.run([sys.executable, "-c", script, name, other,
                            str(tmp_path / f"{name}.h5")], capture_output=True, text=True,
                           cwd=ROOT)
        assert p.returncode == 0, p.stderr
        assert p.stdout.strip() == expected, name


def test_the_package_installs_every_room():
    """pyproject.toml installs every package of the house: found by
    setuptools, or each listed (a list went stale once, and a clean
    install failed on a folder that had moved)."""
    import tomllib

    with open(os.path.join(ROOT, "pyproject.toml"), "rb") as f:
        tool = tomllib.load(f)["tool"]["setuptools"]
    packages = {m for m, path in modules().items() if path.endswith("__init__.py")}
    if "packages" in tool and isinstance(tool["packages"], list):
        assert set(tool["packages"]) == packages
    else:
        assert tool["packages"]["find"]["include"] == [f"{PACKAGE}*"]


def test_no_long_function_or_class():
    long = long_definitions()
    assert set(long) <= LONG_AS_YET, {k: v for k, v in long.items() if k not in LONG_AS_YET}


if __name__ == "__main__":
    graph = import_graph()
    for component in cycles(graph):
        print("cycle:", " ".join(component))
        print(describe(graph, component))
    for line in room_breaches(graph) + petsc_breaches():
        print("breach:", line)
    for name, lines in long_definitions().items():
        print(f"{lines} lines: {name}" + (" (listed)" if name in LONG_AS_YET else ""))
    sys.exit(0)
