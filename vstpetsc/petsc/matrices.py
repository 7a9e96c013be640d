"""PETSc matrices from the numpy block bands of :mod:`vstpetsc.slab`, each
rank holding the rows of its nodes n0..n1-1."""

import numpy as np
from petsc4py import PETSc

from vstpetsc import slab


def block_matrix(blocks, nodes, comm, mat_type="baij"):
    """The 2 x 2 block tridiagonal matrix of ``blocks`` (N, 3, 2, 2): BAIJ
    by default (PETSc's unrolled 2 x 2 kernels solve 30 % faster than AIJ
    here), AIJ for solvers that need it (SuperLU_dist)."""
    n0, n1 = nodes
    nloc, nglob = 2 * (n1 - n0), 2 * blocks.shape[0]
    if mat_type == "aij":
        indptr, indices, data = slab.block_rows_csr(blocks, n0, n1)
        mat = PETSc.Mat().createAIJ(size=((nloc, nglob), (nloc, nglob)), bsize=2,
                                    csr=(indptr.astype(PETSc.IntType),
                                         indices.astype(PETSc.IntType), data), comm=comm)
    else:
        indptr, indices, data = slab.block_rows_bcsr(blocks, n0, n1)
        mat = PETSc.Mat().createBAIJ(size=((nloc, nglob), (nloc, nglob)), bsize=2,
                                     csr=(indptr.astype(PETSc.IntType),
                                          indices.astype(PETSc.IntType),
                                          np.ascontiguousarray(data).ravel()), comm=comm)
    mat.assemble()
    return mat


class Increment:
    """The running-sum increment b += G z (three entries a row,
    slab.increment_rows), in PETSc's sliced ELLPACK format where available
    (its products are 15 % faster than AIJ's here).

    On several ranks each rank multiplies its rows with a sequential matrix
    on the ghosted local vector of the DMDA: every row then sums its entries
    left to right as on one rank (PETSc's parallel formats add the
    off-process entries last), so the result does not depend on the ranks.
    """

    def __init__(self, ops, dt, space, b):
        n0, n1 = space.nodes
        indptr, indices, data = slab.increment_rows(ops, dt, n0, n1)
        self.parallel = space.comm.getSize() > 1
        if self.parallel:
            g0 = max(n0 - 1, 0)
            self.local = space.da.createLocalVec()
            cols = self.local.getSize()
            indices = indices - 2 * g0
            self.b = PETSc.Vec().createWithArray(b.getArray(), comm=PETSc.COMM_SELF)
            comm, size = PETSc.COMM_SELF, (2 * (n1 - n0), cols)
        else:
            comm, nglob = space.comm, 2 * ops.m_diag.size
            size = ((2 * (n1 - n0), nglob), (2 * (n1 - n0), nglob))
        mat = PETSc.Mat().createAIJ(size=size, csr=(indptr.astype(PETSc.IntType),
                                                    indices.astype(PETSc.IntType), data),
                                    comm=comm)
        mat.assemble()
        try:
            mat.convert("sell")      # in place
        except PETSc.Error:
            pass
        self.G, self.space = mat, space

    def add_to(self, X, b):
        """b += G X."""
        if not self.parallel:
            self.G.multAdd(X, b, b)
            return
        self.space.da.globalToLocal(X, self.local)
        self.G.multAdd(self.local, self.b, self.b)
