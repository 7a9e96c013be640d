"""A plane-strain mesh distributed over the ranks by PETSc's DMPlex, and
its matrices assembled in parallel.

DMPlex partitions the cells (with an overlap of one cell, so that each
rank holds every cell around the vertices it owns) and numbers the
vertices globally, each rank owning a contiguous range.  A rank computes
the element matrices of all its cells at once (vstpetsc.plane.elements)
and keeps the entries of the rows it owns: every such row is then whole,
and the rank's rows go to PETSc's parallel AIJ in one CSR call (no loop
over cells, no communication in the assembly).  The unknowns are
(v_x, v_y) of each vertex in DMPlex's global numbering.

Cells of one kind (createFromCellList takes one corner count): the
generated rectangle; a mixed Gmsh file comes through DMPlex's own reader
(next step)."""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from petsc4py import PETSc

from vstpetsc.plane import assembly
from vstpetsc.plane.dmplex import _cells
from vstpetsc.plane.mesh import PlaneMesh


@dataclass
class LocalMesh:
    """What a rank holds: its cells (those it owns first, then the
    overlap), their vertices' coordinates, each local vertex's global
    number, the rank's range of owned global vertices."""

    mesh: PlaneMesh
    global_vertex: np.ndarray
    owned: np.ndarray
    start: int
    stop: int
    size: int
    comm: object


def distribute(mesh, comm, overlap=1):
    """The LocalMesh of each rank from ``mesh`` (read on rank 0; ignored
    elsewhere) with DMPlex's partition."""
    rank = comm.getRank()
    corners = 4 if mesh.quadrilaterals.size else 3
    if mesh.triangles.size and mesh.quadrilaterals.size:
        raise ValueError("a mixed mesh cannot yet be distributed from cell lists")
    cells = mesh.cells[:, :corners].astype(PETSc.IntType) if rank == 0 else \
        np.zeros((0, corners), dtype=PETSc.IntType)
    coords = mesh.coordinates if rank == 0 else np.zeros((0, 2))
    dm = PETSc.DMPlex().createFromCellList(2, cells, coords, interpolate=True, comm=comm)
    if comm.getSize() > 1:
        dm.distribute(overlap=overlap)
    local, _ = _cells(dm)
    xy = dm.getCoordinatesLocal().getArray().reshape(-1, 2)
    numbers = dm.getVertexNumbering().getIndices()
    owned = numbers >= 0
    global_vertex = np.where(owned, numbers, -numbers - 1)
    counts = comm.tompi4py().allgather(int(owned.sum()))
    start = int(sum(counts[:rank]))
    lm = PlaneMesh(np.ascontiguousarray(xy), local, np.zeros(local.shape[0], dtype=int))
    return LocalMesh(lm, global_vertex, owned, start, start + counts[rank], sum(counts), comm)


def owned_rows(local, blocks):
    """The rank's rows (its owned vertices' dofs) of the sum of element
    matrices {(cells, Ke)}, as CSR (2 owned, 2 size) in global columns."""
    rows, cols, vals = [], [], []
    g = local.global_vertex
    for cells, Ke in blocks:
        nodes = local.mesh.cells[cells, :Ke.shape[1] // 2]
        d = assembly.dofs(g[nodes])
        r = np.repeat(d, d.shape[1], axis=1).ravel()
        keep = (r >= 2 * local.start) & (r < 2 * local.stop)
        rows.append(r[keep] - 2 * local.start)
        cols.append(np.tile(d, (1, d.shape[1])).ravel()[keep])
        vals.append(Ke.ravel()[keep])
    n = 2 * (local.stop - local.start)
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(n, 2 * local.size))


def parallel_matrix(local, csr):
    """PETSc's parallel AIJ of a rank's CSR rows."""
    csr.sort_indices()
    n, N = csr.shape[0], csr.shape[1]
    return PETSc.Mat().createAIJ(((n, N), (n, N)), csr=(
        csr.indptr.astype(PETSc.IntType), csr.indices.astype(PETSc.IntType), csr.data),
        comm=local.comm)


def matrices(local, lam, mu, rho, mass="averaged"):
    """(M, K) as parallel AIJ on the ranks' owned rows."""
    from vstpetsc.plane import elements

    parts = assembly.element_matrices(local.mesh, lam, mu, rho)
    to_mass = elements.MASSES[mass]
    K = owned_rows(local, [(cells, Ke) for cells, Ke, _ in parts.values()])
    M = owned_rows(local, [(cells, to_mass(Me)) for cells, _, Me in parts.values()])
    return parallel_matrix(local, M), parallel_matrix(local, K)
