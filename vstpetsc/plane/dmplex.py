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
        raise ValueError(f"{path}: a {dm.getDimension()}-D mesh (plane strain needs 2-D)")
    cells, vertices = _cells(dm)
    coordinates = dm.getCoordinatesLocal().getArray().reshape(-1, dm.getCoordinateDim())[:, :2]
    regions, curves = _groups(dm, cells.shape[0], vertices)
    names = tuple(regions)
    region = np.full(cells.shape[0], -1)
    for i, members in enumerate(regions.values()):
        region[members] = i
    if names and (region < 0).any():
        raise ValueError(f"{path}: {int((region < 0).sum())} cells in no physical surface")
    if not names:
        names, region = ("domain",), np.zeros(cells.shape[0], dtype=int)
    mesh = PlaneMesh(np.ascontiguousarray(coordinates), cells, region, names, curves)
    return _counter_clockwise(mesh)


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


def _groups(dm, ncells, vertices):
    """({region: its cells}, {curve: its edges (m, 2)}) from the labels."""
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
        if cells.size:
            regions[name] = np.unique(cells)
        if edges.size:
            curves[name] = np.array([dm.getCone(e) for e in edges], dtype=np.int64) - v0
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
