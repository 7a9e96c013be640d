"""The plane-strain matrices of a mesh: each cell kind's element matrices
at once (vstpetsc.plane.elements), summed into sparse matrices over the
unknowns (v_x, v_y) interleaved per node (PETSc's AIJ of them:
vstpetsc.plane.solver.matrices).

Materials are per cell (lambda, mu, rho arrays, from the regions)."""

import numpy as np
import scipy.sparse as sp

from vstpetsc.plane import elements


def element_matrices(mesh, lam, mu, rho, within=None):
    """{"triangles": (cells, K_e, M_e), "quadrilaterals": ...}: each kind's
    cells (indices) and their consistent element matrices; with
    ``within`` = (first, stop), of the cells in that range only."""
    each = lambda a: np.broadcast_to(np.asarray(a, float), (mesh.ncells,))
    lam, mu, rho = each(lam), each(mu), each(rho)
    out = {}
    for kind, cells, corners, kernel in (
            ("triangles", mesh.triangles, 3, elements.triangle_matrices),
            ("quadrilaterals", mesh.quadrilaterals, 4, elements.quadrilateral_matrices)):
        if within is not None:
            cells = cells[(cells >= within[0]) & (cells < within[1])]
        if cells.size:
            xy = mesh.coordinates[mesh.cells[cells, :corners]]
            D = elements.elasticity(lam[cells], mu[cells])
            out[kind] = (cells, *kernel(xy, D, rho[cells]))
    return out


def dofs(nodes):
    """(n, 2k) the interleaved unknowns of the cells' nodes (n, k)."""
    return (2 * nodes[:, :, None] + np.arange(2)).reshape(nodes.shape[0], -1)


def assemble(mesh, blocks, number=None, owned=None, size=None):
    """The CSR sum of element matrices [(cells, Ke)]: (2 nn, 2 nn); or, on
    one rank of several, with ``number`` each local node's global number,
    the rows of the global nodes ``owned`` = (first, stop) in global
    columns, (2 owned, 2 size)."""
    rows, cols, vals = [np.zeros(0, int)], [np.zeros(0, int)], [np.zeros(0)]
    first, stop = (0, mesh.nnodes) if owned is None else owned
    for cells, Ke in blocks:
        nodes = mesh.cells[cells, :Ke.shape[1] // 2]
        d = dofs(nodes if number is None else number[nodes])
        r = np.repeat(d, d.shape[1], axis=1).ravel()
        keep = (r >= 2 * first) & (r < 2 * stop)
        rows.append(r[keep] - 2 * first)
        cols.append(np.tile(d, (1, d.shape[1])).ravel()[keep])
        vals.append(Ke.ravel()[keep])
    shape = (2 * (stop - first), 2 * (mesh.nnodes if size is None else size))
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=shape)


def matrices(mesh, lam, mu, rho, mass="averaged"):
    """(M, K) of the mesh, CSR; ``mass`` "consistent", "lumped" or "averaged"."""
    parts = element_matrices(mesh, lam, mu, rho)
    to_mass = elements.MASSES[mass]
    K = assemble(mesh, [(cells, Ke) for cells, Ke, _ in parts.values()])
    M = assemble(mesh, [(cells, to_mass(Me)) for cells, _, Me in parts.values()])
    return M, K


def identity_rows(A, rows, first):
    """A (CSR, owned rows; global columns from ``first``) with ``rows``
    made identities (held unknowns): the held rows' entries dropped and a
    1 put on their diagonals, on the CSR arrays at once (LIL's row
    assignment took 5 s for 6.7e4 unknowns; this, milliseconds)."""
    A = sp.csr_matrix(A)
    rows = np.asarray(rows, dtype=int)
    if not rows.size:
        return A
    held = np.zeros(A.shape[0], dtype=bool)
    held[rows] = True
    counts = np.diff(A.indptr)
    keep = ~np.repeat(held, counts)
    counts[held] = 0
    kept = sp.csr_matrix((A.data[keep], A.indices[keep], np.r_[0, np.cumsum(counts)]),
                         shape=A.shape)
    ones = sp.csr_matrix((np.ones(rows.size), (rows, first + rows)), shape=A.shape)
    return sp.csr_matrix(kept + ones)
