"""The plane-strain matrices of a mesh: each cell kind's element matrices
at once (vstpetsc.plane.elements), summed into sparse matrices over the
unknowns (v_x, v_y) interleaved per node; PETSc's AIJ from them.

Materials are per cell (lambda, mu, rho arrays, from the regions)."""

import numpy as np
import scipy.sparse as sp

from vstpetsc.plane import elements


def element_matrices(mesh, lam, mu, rho):
    """{"triangles": (cells, K_e, M_e), "quadrilaterals": ...}: each kind's
    cells (indices) and their consistent element matrices."""
    each = lambda a: np.broadcast_to(np.asarray(a, float), (mesh.ncells,))
    D = elements.elasticity(each(lam), each(mu))
    rho = each(rho)
    out = {}
    for kind, cells, corners, kernel in (
            ("triangles", mesh.triangles, 3, elements.triangle_matrices),
            ("quadrilaterals", mesh.quadrilaterals, 4, elements.quadrilateral_matrices)):
        if cells.size:
            xy = mesh.coordinates[mesh.cells[cells, :corners]]
            out[kind] = (cells, *kernel(xy, D[cells], rho[cells]))
    return out


def dofs(nodes):
    """(n, 2k) the interleaved unknowns of the cells' nodes (n, k)."""
    return (2 * nodes[:, :, None] + np.arange(2)).reshape(nodes.shape[0], -1)


def assemble(mesh, blocks):
    """The (2 nn, 2 nn) CSR sum of element matrices {kind: (cells, Ke)}."""
    rows, cols, vals = [], [], []
    for cells, Ke in blocks:
        d = dofs(mesh.cells[cells, :Ke.shape[1] // 2])
        rows.append(np.repeat(d, d.shape[1], axis=1).ravel())
        cols.append(np.tile(d, (1, d.shape[1])).ravel())
        vals.append(Ke.ravel())
    n = 2 * mesh.nnodes
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(n, n))


def matrices(mesh, lam, mu, rho, mass="averaged"):
    """(M, K) of the mesh, CSR; ``mass`` "consistent", "lumped" or "averaged"."""
    parts = element_matrices(mesh, lam, mu, rho)
    to_mass = elements.MASSES[mass]
    K = assemble(mesh, [(cells, Ke) for cells, Ke, _ in parts.values()])
    M = assemble(mesh, [(cells, to_mass(Me)) for cells, _, Me in parts.values()])
    return M, K


def petsc_matrix(A, comm=None):
    """A CSR matrix as PETSc's AIJ (sequential unless ``comm`` says)."""
    from petsc4py import PETSc

    A = A.tocsr()
    A.sort_indices()
    return PETSc.Mat().createAIJ(A.shape, csr=(A.indptr.astype(PETSc.IntType),
                                               A.indices.astype(PETSc.IntType), A.data),
                                 comm=comm or PETSc.COMM_SELF)
