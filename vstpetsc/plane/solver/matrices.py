"""PETSc's matrices of the plane-strain room's CSR matrices, and the slab
matrix in blocks of a node's four unknowns.

The slab's unknowns are 4 i + 2 c + a (node i, component c, time node a:
vstpetsc.spacetime.slab's 2 d + a with d = 2 i + c), so the slab matrix
HM (x) M + dt HC (x) C + dt^2 HK (x) K is, node pair by node pair, the
4 x 4 block sum_X numpy.kron(X_ij, H_X) of the spatial 2 x 2 blocks
X_ij: PETSc's BAIJ of block size 4 stores it with one column index per
16 values (AIJ: one per value), built here from the node blocks without
the Kronecker products' coordinate lists (at 1e6 cells those held 3.5 GB
beside the matrix)."""

import numpy as np
import scipy.sparse as sp
from petsc4py import PETSc

from vstpetsc.spacetime.slab import HC, HK, HM

BLOCK = 4           # a node's unknowns in a slab: (x, y) x two time nodes
ROWS = 1 << 15      # node rows of the slab matrix formed at once


def petsc_matrix(A, comm=None):
    """PETSc's AIJ of a CSR matrix: the whole matrix on one rank, or on
    ``comm`` the rows a rank owns (global columns; local rows = columns)."""
    A = A.tocsr()
    A.sort_indices()
    n, N = A.shape
    return PETSc.Mat().createAIJ(((n, N), (n, N)), comm=comm or PETSc.COMM_SELF, csr=(
        A.indptr.astype(PETSc.IntType), A.indices.astype(PETSc.IntType), A.data))


def node_matrix(A, comm=None):
    """PETSc's BAIJ of block size 2 (a node's x and y) of a spatial CSR
    matrix over interleaved dofs: owned rows, global columns (a quarter
    less memory than its AIJ; its products equal the AIJ's to rounding:
    a row's sums in another order)."""
    B = sp.csr_matrix(A).tobsr(blocksize=(2, 2))
    B.sort_indices()
    n, N = B.shape
    return PETSc.Mat().createBAIJ(((n, N), (n, N)), 2, comm=comm or PETSc.COMM_SELF, csr=(
        B.indptr.astype(PETSc.IntType), B.indices.astype(PETSc.IntType), B.data.ravel()))


def _node_pattern(blocks):
    """The union of BSR matrices' block patterns as a sorted CSR of ones."""
    union = None
    for X in blocks:
        ones = sp.csr_matrix((np.ones(X.indices.size), X.indices, X.indptr),
                             shape=(X.shape[0] // 2, X.shape[1] // 2))
        union = ones if union is None else union + ones
    union.sort_indices()
    return union


def _aligned(X, pattern):
    """(nb, 2, 2) the node blocks of the BSR ``X`` at the blocks of
    ``pattern`` (zeros where X has none)."""
    width = np.int64(pattern.shape[1])
    rows = np.repeat(np.arange(pattern.shape[0], dtype=np.int64), np.diff(pattern.indptr))
    keys = rows * width + pattern.indices
    mine = np.repeat(np.arange(X.shape[0] // 2, dtype=np.int64), np.diff(X.indptr)) * width \
        + X.indices
    out = np.zeros((keys.size, 2, 2))
    out[np.searchsorted(keys, mine)] = X.data
    return out


def slab_terms(M, C, K, dt):
    """[(spatial matrix, its time matrix)] of the slab matrix, in
    vstpetsc.spacetime.slab.sparse_slab_matrix's order of summation."""
    return [(M, HM), (K, dt * dt * HK)] + ([(C, dt * HC)] if C is not None else [])


def block_rows(terms, first, stop):
    """(pattern, values (nb, 4, 4)) of the slab matrix's node rows [first,
    stop) (of the spatial matrices' rows: CSR over interleaved dofs): the
    union of the spatial node blocks as a CSR of ones (global node
    columns), each block the same sum as sparse_slab_matrix's, in its
    order."""
    bsr = [X[2 * first:2 * stop].tobsr(blocksize=(2, 2)) for X, _ in terms]
    for X in bsr:
        X.sort_indices()
    pattern = _node_pattern(bsr)
    values = np.zeros((pattern.indices.size, 2, 2, 2, 2))      # (block, c, a, e, b)
    for X, (_, H) in zip(bsr, terms):
        blocks = _aligned(X, pattern)
        for c in range(2):
            for e in range(2):         # (n, 2, 2) temporaries: not the (n, 16) product
                values[:, c, :, e, :] += blocks[:, c, e, None, None] * H
    return pattern, values.reshape(-1, BLOCK, BLOCK)


def slab_matrix(M, C, K, dt, comm, rows=ROWS):
    """PETSc's BAIJ (block size 4) of the slab matrix: a rank's owned rows,
    formed ``rows`` node rows at a time (its structure first, then its
    values), so that no array of the whole matrix's values exists beside
    PETSc's."""
    terms = slab_terms(M, C, K, dt)
    nodes = M.shape[0] // 2
    chunks = [(a, min(a + rows, nodes)) for a in range(0, nodes, rows)]
    patterns = [_node_pattern([X[2 * a:2 * b].tobsr(blocksize=(2, 2)) for X, _ in terms])
                for a, b in chunks]
    indptr = np.concatenate([[0]] + [p.indptr[1:] for p in patterns])
    indptr[1:] += np.repeat(np.cumsum([0] + [p.indices.size for p in patterns[:-1]]),
                            [b - a for a, b in chunks])
    n, N = BLOCK * nodes, 2 * M.shape[1]
    A = PETSc.Mat().createBAIJ(((n, N), (n, N)), BLOCK, comm=comm)
    A.setPreallocationCSR((indptr.astype(PETSc.IntType), np.concatenate(
        [p.indices for p in patterns] or [np.zeros(0, int)]).astype(PETSc.IntType)))
    del patterns
    first = A.getOwnershipRange()[0] // BLOCK
    for a, b in chunks:
        pattern, values = block_rows(terms, a, b)
        rows_of = np.repeat(np.arange(first + a, first + b), np.diff(pattern.indptr))
        A.setValuesBlockedRCV(rows_of.astype(PETSc.IntType)[:, None],
                              pattern.indices.astype(PETSc.IntType)[:, None],
                              values.reshape(-1, BLOCK * BLOCK))
    A.assemble()
    return A


def slab_operator(M, C, K, dt, comm):
    """The slab matrix of a run: slab_matrix (BAIJ), or with
    ``-vst_plane_blocks 0`` the AIJ of vstpetsc.spacetime.slab's sparse
    form (one value, one index: a third more memory)."""
    from vstpetsc.spacetime.slab import sparse_slab_matrix

    if PETSc.Options().getBool("vst_plane_blocks", True):
        return slab_matrix(M, C, K, dt, comm)
    return petsc_matrix(sparse_slab_matrix(M, C, K, dt), comm)
