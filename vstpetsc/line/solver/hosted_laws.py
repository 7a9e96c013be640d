"""Contact pairs and Coulomb friction inside a hysteretic soil's Newton
(docs/nonlinear-soil.md, "A yielding column with interfaces").

A case with a ``shear_law`` and ``[[contact]]`` pairs solves one system a
slab,

    F(X) = A X - b + W r(X) + E WE P f(P^T VE E^T X) = 0,

the soil's rows W r (vstpetsc.line.solver.soil_coupling) and the laws' rows
(vstpetsc.line.solver.newton, ``Full``) together, by the soil's Newton on all
unknowns.  Its tangent adds to the soil's the laws' blocks
WE P f'(y) P^T VE on their dofs E.  The nodes of a pair are neighbours in
the mesh (vstpetsc.line.model) and so are their shear twins, so every law block
lies in A's block-tridiagonal pattern: the factors of A + soil + laws are
the soil's Newton's with a few more blocks added, and no step needs
anything beyond them.

The laws' own bookkeeping (their terms carried into the next slab, the
work each energy term takes, the restart state) stays with the LawSolver.
"""

import numpy as np


class HostedLaws:
    """The laws of ``law_solver`` (a LawSolver) as rows and tangent blocks
    of the soil's Newton on ``solver``'s unknowns."""

    def __init__(self, law_solver, solver):
        self.owner = law_solver
        self.laws = law_solver.laws
        self.c = law_solver.coupling
        self.dt = solver.dt
        nodes = self.laws.nodes
        k = self.laws.size
        self.jac = np.zeros((k, k))           # d rows / d z on E at the last evaluation
        self.kept = np.zeros((k, k))          # the blocks the factors hold (a restart's)
        self.y = np.zeros(self.laws.reduced)  # the coordinates of the last evaluation
        # the 2 x 2 blocks (row node, column node) of E x E in A's pattern
        i, j = np.meshgrid(np.arange(nodes.size), np.arange(nodes.size), indexing="ij")
        near = np.abs(nodes[i] - nodes[j]) <= 1
        self.block_index = (i[near], j[near])
        self.block_nodes = (nodes[i[near]], nodes[j[near]])
        far = (self.laws.P @ self.laws.P.T).reshape(nodes.size, 2, nodes.size, 2)
        if np.any(far.transpose(0, 2, 1, 3)[~near]):
            raise ValueError("a law couples nodes that are not neighbours")
        self.local = self.c.local
        self.acting = False
        # y = R0 z_E and the rows U f on E (the compiled Newton's products)
        self.R0 = self.c.R0
        self.U = self.c.WE @ self.laws.P
        self.native = None          # the laws in the compiled Newton (native/hosted_laws.py)

    def start(self, slab_index):
        """Before the slab's Newton: the laws' start, and the last slab's
        terms taken out of the law-free solution (the predictor)."""
        self.laws.start_slab(self.dt, (slab_index - 1) * self.dt)
        if self.owner.acted:
            self.owner.influence.subtract(self.owner.f)

    def rows(self, X, tangent, array=None):
        """The laws' rows on E (W-mixed) at X (``array``: X's numpy array,
        one rank); with ``tangent`` their blocks too."""
        z = self.c.gather(X) if array is None else np.take(array, self.local)
        self.y = self.R0 @ z
        self.acting = self.laws.evaluate(self.y)
        if tangent:
            self.jac[...] = self.U @ self.laws.jac @ self.R0
        return self.U @ self.laws.f

    def add(self, F, rows, array=None):
        """F += the rows (``array``: F's numpy array, one rank)."""
        if array is None:
            self.c.gather.add_rows(F, rows)
        else:
            array[self.local] += rows

    def tangent_rows(self, z):
        """The laws' tangent applied to the gathered direction z on E."""
        return self.jac @ z

    def blocks(self):
        """The law blocks (n, 2, 2) of the last evaluation in the order of
        ``block_nodes``; kept as the factors' (for a restart)."""
        self.kept[...] = self.jac
        i, j = self.block_index
        n = self.jac.shape[0] // 2
        return self.jac.reshape(n, 2, n, 2).transpose(0, 2, 1, 3)[i, j]

    def restore_blocks(self, kept):
        """The blocks the factors held when the run was saved (jac and
        kept both, as at that refresh)."""
        self.jac[...] = kept.reshape(self.jac.shape)
        self.kept[...] = self.jac

    def compile(self, lib):
        """The laws' evaluation in the compiled Newton (its struct)."""
        from vstpetsc.line.native.hosted_laws import CompiledLaws

        self.native = CompiledLaws(lib, self)
        return self.native.s

    def converged(self):
        """The slab's Newton converged with the laws' last evaluation at its
        solution: their terms and work to the LawSolver."""
        if self.native is not None:
            self.acting = self.native.finish()
        self.owner.took(self.y, self.acting)
