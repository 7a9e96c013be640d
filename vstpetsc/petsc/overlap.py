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
        # the grown right-hand side and solution, in arrays of ours
        self.b_grown = np.zeros(2 * (e1 - e0))
        self.x_grown = np.zeros(2 * (e1 - e0))
        self.b_vec, self.x_vec = (PETSc.Vec().createWithArray(a, comm=PETSc.COMM_SELF)
                                  for a in (self.b_grown, self.x_grown))
        # owned dofs sit at [lo, hi) of the grown arrays; the ghosts around
        self.lo, self.hi = 2 * (n0 - e0), 2 * (n1 - e0)
        ghosts = np.r_[2 * e0:2 * n0, 2 * n1:2 * e1].astype(PETSc.IntType)
        places = np.r_[0:self.lo, self.hi:self.b_grown.size].astype(PETSc.IntType)
        template = A.createVecLeft()
        self.ghosts = PETSc.Scatter().create(
            template, PETSc.IS().createGeneral(ghosts, comm=PETSc.COMM_SELF),
            self.b_vec, PETSc.IS().createGeneral(places, comm=PETSc.COMM_SELF))
        self.mpi = space.comm.tompi4py()

    def apply(self, b, x):
        """x = the restricted Schwarz solution for b (global vectors)."""
        self.ghosts.scatter(b, self.b_vec, addv=PETSc.InsertMode.INSERT,
                            mode=PETSc.ScatterMode.FORWARD)
        self.b_grown[self.lo:self.hi] = b.getArray(readonly=True)
        self.pc.apply(self.b_vec, self.x_vec)
        x.getArray()[:] = self.x_grown[self.lo:self.hi]

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
