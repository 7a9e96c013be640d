"""The forces of prescribed velocities.  Their rows of the slab matrix are
replaced by v^a = v_h; the force the constraint exerts, integrated against
T_a, is the residual of the original rows at the solution,
Q = A_orig x - (r + F).  It is carried over in the running sum like any
force, so the running right-hand side of those rows stays exact, and its
work enters the energy balance (docs/loads.md section 2)."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.spacetime import slab

from vstpetsc.line import bands


class Reactions:
    """The constrained nodes' original rows (a small matrix B) and their
    held right-hand side."""

    def __init__(self, space, ops, dt, W, V, nodes):
        self.space, self.W, self.V = space, W, V
        self.Winv = np.linalg.inv(W)
        self.carry_m = W @ (slab.CARRY - np.eye(2)) @ self.Winv
        n0, n1 = space.nodes
        nodes = np.unique(np.asarray(nodes, dtype=int))
        own = nodes[(nodes >= n0) & (nodes < n1)]
        self.rows = (2 * (own - n0)[:, None] + np.arange(2)).ravel()
        blocks = bands.slab_matrix(ops, dt, W, V)
        indptr, indices, data = bands.node_rows_csr(blocks, own)
        nrows, total = 2 * own.size, 2 * nodes.size
        self.B = PETSc.Mat().createAIJ(
            size=((nrows, total), (2 * (n1 - n0), 2 * ops.m_diag.size)),
            csr=(indptr.astype(PETSc.IntType), indices.astype(PETSc.IntType), data),
            comm=space.comm)
        self.B.assemble()
        self.q = self.B.createVecLeft()
        self.held = np.zeros(self.rows.size)
        self.Q = np.zeros(self.rows.size)

    def hold(self, arr):
        """Keep W (r + F) of the constrained rows before they are overwritten."""
        self.held[:] = arr[self.rows]

    def solved(self, X):
        """Q (mixed by W) at the slab's solution X (collective)."""
        self.B.mult(X, self.q)
        self.Q[:] = self.q.getArray(readonly=True) - self.held

    def carry(self, arr):
        """Restore the rows' running sum and carry Q over (before b += G z
        is applied to them)."""
        arr[self.rows] = self.held

    def carry_after(self, arr):
        arr[self.rows] -= (self.Q.reshape(-1, 2) @ self.carry_m.T).ravel()

    def work(self, x):
        """sum_a Q^a v^a of the owned constrained nodes (x: local z array)."""
        if not self.rows.size:
            return 0.0
        Q = self.Q.reshape(-1, 2) @ self.Winv.T           # unmixed: int T_a R dt
        v = x[self.rows].reshape(-1, 2) @ self.V.T
        return float(np.sum(Q * v))
