"""PETSc matrices from the numpy block bands of :mod:`vstpetsc.line.bands`, each
rank holding the rows of its nodes n0..n1-1."""

import numpy as np
from petsc4py import PETSc


from vstpetsc.line import bands


def block_matrix(blocks, nodes, comm, mat_type="baij"):
    """The 2 x 2 block tridiagonal matrix of ``blocks`` (N, 3, 2, 2): BAIJ
    by default (PETSc's unrolled 2 x 2 kernels solve 30 % faster than AIJ
    here), AIJ for solvers that need it (SuperLU_dist)."""
    n0, n1 = nodes
    nloc, nglob = 2 * (n1 - n0), 2 * blocks.shape[0]
    if mat_type == "aij":
        indptr, indices, data = bands.block_rows_csr(blocks, n0, n1)
        mat = PETSc.Mat().createAIJ(size=((nloc, nglob), (nloc, nglob)), bsize=2,
                                    csr=(indptr.astype(PETSc.IntType),
                                         indices.astype(PETSc.IntType), data), comm=comm)
    else:
        indptr, indices, data = bands.block_rows_bcsr(blocks, n0, n1)
        mat = PETSc.Mat().createBAIJ(size=((nloc, nglob), (nloc, nglob)), bsize=2,
                                     csr=(indptr.astype(PETSc.IntType),
                                          indices.astype(PETSc.IntType),
                                          np.ascontiguousarray(data).ravel()), comm=comm)
    mat.assemble()
    return mat
