"""The slab matrix solved exactly on several ranks by its interiors and a
separator: each rank factors its own part, a small dense Schur complement
joins them (the default beyond the Schwarz default's Courant number up to
stepper.REDUNDANT_UNKNOWNS).

The separator S is the nodes of each rank that couple (in A or A^T) with
a node of a higher rank; the rest of a rank's nodes, its interior I_r,
couple with its own and with S alone.  So with B_r = A restricted to I_r
and S (S last), factored B_r = L U with no pivots (as PETSc's LU) in
nested dissection of I_r,

    A_SI_r A_II_r^-1 A_IS_r = L_SI U_IS,
    Schur = A_SS - sum_r L_SI U_IS        (dense, every rank),

and a solve of A x = b is, on each rank, a forward sweep z = L_II^-1 b_I,
the separator's right-hand side g = b_S - sum_r L_SI z (one allreduce of
|S| numbers), x_S = Schur^-1 g (every rank, the same bits), and a
backward sweep x_I = U_II^-1 (z - U_IS x_S): each rank reads its own
factors once, about half the whole matrix's on two ranks.  The factors
(SuperLU's, scipy) are kept in 4 x 4 node blocks and swept by the
compiled vst_block_sweep (without it, scipy's triangular solves).

On the 1 m rockfill dam's slab matrix (12 942 nodes, cut in two): a
rank's solve 2.3 ms against the whole matrix's PETSc LU 5.6-6.2 ms, its
factorisation 0.3 s against 0.85 s (bench/README.md)."""

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from petsc4py import PETSc

from vstpetsc.native import library
from vstpetsc.petsc import plain_before_petsc_ends

BLOCK = 4


