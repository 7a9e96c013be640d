"""The slab solve on several ranks: each rank's LU of its part of the band
grown by ``overlap`` nodes on either side, applied once (restricted
additive Schwarz), written out instead of PETSc's PCASM.

PCASM does the same arithmetic but moves the whole vector through general
index scatters twice a slab (restriction and prolongation) and zeroes its
work vectors: at 1e6 elements on two ranks about 6 of its 13 ms a slab
(``-log_view``: VecScatterBegin, VecSet).  Here the only communication is
the right-hand side at the 2 x ``overlap`` ghost nodes; the owned part is
one contiguous copy in and one out.  Same sub-matrix (the rows and
columns of the grown range), same LU in natural ordering, so the same
answer as ``-pc_type asm -pc_asm_overlap k -sub_pc_type lu`` with natural
ordering (tests/test_parallel.py).
"""

import math

import numpy as np
from petsc4py import PETSc


def grown_range(nodes, nnodes, overlap):
    """(e0, e1): the nodes [n0, n1) grown by ``overlap`` on either side,
    clipped to the mesh."""
    n0, n1 = nodes
    return max(0, n0 - overlap), min(nnodes, n1 + overlap)


class Grown:
    """A right-hand side and a solution over the grown range, in arrays of
    ours, with their sequential PETSc vectors."""

    def __init__(self, size):
        self.b, self.x = np.zeros(size), np.zeros(size)
        self.b_vec, self.x_vec = (PETSc.Vec().createWithArray(a, comm=PETSc.COMM_SELF)
                                  for a in (self.b, self.x))


class OverlapLU:
    """Solves A x = b approximately to rounding (docs/parallel.md) with the
    factors of each rank's grown block of the slab matrix A."""

    def __init__(self, A, space, overlap):
        nnodes = space.da.getSizes()[0]
        self.overlap = overlap
        n0, n1 = space.nodes
        e0, e1 = grown_range(space.nodes, nnodes, overlap)
        grown = PETSc.IS().createStride(2 * (e1 - e0), 2 * e0, 1, comm=PETSc.COMM_SELF)
        block = A.createSubMatrices(grown, grown)[0]
        self.pc = PETSc.PC().create(comm=PETSc.COMM_SELF)
        self.pc.setOperators(block)
        self.pc.setType("lu")
        self.pc.setFactorSolverType("petsc")
        self.pc.setFactorOrdering("natural")
        self.pc.setUp()
        # owned dofs sit at [lo, hi) of the grown arrays; the ghosts around
        self.lo, self.hi = 2 * (n0 - e0), 2 * (n1 - e0)
        # ``bound``: the solver's own b and x are views of its owned part
        # (owned_vectors), so that their solve copies nothing in or out (two
        # passes over the owned vector, 10 % of a slab at 1e6 elements);
        # any other vectors go through ``spare``
        self.bound, self.spare = Grown(2 * (e1 - e0)), Grown(2 * (e1 - e0))
        self.owned = (None, None)
        ghosts = np.r_[2 * e0:2 * n0, 2 * n1:2 * e1].astype(PETSc.IntType)
        places = np.r_[0:self.lo, self.hi:2 * (e1 - e0)].astype(PETSc.IntType)
        template = A.createVecLeft()
        self.ghosts = PETSc.Scatter().create(
            template, PETSc.IS().createGeneral(ghosts, comm=PETSc.COMM_SELF),
            self.bound.b_vec, PETSc.IS().createGeneral(places, comm=PETSc.COMM_SELF))
        self.mpi = space.comm.tompi4py()

    def owned_vectors(self, comm):
        """((b, its array), (x, its array)): global vectors of the
        solver's layout on the owned part of the bound grown arrays; a
        solve of that b into that x copies nothing.  Once per solver."""
        out = []
        for a in (self.bound.b, self.bound.x):
            view = a[self.lo:self.hi]
            out.append((PETSc.Vec().createWithArray(view, size=(view.size, PETSc.DECIDE),
                                                    bsize=2, comm=comm), view))
        self.owned = (out[0][0], out[1][0])
        return out

    def apply(self, b, x):
        """x = the restricted Schwarz solution for b (global vectors)."""
        rhs = self.bound if b is self.owned[0] else self.spare
        sol = self.bound if x is self.owned[1] else self.spare
        self.ghosts.scatter(b, rhs.b_vec, addv=PETSc.InsertMode.INSERT,
                            mode=PETSc.ScatterMode.FORWARD)
        if rhs is self.spare:
            rhs.b[self.lo:self.hi] = b.getArray(readonly=True)
        self.pc.apply(rhs.b_vec, sol.x_vec)
        if sol is self.spare:
            x.getArray()[:] = sol.x[self.lo:self.hi]

    def finite(self, array):
        """Whether a solution (this rank's part ``array``) is finite on
        every rank: an LU solve carries a NaN or Inf anywhere in b or the
        factors into every entry of its backward sweep, so each rank looks
        at its first entry."""
        ok = array.size == 0 or math.isfinite(array[0])
        return self.mpi.allreduce(ok, op=_land())

    def describe(self):
        return (f"restricted additive Schwarz (each rank's LU of its part grown by "
                f"{self.overlap} nodes, applied once)")


def _land():
    from mpi4py import MPI

    return MPI.LAND
