"""A PlaneMesh written as a Gmsh 2.2 ASCII file (what vstpetsc.plane.solver.dmplex
reads back through PETSc): its curves as physical curve groups and its
regions as physical surface groups, by name.  For the bundled examples'
meshes (docs/make_example_meshes.py) and the tests.  Pure Python."""

import pathlib

def write_gmsh22(path, m, clockwise=()):
    """``m`` as a Gmsh 2.2 ASCII file (cells listed in ``clockwise`` reversed)."""
    names = list(m.curves) + list(m.region_names)
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    lines += [f'1 {i + 1} "{n}"' for i, n in enumerate(m.curves)]
    lines += [f'2 {len(m.curves) + i + 1} "{n}"' for i, n in enumerate(m.region_names)]
    lines += ["$EndPhysicalNames", "$Nodes", str(m.nnodes)]
    lines += [f"{i + 1} {x!r} {y!r} 0" for i, (x, y) in enumerate(m.coordinates)]
    lines += ["$EndNodes", "$Elements"]
    rows = []
    for i, (name, edges) in enumerate(m.curves.items()):
        rows += [f"1 2 {i + 1} {i + 1} {a + 1} {b + 1}" for a, b in edges]
    for c, (cell, r) in enumerate(zip(m.cells, m.region)):
        nodes = cell[cell >= 0]
        nodes = nodes[::-1] if c in clockwise else nodes
        kind = 3 if nodes.size == 4 else 2
        tag = len(m.curves) + r + 1
        rows.append(f"{kind} 2 {tag} {tag} " + " ".join(str(n + 1) for n in nodes))
    lines += [str(len(rows))] + [f"{k + 1} {row}" for k, row in enumerate(rows)]
    lines += ["$EndElements"]
    path = pathlib.Path(path)
    path.write_text("\n".join(lines) + "\n")
    return path