def _node_pattern(rows_csr, nodes):
    """The node pattern (CSR of ones) of a CSR matrix in 4 x 4 blocks."""
    B = sp.csr_matrix(rows_csr).tobsr(blocksize=(BLOCK, BLOCK))
    return sp.csr_matrix((np.ones(B.indices.size), B.indices, B.indptr),
                         shape=(B.shape[0] // BLOCK, nodes))


def _csr_of(sub):
    """scipy CSR of a sequential PETSc matrix."""
    if sub.getType() != "seqaij":
        sub = sub.convert("aij")
    indptr, indices, values = sub.getValuesCSR()
    return sp.csr_matrix((values, indices, indptr), shape=sub.getSize())


def _submatrix(A, rows, cols):
    """scipy CSR of A's dofs of the nodes ``rows`` x ``cols`` (any rank's:
    collective), in their order."""
    def block_is(nodes):
        order = np.argsort(nodes, kind="stable")
        return PETSc.IS().createBlock(BLOCK, nodes[order].astype(PETSc.IntType),
                                      comm=PETSc.COMM_SELF), order
    (ir, r_order), (ic, c_order) = block_is(rows), block_is(cols)
    sub = _csr_of(A.createSubMatrices(ir, ic)[0])
    back = lambda order: (BLOCK * np.argsort(order)[:, None] + np.arange(BLOCK)).ravel()
    return sub[back(r_order)][:, back(c_order)]


def separator(own_rows, first, ranges, comm):
    """(S, interior): the separator's global nodes (sorted, every rank's
    list) and this rank's interior nodes, from this rank's node rows
    ``own_rows`` (CSR over global nodes, row i is node first + i) and every
    rank's node range ``ranges``."""
    mpi = comm.tompi4py()
    rank, size = mpi.Get_rank(), mpi.Get_size()
    starts = np.array([lo for lo, _ in ranges])
    rows = first + np.repeat(np.arange(own_rows.shape[0]), np.diff(own_rows.indptr))
    owner = np.searchsorted(starts, own_rows.indices, side="right") - 1
    mine = np.unique(rows[owner > rank])                 # my nodes coupled upwards
    asked = [np.unique(own_rows.indices[owner == q]) if q < rank else np.zeros(0, int)
             for q in range(size)]                       # lower ranks' nodes I couple to
    told = mpi.alltoall(asked)
    S_mine = np.union1d(mine, np.concatenate(told)).astype(np.int64)
    S = np.sort(np.concatenate(mpi.allgather(S_mine)))
    lo, hi = ranges[rank]
    interior = np.setdiff1d(np.arange(lo, hi), S_mine)
    return S, interior


def _nested_dissection(graph):
    """PETSc's nested dissection order of a symmetric node graph (CSR)."""
    graph = sp.csr_matrix(graph)
    graph.sort_indices()
    m = PETSc.Mat().createAIJ(graph.shape, comm=PETSc.COMM_SELF, csr=(
        graph.indptr.astype(PETSc.IntType), graph.indices.astype(PETSc.IntType),
        np.ones(graph.nnz)))
    order = m.getOrdering("nd")[0].getIndices().copy()
    m.destroy()
    return order


def _sweep_blocks(T, nb, backward):
    """(ptr, cols, off-diagonal blocks, inverse diagonal blocks) of the
    triangular T (first nb block rows and columns) in the order a sweep
    takes its rows (vst_block_sweep: descending for the backward one)."""
    T = sp.csr_matrix(T).tobsr(blocksize=(BLOCK, BLOCK))
    T.sort_indices()
    row = np.repeat(np.arange(nb), np.diff(T.indptr))
    diag = row == T.indices
    dinv = np.linalg.inv(T.data[diag])
    row, col, off = row[~diag], T.indices[~diag], T.data[~diag]
    step = row
    if backward:
        order = np.lexsort((np.arange(row.size), -row))
        row, col, off, dinv = row[order], col[order], off[order], dinv[::-1]
        step = nb - 1 - row
    ptr = np.concatenate([[0], np.cumsum(np.bincount(step, minlength=nb))])
    return (ptr.astype(np.int32), col.astype(np.int32), np.ascontiguousarray(off),
            np.ascontiguousarray(dinv))


class Interior:
    """A rank's factors of B_r = A restricted to its interior (nested
    dissection) and the separator (last): the sweeps over the interior and
    L_SI, U_IS."""

    def __init__(self, B, n):
        lu = spla.splu(sp.csc_matrix(B), permc_spec="NATURAL", diag_pivot_thresh=0.0,
                       options=dict(SymmetricMode=True))
        identity = np.arange(B.shape[0])
        if not ((lu.perm_r == identity).all() and (lu.perm_c == identity).all()):
            raise RuntimeError("the separated slab LU pivoted: use -vst_plane_whole_lu 1")
        L, U = lu.L.tocsr(), lu.U.tocsr()
        del lu
        self.n = n
        self.L_SI, self.U_IS = L[n:, :n].tocsr(), U[:n, n:].tocsr()
        self.lib = library() if PETSc.Options().getBool("vst_native", True) else None
        if self.lib is not None:
            self.lower = _sweep_blocks(L[:n, :n], n // BLOCK, False)
            self.upper = _sweep_blocks(U[:n, :n], n // BLOCK, True)
        else:
            self.lower, self.upper = L[:n, :n].tocsr(), U[:n, :n].tocsr()

    def stored(self):
        """The factor values this rank holds."""
        held = [self.L_SI.nnz, self.U_IS.nnz]
        for f in (self.lower, self.upper):
            held += [f[2].size + f[3].size] if isinstance(f, tuple) else [f.nnz]
        return sum(held)

    def schur_part(self):
        """-L_SI U_IS (dense): this rank's term of the Schur complement."""
        return -(self.L_SI @ self.U_IS).toarray()

    def _sweep(self, blocks, x, backward):
        ptr, col, off, dinv = blocks
        self.lib.vst_block_sweep(ptr.size - 1, backward, ptr.ctypes.data, col.ctypes.data,
                                 off.ctypes.data, dinv.ctypes.data, x.ctypes.data)

    def forward(self, b_I):
        """z = L_II^-1 b_I (kept) and -L_SI z."""
        if self.lib is not None:
            self.z = np.array(b_I, dtype=float)
            self._sweep(self.lower, self.z, 0)
        else:
            self.z = spla.spsolve_triangular(self.lower, b_I, lower=True, unit_diagonal=True)
        return -(self.L_SI @ self.z)

    def backward(self, x_S):
        """x_I = U_II^-1 (z - U_IS x_S)."""
        y = self.z - self.U_IS @ x_S
        if self.lib is None:
            return spla.spsolve_triangular(self.upper, y, lower=False)
        self._sweep(self.upper, y, 1)
        return y


class SeparatedLU:
    """petsc4py's Python PC context: each rank's interior LU and the
    separator's Schur complement (collective apply).  It holds its own
    values: once set up it needs no more of the slab matrix."""

    settled = True

    def setUp(self, pc):
        A = pc.getOperators()[1]
        comm = A.getComm()
        self.mpi = comm.tompi4py()
        lo, hi = (r // BLOCK for r in A.getOwnershipRange())
        nodes = A.getSize()[0] // BLOCK
        ranges = self.mpi.allgather((lo, hi))
        own = _submatrix(A, np.arange(lo, hi), np.arange(nodes))
        pattern = _node_pattern(own, nodes)
        S, interior = separator(pattern, lo, ranges, comm)
        graph = pattern[interior - lo][:, interior]
        interior = interior[_nested_dissection(graph + graph.T)]
        local = np.concatenate([interior, S])
        B = _submatrix(A, local, local)
        n = BLOCK * interior.size
        self.part = Interior(B, n)
        terms = self.part.schur_part()
        self.mpi.Allreduce(terms.copy(), terms)
        self.schur = scipy.linalg.lu_factor(B[n:, n:].toarray() + terms)
        del B
        dofs = lambda nodes: (BLOCK * (nodes[:, None] - lo) + np.arange(BLOCK)).ravel()
        self.interior_rows = dofs(interior)
        owned = (S >= lo) & (S < hi)
        self.s_rows, self.s_owned = dofs(S[owned]), (
            np.flatnonzero(owned)[:, None] * BLOCK + np.arange(BLOCK)).ravel()
        self.g = np.zeros(BLOCK * S.size)

    def apply(self, pc, b, x):
        b = b.getArray(readonly=True)
        g = self.part.forward(b[self.interior_rows])
        g[self.s_owned] += b[self.s_rows]
        self.mpi.Allreduce(g, self.g)
        x_S = scipy.linalg.lu_solve(self.schur, self.g)
        out = np.empty(b.size)
        out[self.interior_rows] = self.part.backward(x_S)
        out[self.s_rows] = x_S[self.s_owned]
        x.setArray(out)


def separated_lu(ksp):
    """Make ``ksp``'s preconditioner a SeparatedLU."""
    pc = ksp.getPC()
    pc.setType("python")
    pc.setPythonContext(SeparatedLU())
    plain_before_petsc_ends(ksp, lambda ksp: ksp.getPC().setType("none"))
