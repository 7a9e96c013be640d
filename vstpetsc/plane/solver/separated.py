"""The slab matrix solved exactly on several ranks by its interiors and a
separator: each rank factors its own part, a small dense Schur complement
joins them (the default beyond the Schwarz default's Courant number up to
stepper.REDUNDANT_UNKNOWNS).

The separator S is, between two ranks whose nodes couple (in A or A^T),
the coupled nodes of the rank with more nodes; the rest of a rank's
nodes, its interior I_r, couple with its own and with S alone.  So with B_r = A restricted to I_r
and S (S last), factored B_r = L U with no pivots (as PETSc's LU) in
nested dissection of I_r,

    A_SI_r A_II_r^-1 A_IS_r = L_SI U_IS = A_SS - L_SS U_SS,
    Schur = A_SS - sum_r L_SI U_IS        (dense, every rank),

and a solve of A x = b is, on each rank, a forward sweep z = L_II^-1 b_I,
the separator's right-hand side g = b_S - sum_r L_SI z (one allreduce of
|S| numbers), x_S = Schur^-1 g (every rank, the same bits), and a
backward sweep x_I = U_II^-1 (z - U_IS x_S): each rank reads its own
factors once, about half the whole matrix's on two ranks.  The factors
(SuperLU's, scipy) are kept in 4 x 4 node blocks by columns and swept
by the compiled vst_column_sweep (native/block_sweep.c; without it, or
with -vst_native 0, scipy's triangular solves).

On the 1 m rockfill dam's slab matrix (12 942 nodes; METIS's two parts,
vstpetsc.plane.solver.partition, the separator 73 nodes; interiors in
METIS's nested dissection) the two ranks' solves at once took 2.3-3.4 ms
(min of 80) against 5.6-6.2 for the whole matrix's PETSc LU on one;
their set-up 0.4-0.9 s a rank (the machine's load) against 0.8-1.1
(docs/parallel.md, bench/README.md "Two ranks on a dam")."""

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from petsc4py import PETSc

from vstpetsc.errors import SolveFailed
from vstpetsc.native import library, metis_order
from vstpetsc.petsc import python_context, python_preconditioner

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
    sub = sub[back(r_order)]
    # the columns renumbered in place (scipy's column pick took 0.1 s a rank)
    new_of = np.empty(sub.shape[1], dtype=sub.indices.dtype)
    new_of[back(c_order)] = np.arange(sub.shape[1])
    sub.indices = new_of[sub.indices]
    sub.has_sorted_indices = False
    return sub


def separator(own_rows, first, ranges, comm):
    """(S, interior): the separator's global nodes (sorted, every rank's
    list) and this rank's interior nodes, from this rank's node rows
    ``own_rows`` (CSR over global nodes, row i is node first + i) and every
    rank's node range ``ranges``.  Between two ranks that couple, the
    separator is the nodes on the side of the one with more nodes (its
    interior shrinks, the two interiors' factors come closer in size)."""
    mpi = comm.tompi4py()
    rank, size = mpi.Get_rank(), mpi.Get_size()
    starts = np.array([lo for lo, _ in ranges])
    count = np.array([hi - lo for lo, hi in ranges])
    # side[r, q]: whether r's nodes next to q's are the separator
    side = (count[:, None] > count[None, :]) | \
        ((count[:, None] == count[None, :]) & (np.arange(size)[:, None] < np.arange(size)))
    rows = first + np.repeat(np.arange(own_rows.shape[0]), np.diff(own_rows.indptr))
    owner = np.searchsorted(starts, own_rows.indices, side="right") - 1
    across = owner != rank
    mine = np.unique(rows[across & side[rank, owner]])     # my nodes on my side
    told = mpi.alltoall([np.unique(own_rows.indices[(owner == q) & ~side[rank, q]])
                         if q != rank else np.zeros(0, int) for q in range(size)])
    S_mine = np.union1d(mine, np.concatenate(told)).astype(np.int64)
    S = np.sort(np.concatenate(mpi.allgather(S_mine)))
    lo, hi = ranges[rank]
    return S, np.setdiff1d(np.arange(lo, hi), S_mine)


ORDERINGS = ("metis", "petsc")


