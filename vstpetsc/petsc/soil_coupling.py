"""A hysteretic soil in the solver's unknowns (docs/nonlinear-soil.md):
its nodes' unknowns z gathered on every rank, the residual rows W r and
the tangent's element blocks W (dt/h) dQ V, and the LU factors of
A + that tangent."""

import numpy as np
from petsc4py import PETSc

from vstpetsc import slab
from vstpetsc.petsc.space import DofGather


class SoilCoupling:
    """The soil's nodes (every node of a governed element) in the solver's
    space.  ``residual(values)`` of the gathered unknowns gives the rows
    W r (free nodes only: a prescribed node's rows are identities in A)
    and the element blocks; compiled when ``soil.native`` is set."""

    def __init__(self, soil, solver, fixed_nodes):
        self.soil, self.dt = soil, solver.dt
        nodes = soil.nodes
        dofs = (2 * nodes[:, None] + np.arange(2)).ravel()
        self.gather = DofGather(solver.X, dofs, solver.space.nodes)
        # one rank: the dofs' places in the solver's own arrays
        self.local = self.gather.local if solver.space.comm.getSize() == 1 else None
        self.left = np.searchsorted(nodes, soil.left)
        self.right = self.left + 1
        self.n = nodes.size
        self.free = (~np.isin(nodes, fixed_nodes)).astype(float)[:, None]
        self.held = 1.0 - self.free
        self.V, self.W = solver.V, solver.W
        self.scale = (self.dt / soil.h)[:, None]            # D_b = dt (v_r^b - v_l^b) / h
        if soil.native is not None:
            soil.native.bind_residual(self.left, self.scale[:, 0], self.free[:, 0],
                                      self.V, self.W, self.n)

    def residual(self, values, tangent=True):
        """(rows W r (2n,), blocks (ne, 2, 2) or None, D (ne, 2), Q (ne, 2))
        at the gathered unknowns ``values``."""
        if self.soil.native is not None:
            return self.soil.native.residual(values, self.dt, tangent)
        D = self.increments(values)
        Q, dQ = self.soil.slab(D[:, 0], D[:, 1], self.dt, tangent)
        blocks = self.W @ (self.scale[:, :, None] * dQ) @ self.V if tangent else None
        return self.rows(Q), blocks, D, Q

    def increments(self, values):
        """D (ne, 2) from the gathered unknowns (z basis, per node)."""
        v = values.reshape(-1, 2) @ self.V.T
        return (v[self.right] - v[self.left]) * self.scale

    def node_forces(self, element_forces):
        """Per node (n, 2), velocity basis, from per-element (ne, 2) forces
        on the right node (the left node takes their negative; a node is
        the left node of one element at most, and the right of one)."""
        rows = np.zeros((self.n, 2))
        rows[self.left] -= element_forces
        rows[self.right] += element_forces
        return rows

    def rows(self, element_forces):
        """W-mixed rows of the free nodes, in gathered order."""
        return ((self.node_forces(element_forces) * self.free) @ self.W.T).ravel()

    def tangent_rows(self, blocks, values):
        """The tangent's rows for the gathered direction ``values`` (z)."""
        z = values.reshape(-1, 2)
        f = np.einsum("eab,eb->ea", blocks, z[self.right] - z[self.left])
        rows = np.zeros((self.n, 2))
        rows[self.left] -= f
        rows[self.right] += f
        return (rows * self.free).ravel()

    def support_work(self, element_forces, values):
        """The work of the supports that hold prescribed nodes against these
        forces over the slab: sum_a f^a v^a at those nodes (the reactions of
        the linear rows do not see them)."""
        if not self.held.any():
            return 0.0
        v = values.reshape(-1, 2) @ self.V.T
        return float(np.sum(self.node_forces(element_forces) * self.held * v))


class TangentFactors:
    """LU factors of A + the soil's tangent (one rank), kept and reused
    until :meth:`refresh` is asked; until the first refresh, and on
    several ranks, A's own factors (``linear``)."""

    def __init__(self, coupling, solver, ops, fixed_nodes):
        self.linear = solver.linear
        self.fresh = False
        self.blocks = np.zeros((coupling.soil.left.size, 2, 2))     # of the last refresh
        self.P = None
        if solver.space.comm.getSize() > 1:
            return
        from vstpetsc.petsc.matrices import block_matrix

        fixed = (2 * np.asarray(fixed_nodes, dtype=int)[:, None] + np.arange(2)).ravel()
        blocks = slab.impose_dirichlet(slab.slab_matrix(ops, solver.dt, solver.W, solver.V),
                                       fixed, 1.0)
        n0, n1 = solver.space.nodes
        self.P = block_matrix(blocks, (n0, n1), solver.space.comm)
        self.lu = PETSc.PC().create(comm=solver.space.comm)
        self.lu.setType("lu")
        self.lu.setOperators(self.P, self.P)
        indptr, indices, data = slab.block_rows_bcsr(blocks, n0, n1)
        self.csr = (indptr.astype(PETSc.IntType), indices.astype(PETSc.IntType))
        self.data = np.ascontiguousarray(data)
        self.base = self.data.copy()
        gl = coupling.soil.left
        slot = lambda row, col: indptr[row] + np.searchsorted(
            indices[indptr[row]:indptr[row + 1]], col)
        # where each soil element's four blocks sit in the block CSR data
        self.at = {key: np.array([slot(r, c) for r, c in pairs], dtype=int)
                   for key, pairs in (("ll", zip(gl, gl)), ("lr", zip(gl, gl + 1)),
                                      ("rr", zip(gl + 1, gl + 1)), ("rl", zip(gl + 1, gl)))}
        self.lf = coupling.free[coupling.left, 0][:, None, None]
        self.rf = coupling.free[coupling.right, 0][:, None, None]

    @property
    def refreshable(self):
        return self.P is not None

    def refresh(self, blocks):
        """Factor A + the tangent of the element ``blocks``."""
        if self.P is None:
            return
        self.blocks[...] = blocks
        data, at = self.data, self.at
        data[...] = self.base
        left, right = self.lf * blocks, self.rf * blocks
        data[at["ll"]] += left
        data[at["lr"]] -= left
        data[at["rr"]] += right
        data[at["rl"]] -= right
        self.P.setValuesBlockedCSR(*self.csr, data.ravel())
        self.P.assemble()
        self.lu.setUp()
        self.fresh = True

    def solve(self, r, y):
        if self.fresh:
            self.lu.apply(r, y)
        else:
            self.linear.solve(r, y)

    def apply(self, pc, r, y):
        """As a Python PC."""
        self.solve(r, y)
