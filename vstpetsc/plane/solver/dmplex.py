"""Meshes through PETSc's DMPlex: a Gmsh file (2.2 or 4.1, ASCII or
binary; PETSc's reader) as a PlaneMesh, its physical surface groups as
regions and its physical curve groups as curves, by name
(``-dm_plex_gmsh_use_regions``: one label a group, named as it).

Cells come counter-clockwise (a clockwise one is reversed: Gmsh keeps
the orientation it was drawn in), vertices numbered as DMPlex numbers
them.  Reading walks the cells once (DMPlex's closure of each, at set-up
only)."""

import numpy as np

from vstpetsc.plane.mesh import PlaneMesh
from vstpetsc.plane.mesh_checks import check_cells

SKIPPED_LABELS = ("celltype", "depth", "Cell Sets", "Face Sets", "Vertex Sets")


def read_gmsh(path):
    """The PlaneMesh of a Gmsh file (ValueError naming what is wrong)."""
    from petsc4py import PETSc

    opts, key = PETSc.Options(), "dm_plex_gmsh_use_regions"
    given = opts.hasName(key)
    opts[key] = None
    try:
        dm = PETSc.DMPlex().createFromFile(str(path), interpolate=True, comm=PETSc.COMM_SELF)
    finally:
        if not given:
            opts.delValue(key)
    if dm.getDimension() != 2:
        raise ValueError(f"a {dm.getDimension()}-D mesh (plane strain needs 2-D)")
    cells, vertices = _cells(dm)
    coordinates = dm.getCoordinatesLocal().getArray().reshape(-1, dm.getCoordinateDim())[:, :2]
    if coordinates.shape[0] != vertices[1] - vertices[0]:
        # PETSc keeps a curved cell's extra nodes as coordinates of its edges
        raise ValueError("cells of higher order (6-node triangles, 8- or 9-node "
                         "quadrilaterals): linear triangles and 4-node quadrilaterals only")
    # the cells first: a bow-tie's sides are not the curves' line elements
    mesh = _counter_clockwise(PlaneMesh(np.ascontiguousarray(coordinates), cells,
                                        np.zeros(cells.shape[0], dtype=int)))
    check_cells(mesh)
    regions, curves = _groups(dm, cells.shape[0], vertices, physical_dimensions(path))
    names = tuple(regions)
    region = np.full(cells.shape[0], -1)
    for i, members in enumerate(regions.values()):
        region[members] = i
    if names and (region < 0).any():
        raise ValueError(f"{int((region < 0).sum())} cells in no physical surface")
    if not names:               # a file without physical surfaces: one region
        names, region = ("domain",), np.zeros(cells.shape[0], dtype=int)
    return PlaneMesh(mesh.coordinates, mesh.cells, region, names, curves)


def _cells(dm):
    """(ne, 4) vertex numbers of each cell in closure order (-1 pads a
    triangle) and the vertex points' range."""
    c0, c1 = dm.getHeightStratum(0)
    v0, v1 = dm.getDepthStratum(0)
    cells = -np.ones((c1 - c0, 4), dtype=np.int64)
    for c in range(c0, c1):
        points = dm.getTransitiveClosure(c)[0]
        corners = points[(points >= v0) & (points < v1)] - v0
        if corners.size not in (3, 4):
            raise ValueError(f"a cell of {corners.size} corners (triangles and "
                             "quadrilaterals only)")
        cells[c - c0, :corners.size] = corners
    return cells, (v0, v1)


def physical_dimensions(path):
    """{name: dimension} of the file's physical groups ($PhysicalNames,
    text in every Gmsh format; {} without)."""
    out, count = {}, None
    with open(path, "rb") as f:
        for raw in f:
            line = raw.strip()
            if count is None:
                if line == b"$PhysicalNames":
                    count = -1
                elif line in (b"$Nodes", b"$Entities", b"$Elements"):
                    return out
                continue
            if line == b"$EndPhysicalNames" or count == 0:
                return out
            if count < 0:
                count = int(line)
                continue
            dim, _, name = line.decode("utf-8", "replace").split(maxsplit=2)
            out[name.strip('"')] = int(dim)
            count -= 1
    return out


def _groups(dm, ncells, vertices, dims):
    """({region: its cells}, {curve: its edges (m, 2)}) from the labels;
    ValueError for a physical curve's line element that is no side of a
    cell (PETSc labels the cell that holds both its nodes instead)."""
    v0, _ = vertices
    e0, e1 = dm.getHeightStratum(1)
    regions, curves = {}, {}
    for i in range(dm.getNumLabels()):
        name = dm.getLabelName(i)
        if name in SKIPPED_LABELS:
            continue
        label = dm.getLabel(name)
        points = np.concatenate([dm.getStratumIS(name, int(v)).getIndices()
                                 for v in label.getValueIS().getIndices()] or [[]]).astype(int)
        cells = points[points < ncells]
        edges = points[(points >= e0) & (points < e1)]
        if cells.size and dims.get(name) == 1:
            raise ValueError(f"the physical curve {name!r} has line elements that are no side "
                             f"of a cell (one crosses cell {cells[0]}): draw curves along the "
                             "cells' edges")
        if cells.size:
            regions[name] = np.unique(cells)
        if edges.size:
            curves[name] = np.array([dm.getCone(e) for e in edges], dtype=np.int64) - v0
    both = set(regions) & set(curves)
    if both:
        raise ValueError(f"the name {sorted(both)[0]!r} is a physical surface's and a "
                         "physical curve's: give them different names")
    return regions, curves


def _counter_clockwise(mesh):
    """The mesh with its clockwise cells reversed."""
    flip = mesh.areas() < 0
    if flip.any():
        tri = flip & (mesh.cells[:, 3] < 0)
        quad = flip & (mesh.cells[:, 3] >= 0)
        mesh.cells[tri, :3] = mesh.cells[tri, 2::-1]
        mesh.cells[quad] = mesh.cells[quad, ::-1]
    return mesh
