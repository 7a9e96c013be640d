"""The slab matrix's product from the spatial matrices, without the slab
matrix (``-vst_plane_matrix_free``).

A = HM (x) M + dt HC (x) C + dt^2 HK (x) K over the slab unknowns
2 d + a (spatial dof d, time node a): with x's two time nodes' velocities
v_b = x[b::2], (A x)[2 d + a] = sum_X sum_b H_X[a, b] (X v_b)[d], that is
the (n, 2) array of A x equals Q H, where Q's columns are the products
X v_b (two a spatial matrix) and H stacks the time matrices' transposes.
So a product is one copy of x into two columns, two sparse products a
spatial matrix (M and K in 2 x 2 node blocks hold a quarter of the slab
matrix's values each: read twice, as much memory traffic as the slab
matrix's own product) and one small dense product.  Held dofs keep their
identity rows (``rows``: the slab matrix's local rows made identities).

What it is for: the slab matrix is assembled to set up the preconditioner
(ILU(0), LU, Schwarz blocks: each holds its own values) and let go then,
so a run holds a slab matrix's worth less (at 1e6 cells 1.17 GB:
bench/plane_memory.py) for a slower product.  Its products equal the
assembled matrix's to rounding (sums in another order), not bit for
bit."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.petsc import plain_before_petsc_ends
from vstpetsc.plane.solver.matrices import node_matrix, slab_terms


class SlabProduct:
    """PETSc's Python-matrix context of A x (collective on ``comm``):
    ``terms`` [(spatial PETSc matrix, its 2 x 2 time matrix times dt's
    power)], the rows of ``rows`` identities."""

    def __init__(self, terms, rows, comm):
        first = terms[0][0]
        n, N = first.getSizes()[0]
        self.sizes = ((2 * n, 2 * N), (2 * n, 2 * N))
        self.rows = np.asarray(rows, dtype=int)
        self.matrices = [X for X, _ in terms]
        # H[2 t + b, a] = H_t[a, b]: (A x)(d, a) = sum_(t, b) Q[d, 2 t + b] H[2 t + b, a]
        self.H = np.concatenate([np.asarray(H, dtype=float).T for _, H in terms])
        self.v = np.zeros((n, 2), order="F")
        self.Q = np.zeros((n, 2 * len(terms)), order="F")
        vec = lambda column: PETSc.Vec().createWithArray(column, size=(n, N), comm=comm)
        self.v_vecs = [vec(self.v[:, b]) for b in range(2)]
        self.q_vecs = [vec(self.Q[:, k]) for k in range(self.Q.shape[1])]

    def mult(self, mat, x, y):
        xs = x.getArray(readonly=True)
        self.v[...] = xs.reshape(-1, 2)
        for t, X in enumerate(self.matrices):
            for b in range(2):
                X.mult(self.v_vecs[b], self.q_vecs[2 * t + b])
        out = y.getArray()
        np.matmul(self.Q, self.H, out=out.reshape(-1, 2))
        out[self.rows] = xs[self.rows]
        y.stateIncrease()          # written through the array: PETSc's cached norms go


def slab_product(terms, rows, comm):
    """The Python matrix of SlabProduct(terms, rows, comm), assembled."""
    context = SlabProduct(terms, rows, comm)
    A = PETSc.Mat().createPython(context.sizes, context=context, comm=comm)
    A.setUp()
    plain_before_petsc_ends(A, lambda A: A.setType("shell"))
    return A


def run_operators(A, spatial, springs, dt, rows, first, moving, comm):
    """(operator, preconditioner's matrix, operator without identity rows
    or None) of a run's slab: ``A`` the assembled slab matrix (with the
    pairs' closed springs), ``spatial`` its node matrices (M, C or None,
    K), ``rows`` the held dofs' local slab rows (the rank's first node
    ``first``), ``moving``: whether held dofs move (their reactions' work
    needs the free rows' product).  Assembled (the default): A itself,
    its rows made identities (a copy kept before for the free product);
    with ``-vst_plane_matrix_free``: products from the spatial matrices
    (and ``springs``' node matrix), A only for the preconditioner."""
    assembled = not matrix_free()
    free = A.duplicate(copy=True) if moving and assembled else None
    A.zeroRows((4 * first + rows).astype(PETSc.IntType), diag=1.0)
    if assembled:
        return A, A, free
    M, C, K = spatial
    terms = slab_terms(M, C, K, dt)
    if springs is not None:             # with K's time matrix (slab_terms: M, K, then C)
        terms.append((node_matrix(springs, comm), terms[1][1]))
    operator = slab_product(terms, rows, comm)
    return operator, A, slab_product(terms, [], comm) if moving else None


def matrix_free():
    """``-vst_plane_matrix_free``: a slab's products from the spatial
    matrices (default: the assembled slab matrix's)."""
    return PETSc.Options().getBool("vst_plane_matrix_free", False)
