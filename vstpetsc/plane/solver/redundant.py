"""The whole slab matrix factored on every rank: the preconditioner of a
slab on several ranks beyond the Schwarz default's Courant number (as
PETSc's PCREDUNDANT, written out so that its factors are at hand).

Each rank holds the whole matrix (MatCreateRedundantMatrix, one rank a
copy) and its LU (PETSc's, nested dissection), and an application
gathers the right-hand side to every rank, solves there and keeps the
rank's rows: the one-rank solve on every rank, repeatable bit for bit.
With the factors at hand a rank also solves alone: the interfaces'
coupling columns (vstpetsc.plane.solver.newton_steps.Coupling), each a
solve with an unknown's unit load, are dealt to the ranks."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.petsc import python_context, python_preconditioner


class WholeOnEveryRank:
    """petsc4py's Python PC context: every rank's LU of the whole matrix
    (holding its own values: ``settled``)."""

    settled = True

    def setUp(self, pc):
        A = pc.getOperators()[1]
        self.whole = A.getRedundantMatrix(A.getComm().getSize())
        self.ksp = PETSc.KSP().create(comm=self.whole.getComm())
        self.ksp.setOperators(self.whole)
        self.ksp.setType("preonly")
        self.ksp.getPC().setType("lu")
        self.ksp.getPC().setFactorOrdering("nd")
        self.ksp.setUp()
        self.gather, self.b = PETSc.Scatter.toAll(A.createVecLeft())
        self.x = self.b.duplicate()
        self.rows = slice(*A.getOwnershipRange())

    def apply(self, pc, b, x):
        self.gather.scatter(b, self.b, addv=PETSc.InsertMode.INSERT,
                            mode=PETSc.ScatterMode.FORWARD)
        self.ksp.solve(self.b, self.x)
        x.setArray(self.x.getArray(readonly=True)[self.rows])

    def solve_alone(self, index, values):
        """This rank's solve (not collective) of the load ``values`` at the
        global unknowns ``index``: the whole solution."""
        self.b.zeroEntries()
        self.b.setValues(np.asarray(index, dtype=PETSc.IntType), values,
                         addv=PETSc.InsertMode.ADD)
        self.b.assemble()
        self.ksp.solve(self.b, self.x)
        return self.x.getArray(readonly=True).copy()


def whole_on_every_rank(ksp):
    """Make ``ksp``'s preconditioner a WholeOnEveryRank."""
    python_preconditioner(ksp, WholeOnEveryRank())


def factors_at_hand(ksp):
    """The WholeOnEveryRank of ``ksp``'s preconditioner, or None."""
    return python_context(ksp, WholeOnEveryRank)
