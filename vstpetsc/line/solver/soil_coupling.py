"""A hysteretic soil in the solver's unknowns (docs/nonlinear-soil.md):
its nodes' unknowns z gathered on every rank, the residual rows W r and
the tangent's element blocks W (dt/h) dQ V, and the LU factors of
A + that tangent."""

import numpy as np
from petsc4py import PETSc


from vstpetsc.line import bands
from vstpetsc.line.solver.space import DofGather


class SoilCoupling:
    """The soil's nodes (every node of a governed element) in the solver's
    space.  ``residual(values)`` of the gathered unknowns gives the rows
    W r (free nodes only: a prescribed node's rows are identities in A)
    and the element blocks; compiled when ``soil.native`` is set."""

    def __init__(self, soil, solver):
        self.soil, self.dt = soil, solver.dt
        nodes = soil.nodes
        dofs = (2 * nodes[:, None] + np.arange(2)).ravel()
        self.gather = DofGather(solver.X, dofs, solver.space.nodes)
        # one rank: the dofs' places in the solver's own arrays
        self.local = self.gather.local if solver.space.comm.getSize() == 1 else None
        self.left = np.searchsorted(nodes, soil.left)
        self.right = self.left + 1
        self.n = nodes.size
        self.free = (~np.isin(nodes, solver.fixed_nodes)).astype(float)[:, None]
        self.held = 1.0 - self.free
        self.any_held = bool(self.held.any())
        self._held()
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

    def tangent_data(self):
        """The tangent's matrix data that the compiled kernel wrote with the
        last residual (None: the factors compute it)."""
        native = self.soil.native
        return None if native is None else native.tangent_data()

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
        if not self.any_held:
            return 0.0
        f = np.zeros((self.held_nodes.size, 2))
        f[self.held_as_left[0]] -= element_forces[self.held_as_left[1]]
        f[self.held_as_right[0]] += element_forces[self.held_as_right[1]]
        v = values.reshape(-1, 2)[self.held_nodes] @ self.V.T
        return float(np.sum(f * v))

    def _held(self):
        """The held nodes (gathered numbers) and, for each element with a
        held node, (the node's place among them, the element), as its left
        and as its right node."""
        self.held_nodes = np.flatnonzero(self.held[:, 0])
        place = -np.ones(self.n, dtype=int)
        place[self.held_nodes] = np.arange(self.held_nodes.size)
        for side, nodes in (("left", self.left), ("right", self.right)):
            el = np.flatnonzero(place[nodes] >= 0)
            setattr(self, f"held_as_{side}", (place[nodes[el]], el))


# an element's four blocks in the tangent: (key, sign), in the order the
# compiled kernel adds them too
SIGNS = (("ll", 1.0), ("lr", -1.0), ("rr", 1.0), ("rl", -1.0))


class TangentFactors:
    """LU factors of A + the soil's tangent, kept and reused until
    :meth:`refresh` is asked; until the first refresh, A's own factors
    (``linear``).  On several ranks every rank factors the whole matrix
    (PETSc's redundant PC), with the one-rank LU's settings."""

    def __init__(self, coupling, solver, laws=None):
        from vstpetsc.line.solver.matrices import block_matrix

        self.linear = solver.linear
        self.laws = laws          # HostedLaws whose blocks join the soil's, or None
        self.fresh = False
        self.blocks = np.zeros((coupling.soil.left.size, 2, 2))     # of the last refresh
        comm = solver.space.comm
        blocks = solver.matrix_blocks()
        n0, n1 = solver.space.nodes
        self.P = block_matrix(blocks, (n0, n1), comm)
        self.lu = self._factors(comm)
        indptr, indices, data = bands.block_rows_bcsr(blocks, n0, n1)
        self.csr = (indptr.astype(PETSc.IntType), indices.astype(PETSc.IntType))
        self.data = np.ascontiguousarray(data)
        self.base = self.data.copy()
        self.at = self._slots(coupling, indptr, indices, n0, n1)
        if laws is not None:
            self.law_at = block_slots(indptr, indices, n0, n1, *laws.block_nodes)
        native = coupling.soil.native
        if native is not None:
            ne = coupling.soil.left.size
            slots, coef = -np.ones((4, ne), dtype=np.int64), np.zeros((4, ne))
            for j, (key, sign) in enumerate(SIGNS):
                mine, slot, free = self.at[key]
                slots[j, mine], coef[j, mine] = slot, sign * free[:, 0, 0]
            native.bind_tangent_data(self.base, slots, coef)

    def _factors(self, comm):
        """The LU PC (prefix ``vst_soil_``): PETSc's own LU in the natural
        order, as A's (a block tridiagonal matrix fills nothing in it);
        on several ranks the same LU of the whole matrix on every rank."""
        from vstpetsc.petsc.options import PREFIX, default

        pc = PETSc.PC().create(comm=comm)
        pc.setOptionsPrefix(PREFIX + "soil_")
        pc.setOperators(self.P, self.P)
        if comm.getSize() == 1:
            pc.setType("lu")
            pc.setFactorSolverType("petsc")
            pc.setFactorOrdering("natural")
        else:
            pc.setType("redundant")
            for key, val in (("redundant_pc_type", "lu"),
                             ("redundant_pc_factor_mat_solver_type", "petsc"),
                             ("redundant_pc_factor_mat_ordering_type", "natural")):
                default(PREFIX + "soil_" + key, val)
        pc.setFromOptions()
        return pc

    @staticmethod
    def _slots(coupling, indptr, indices, n0, n1):
        """{key: (elements, their block's place in this rank's block CSR
        data, the row's free factor)} for the four blocks of each soil
        element (ll: its left node's row and column, lr, rr, rl) in the
        rows this rank holds."""
        gl = coupling.soil.left
        free = coupling.free[:, 0]
        out = {}
        for key, rows, cols, node in (("ll", gl, gl, coupling.left),
                                      ("lr", gl, gl + 1, coupling.left),
                                      ("rr", gl + 1, gl + 1, coupling.right),
                                      ("rl", gl + 1, gl, coupling.right)):
            mine, slot = block_slots(indptr, indices, n0, n1, rows, cols)
            out[key] = (mine, slot, free[node[mine]][:, None, None])
        return out

    def refresh(self, blocks, data=None):
        """Factor A + the tangent of the element ``blocks`` (``data``: its
        block CSR data when the compiled kernel wrote it already)."""
        self.blocks[...] = blocks
        if data is None:
            data = self.data
            data[...] = self.base
            for key, sign in SIGNS:
                mine, slot, free = self.at[key]
                data[slot] += sign * free * blocks[mine]
        if self.laws is not None:      # (a copy: the kernel's data stays its own)
            mine, slot = self.law_at
            data = data.copy()
            data[slot] += self.laws.blocks()[mine]
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


def block_slots(indptr, indices, n0, n1, rows, cols):
    """(which of the blocks (rows, cols) (global nodes) lie in the rows
    n0..n1-1 this rank holds, their places in its block CSR data)."""
    mine = np.flatnonzero((rows >= n0) & (rows < n1))
    slot = np.array([indptr[r - n0] + np.searchsorted(indices[indptr[r - n0]:indptr[r - n0 + 1]], c)
                     for r, c in zip(rows[mine], cols[mine])], dtype=int)
    return mine, slot