def _nested_dissection(graph, ordering):
    """A nested dissection order of a symmetric node graph (CSR, its
    diagonal ignored): ``ordering`` "metis", METIS's (Debian's libmetis5;
    on the 1 m rockfill dam's halves its factors held 9-15 % fewer values
    than with PETSc's and took 0.26 against 0.36-0.39 s to form), else,
    or without the library, PETSc's."""
    graph = sp.csr_matrix(graph)
    graph.setdiag(0)
    graph.eliminate_zeros()
    graph.sort_indices()
    if graph.shape[0] < 3:
        return np.arange(graph.shape[0])
    order = metis_order(graph) if ordering == "metis" else None
    if order is not None:
        return order
    m = PETSc.Mat().createAIJ(graph.shape, comm=PETSc.COMM_SELF, csr=(
        graph.indptr.astype(PETSc.IntType), graph.indices.astype(PETSc.IntType),
        np.ones(graph.nnz)))
    order = m.getOrdering("nd")[0].getIndices().copy()
    m.destroy()
    return order


def _by_columns(lib, T, columns, rows, backward):
    """vst_column_sweep's blocks of T (CSC: SuperLU's L or U) over its
    first ``columns`` block columns and first ``rows`` block rows, in the
    order the sweep takes them (native/block_sweep.c, vst_block_columns):
    (ptr, rows, blocks, inverse diagonal blocks; the identity for a
    column whose diagonal block lies beyond ``rows``)."""
    indptr, indices = T.indptr.astype(np.int32), T.indices.astype(np.int32)
    data = np.ascontiguousarray(T.data, dtype=float)
    slot = np.full(T.shape[0] // BLOCK, -1, dtype=np.int32)
    ptr = np.zeros(columns + 1, dtype=np.int32)
    call = lambda *out: lib.vst_block_columns(columns, rows, int(backward), indptr.ctypes.data,
                                              indices.ctypes.data, data.ctypes.data,
                                              slot.ctypes.data, *out)
    call(ptr.ctypes.data, None, None, None)
    np.cumsum(ptr, out=ptr)
    row, blocks = np.empty(ptr[-1], dtype=np.int32), np.empty((ptr[-1], BLOCK, BLOCK))
    diag = np.zeros((columns, BLOCK, BLOCK))
    call(ptr.ctypes.data, row.ctypes.data, blocks.ctypes.data, diag.ctypes.data)
    swept = np.arange(columns)
    column = columns - 1 - swept if backward else swept
    has = (column < rows) & diag.any(axis=(1, 2))
    dinv = np.broadcast_to(np.eye(BLOCK), diag.shape).copy()
    # (inverted as the transposes' inverses, transposed back: the bits of
    # the sweep's first form, from scipy's blocks of T^T)
    dinv[has] = np.linalg.inv(diag[has].transpose(0, 2, 1)).transpose(0, 2, 1)
    return ptr, row, blocks, dinv


class Interior:
    """A rank's factors of B_r = A restricted to its interior I (nested
    dissection, n unknowns) and the separator S (last, ns): a vector
    x = (x_I, x_S) is swept forwards by L's columns of I (x_I <- L_II^-1
    x_I, x_S <- x_S - L_SI x_I) and backwards by U's columns over the
    rows of I (x_I <- U_II^-1 (x_I - U_IS x_S)); ``take_schur_part`` gives
    this rank's L_SS U_SS - A_SS = -L_SI U_IS (the trailing block of the
    factors)."""

    def __init__(self, B, n):
        lu = spla.splu(sp.csc_matrix(B), permc_spec="NATURAL", diag_pivot_thresh=0.0,
                       options=dict(SymmetricMode=True))
        identity = np.arange(B.shape[0])
        if not ((lu.perm_r == identity).all() and (lu.perm_c == identity).all()):
            raise SolveFailed("the slab matrix's interior LU met a zero pivot "
                              "(-vst_plane_whole_lu 1 factors the whole matrix instead)")
        L, U = lu.L, lu.U                   # (CSC)
        del lu
        self.n = n
        self.schur_part = L[n:, n:].toarray() @ U[n:, n:].toarray() - B[n:, n:].toarray()
        self.lib = library() if PETSc.Options().getBool("vst_native", True) else None
        if self.lib is not None:
            nodes = B.shape[0] // BLOCK
            self.lower = _by_columns(self.lib, L, n // BLOCK, nodes, False)
            self.upper = _by_columns(self.lib, U, nodes, n // BLOCK, True)
        else:
            self.lower = (L[:n, :n].tocsr(), L[n:, :n].tocsr())
            self.upper = (U[:n, :n].tocsr(), U[:n, n:].tocsr())

    def take_schur_part(self):
        """This rank's term of the Schur complement (given once: not kept)."""
        part, self.schur_part = self.schur_part, None
        return part

    def stored(self):
        """The factor values this rank holds."""
        if self.lib is not None:
            return sum(f[2].size + f[3].size for f in (self.lower, self.upper))
        return sum(f.nnz for pair in (self.lower, self.upper) for f in pair)

    def _sweep(self, blocks, x, backward):
        """x <- the sweep of ``blocks`` over x (n + ns, or (n + ns) x k: k
        at once)."""
        ptr, index, off, dinv = blocks
        pointers = (ptr.ctypes.data, index.ctypes.data, off.ctypes.data, dinv.ctypes.data,
                    x.ctypes.data)
        if x.ndim == 1:
            self.lib.vst_column_sweep(ptr.size - 1, backward, *pointers)
        else:
            self.lib.vst_column_sweep_many(ptr.size - 1, backward, *pointers, x.shape[1])

    def forward(self, x):
        """x = (b_I, b_S) <- (z = L_II^-1 b_I, b_S - L_SI z), in place."""
        if self.lib is not None:
            return self._sweep(self.lower, x, 0)
        L_II, L_SI = self.lower
        x[:self.n] = spla.spsolve_triangular(L_II, x[:self.n], lower=True, unit_diagonal=True)
        x[self.n:] -= L_SI @ x[:self.n]

    def backward(self, x):
        """x = (z, x_S) <- (U_II^-1 (z - U_IS x_S), x_S), in place."""
        if self.lib is not None:
            return self._sweep(self.upper, x, 1)
        U_II, U_IS = self.upper
        x[:self.n] = spla.spsolve_triangular(U_II, x[:self.n] - U_IS @ x[self.n:], lower=False)


class SeparatedLU:
    """petsc4py's Python PC context: each rank's interior LU and the
    separator's Schur complement (collective apply).  It holds its own
    values: once set up it needs no more of the slab matrix."""

    settled = True

    def __init__(self, ordering="metis"):
        self.ordering = ordering            # the interiors' (ORDERINGS)

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
        interior = interior[_nested_dissection(graph + graph.T, self.ordering)]
        local = np.concatenate([interior, S])
        B = _submatrix(A, local, local)
        n = BLOCK * interior.size
        self.part = Interior(B, n)
        terms = self.part.take_schur_part()
        self.mpi.Allreduce(terms.copy(), terms)
        # (one rank: no separator, the interior LU alone)
        self.schur = scipy.linalg.lu_factor(B[n:, n:].toarray() + terms) if S.size else None
        del B
        dofs = lambda nodes: (BLOCK * (nodes[:, None] - lo) + np.arange(BLOCK)).ravel()
        self.interior_rows = dofs(interior)
        owned = (S >= lo) & (S < hi)
        self.separated = BLOCK * S.size
        self.s_rows, self.s_owned = dofs(S[owned]), (
            np.flatnonzero(owned)[:, None] * BLOCK + np.arange(BLOCK)).ravel()

    def apply(self, pc, b, x):
        x.setArray(self.solve_many(b.getArray(readonly=True)))

    def solve_many(self, b):
        """This rank's rows of A^-1 b for its rows ``b`` (n, or n x k: k
        solves at once, each column's the bits of its own solve)
        (collective)."""
        n = self.interior_rows.size
        x = np.zeros((n + self.separated,) + b.shape[1:])
        x[:n] = b[self.interior_rows]
        x[n + self.s_owned] = b[self.s_rows]
        self.part.forward(x)
        g = x[n:].copy()
        self.mpi.Allreduce(g, x[n:])
        if self.schur is not None and x.ndim == 2:
            x[n:] = np.column_stack([scipy.linalg.lu_solve(self.schur, c) for c in x[n:].T])
        elif self.schur is not None:
            x[n:] = scipy.linalg.lu_solve(self.schur, x[n:])
        self.part.backward(x)
        out = np.empty(b.shape)
        out[self.interior_rows] = x[:n]
        out[self.s_rows] = x[n + self.s_owned]
        return out


def separated_lu(ksp, ordering="metis"):
    """Make ``ksp``'s preconditioner a SeparatedLU, its interiors in
    ``ordering`` (ORDERINGS)."""
    python_preconditioner(ksp, SeparatedLU(ordering))


def separated_at_hand(ksp):
    """The SeparatedLU of ``ksp``'s preconditioner, or None."""
    return python_context(ksp, SeparatedLU)
