"""What a plane-strain mesh must be before anything is assembled on it
(issue 44): its size within what PETSc's indices and the machine's memory
hold, names that can name HDF5 groups and files, no two nodes at one
point, every cell of positive area and convex.  Each check
raises ValueError with words naming the cell, node or name; the model
turns them into one line naming the key (``mesh.file``, ``mesh.rectangle``,
...).  Pure numpy and scipy, vectorised over all cells."""

import os

import numpy as np

from vstpetsc.input.checker import name_problem

# PETSc here has 32-bit indices: the slab matrix (4 unknowns a node, about
# 150 nonzeros a node) stays below 2^31 nonzeros up to about 1.4e7 nodes
MAX_CELLS = 10 ** 7
# peak memory a node of a run, measured on a 1e6-cell square (bench/README.md,
# GMRES + ILU(0)); LU's factors need more, so this is a lower bound
BYTES_PER_NODE = 8.8e3
FLAT = 1e-10              # a cell's area against its longest side squared
COINCIDENT = 1e-10        # a distance against the mesh's extent


def machine_memory():
    """Bytes of physical memory of this machine."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError):                     # not known: no bound
        return float("inf")


def size_problem(cells, nodes):
    """Why a mesh of ``cells`` cells and about ``nodes`` nodes is too big
    to run here (None if it is not)."""
    if cells > MAX_CELLS:
        return (f"{cells:.3g} cells: at most {MAX_CELLS:.0e} (PETSc's 32-bit indices address "
                "the slab matrix's nonzeros up to 2^31)")
    need, have = nodes * BYTES_PER_NODE, machine_memory()
    if need > have:
        return (f"{cells:.3g} cells, {nodes:.3g} nodes need at least {need / 1e9:.3g} GB "
                f"({BYTES_PER_NODE / 1e3:.3g} kB a node), more than this machine's "
                f"{have / 1e9:.3g} GB")
    return None


def check_names(mesh):
    """ValueError for a region or curve name that cannot name a group."""
    for kind, names in (("region", mesh.region_names), ("curve", tuple(mesh.curves))):
        for name in names:
            problem = name_problem(name)
            if problem:
                raise ValueError(f"the {kind} name {name!r} {problem}")


def check_nodes(mesh):
    """ValueError for two nodes at one point (the mesh cracked there,
    unseen).  (A node in no cell cannot come: PETSc's reader keeps the
    cells' vertices only.)"""
    from scipy.spatial import cKDTree

    x = mesh.coordinates
    extent = float(np.ptp(x, axis=0).max(initial=0.0)) if x.size else 0.0
    close = cKDTree(x).query_pairs(COINCIDENT * extent, output_type="ndarray")
    if close.size:
        a, b = sorted(close[0])
        raise ValueError(f"nodes {a} and {b} lie at one point {_point(x[a])} "
                         f"({len(close)} such pairs): the mesh is cut there; merge duplicate "
                         "nodes (Gmsh: Coherence), or give the cut as an [[interface]]")


def corner_turns(mesh):
    """(ne, 4) the cross products of each cell's consecutive sides at its
    corners (a triangle's fourth is its first's): all positive for a
    convex cell counter-clockwise."""
    cells = np.where(mesh.cells < 0, mesh.cells[:, [0]], mesh.cells)
    corners = np.where(mesh.cells[:, 3:] < 0, 3, 4)
    x = mesh.coordinates[cells]                            # (ne, 4, 2)
    following = np.where(np.arange(4) + 1 < corners, np.arange(1, 5), 0)
    previous = np.where(np.arange(4) > 0, np.arange(-1, 3), corners - 1)
    ahead = np.take_along_axis(x, following[..., None], axis=1) - x
    behind = x - np.take_along_axis(x, previous[..., None], axis=1)
    return behind[..., 0] * ahead[..., 1] - behind[..., 1] * ahead[..., 0]


def check_cells(mesh):
    """ValueError for a cell flat (area below FLAT of its longest side
    squared) or, counter-clockwise, turning clockwise at a corner (a
    bow-tie, a dart)."""
    area = mesh.areas()
    cells = np.where(mesh.cells < 0, mesh.cells[:, [0]], mesh.cells)
    x = mesh.coordinates[cells]
    side = np.linalg.norm(x - np.roll(x, -1, axis=1), axis=2).max(axis=1)
    flat = np.abs(area) <= FLAT * side ** 2
    where = lambda k: _point(mesh.coordinates[mesh.cells[k][mesh.cells[k] >= 0]].mean(axis=0))
    if flat.any():
        k = int(np.argmax(flat))
        raise ValueError(f"cell {k} about {where(k)} has no area ({area[k]:.3g}: its corners "
                         f"on a line, or its sides crossing; {int(flat.sum())} such cells)")
    turns = corner_turns(mesh) * np.sign(area)[:, None]
    corner = np.arange(4) < np.where(mesh.cells[:, 3:] < 0, 3, 4)
    bent = ((turns <= 0) & corner).any(axis=1)
    if bent.any():
        k = int(np.argmax(bent))
        raise ValueError(f"cell {k} about {where(k)} is not convex (its sides cross or turn "
                         f"inward; {int(bent.sum())} such cells)")


def check(mesh, cells=True):
    """Every check of the module, the cheap ones first (``cells``: False
    where the reader checked them already)."""
    problem = size_problem(mesh.ncells, mesh.nnodes)
    if problem:
        raise ValueError(problem)
    check_names(mesh)
    if cells:
        check_cells(mesh)
    check_nodes(mesh)


def _point(x):
    return f"({x[0]:.6g}, {x[1]:.6g})"
