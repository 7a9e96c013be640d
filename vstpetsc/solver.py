"""The slab solver on PETSc: a 1-D DMDA over all nodes (2 dof per node), the
constant slab matrix A factored once per run, and a SNES for slabs with
active contact.

The unknowns and the rows are mixed per node (slab.recurrence: unknowns
z = dt/2 (v^2 - v^1, v^1 + v^2), rows by W) so that the right-hand side is a
running sum: a slab without contact costs one solve with A's factors, one
product with a sparse matrix of three entries per row (b += G z) and one
vector sum (u += z_2); the state (u, v) is formed only for output.  A below
is that transformed slab matrix, X the unknowns z, and the contact kernels,
which work in (v^1, v^2), see them through the per-node transforms VE, WE.

Per slab: one solve with A's factors gives the contact-free solution; if no
pair's gap goes negative anywhere in the slab for it, that is the answer (it
satisfies the full nonlinear equations exactly).  Otherwise Newton (SNES)
starts from it.  Its Jacobian differs from A only on the few pair dofs E:
J = A + E C E^T with a small dense block C, so every Newton step is solved
exactly by a Woodbury update of A's factors (one solve plus k axpys, with
Z = A^{-1} E computed once), and A is never refactored.

``formFunction`` and ``formJacobian`` only unwrap vectors and call the numpy
kernels of :mod:`vstpetsc.contact`.  Every rank evaluates every pair from an
all-gather of the pair dofs, so all ranks take the same decisions.

Options: the linear solver reads the usual ``-ksp_*``/``-pc_*`` options, the
Newton solver ``-snes_*`` (its inner KSP has the prefix ``newton_``), and
``-vst_fd_jacobian`` replaces the hand-written contact tangent by central
differences of the residual (a cross-check; slow).
"""

import numpy as np
from petsc4py import PETSc

from vstpetsc import slab
from vstpetsc.contact import contact_integrals


class SolveFailed(RuntimeError):
    """The nonlinear or linear solve of a slab did not converge."""


def _reason_name(cls, code):
    for name in dir(cls):
        if not name.startswith("_") and getattr(cls, name) == code:
            return name
    return str(code)


def newton_snes(comm, function, F, jacobian, J, exact_inverse, rtol, dm=None):
    """A Newton SNES whose linear step is one application of an exact
    inverse (a Python PC; its KSP has the prefix newton_).  Defaults are set
    here, then the options database has the last word."""
    snes = PETSc.SNES().create(comm=comm)
    if dm is not None:
        snes.setDM(dm)
    snes.setType("newtonls")
    snes.setFunction(function, F)
    snes.setJacobian(jacobian, J, J)
    snes.setTolerances(rtol=rtol, atol=1e-50, stol=1e-14, max_it=30)
    ksp = snes.getKSP()
    ksp.appendOptionsPrefix("newton_")
    ksp.setType("preonly")
    ksp.getPC().setType("python")
    ksp.getPC().setPythonContext(exact_inverse)
    snes.setFromOptions()
    return snes


class SlabSolver:
    """Assembles and solves the slab equations of one run (constant dt).

    Parameters
    ----------
    layout : vstpetsc.mesh.Layout
    dt : float
    dirichlet_dofs : array of global dof numbers with prescribed velocity.
    pairs : list of vstpetsc.contact.ContactPair
    comm : PETSc communicator
    ownership : optional node counts per rank (forces the DMDA layout).
    """

    def __init__(self, layout, dt, dirichlet_dofs, pairs, comm=PETSc.COMM_WORLD,
                 ownership=None):
        self.dt = dt
        self.pairs = pairs
        self.da = PETSc.DMDA().create(
            dim=1, sizes=(layout.nnodes,), dof=2, stencil_width=1, comm=comm,
            ownership_ranges=None if ownership is None else (tuple(ownership),))
        self.da.setUp()
        (n0, n1), = self.da.getRanges()
        self.nodes = (n0, n1)
        dirichlet_dofs = np.asarray(dirichlet_dofs, dtype=int)
        d = dirichlet_dofs
        if d.size % 2 or (d[0::2] % 2).any() or not np.array_equal(d[1::2], d[0::2] + 1):
            raise ValueError("Dirichlet dofs must come as both dofs of a node")
        self.mat_type = PETSc.Options().getString("vst_mat_type", "baij")
        if self.mat_type not in ("baij", "aij"):
            raise ValueError(f"-vst_mat_type: 'baij' or 'aij', got {self.mat_type!r}")
        # Unknowns per node z = V^{-1} (v^1, v^2), rows mixed by W, so that the
        # right-hand side is a running sum (slab.recurrence): per slab one
        # solve, one sparse product and one vector sum, no state update.
        self.W, self.V, _, _ = slab.recurrence(dt)
        self.Vinv = np.linalg.inv(self.V)
        self.WT = self.W @ slab.CARRY                     # W T
        self.carry = self.W @ (slab.CARRY - np.eye(2)) @ np.linalg.inv(self.W)
        self.A = self._matrix(slab.impose_dirichlet(
            slab.slab_matrix(layout, dt, self.W, self.V), dirichlet_dofs, 1.0))
        self.R = self._matrix(slab.rhs_operator(layout, dt, self.W))
        self.G = self._increment_matrix(layout, dt)
        self.Y = self.da.createGlobalVec()      # (u, v) per node, for input and output
        self.X = self.da.createGlobalVec()      # slab unknowns z per node
        self.b = self.X.duplicate()             # W r: the running right-hand side
        self.F = self.X.duplicate()
        self.u = np.zeros(n1 - n0)              # displacement of the owned nodes
        self._loads = None                      # (local dofs, -W T f) of the open slab
        self._dirichlet = (None, None, None)    # (dofs, owned, local dofs) last seen
        self.its = (0, 0)
        self.linear_its = 0
        self._setup_pairs()
        self._setup_solvers()

    # -- assembly ----------------------------------------------------------
    def _matrix(self, blocks, diagonal_only=False):
        """A block (2 x 2) sparse matrix from the blocks of the owned nodes:
        BAIJ by default (PETSc's unrolled 2x2 kernels solve 30 % faster than
        AIJ here); -vst_mat_type aij for solvers that need AIJ (SuperLU_dist)."""
        n0, n1 = self.nodes
        nloc, nglob = 2 * (n1 - n0), 2 * blocks.shape[0]
        if self.mat_type == "aij":
            if diagonal_only:
                full = np.zeros((blocks.shape[0], 3, 2, 2))
                full[:, 1] = blocks
                blocks = full
            indptr, indices, data = slab.block_rows_csr(blocks, n0, n1)
            mat = PETSc.Mat().createAIJ(size=((nloc, nglob), (nloc, nglob)), bsize=2,
                                        csr=(indptr.astype(PETSc.IntType),
                                             indices.astype(PETSc.IntType), data),
                                        comm=self.da.getComm())
            mat.assemble()
            return mat
        if diagonal_only:
            nodes = np.arange(n0, n1)
            indptr, indices, data = np.arange(n1 - n0 + 1), nodes, blocks[n0:n1]
        else:
            indptr, indices, data = slab.block_rows_bcsr(blocks, n0, n1)
        mat = PETSc.Mat().createBAIJ(size=((nloc, nglob), (nloc, nglob)), bsize=2,
                                     csr=(indptr.astype(PETSc.IntType),
                                          indices.astype(PETSc.IntType),
                                          np.ascontiguousarray(data).ravel()),
                                     comm=self.da.getComm())
        mat.assemble()
        return mat

    def _increment_matrix(self, layout, dt):
        """The running-sum increment (three entries a row) in PETSc's sliced
        ELLPACK format where available: its products are 15 % faster than
        AIJ's here."""
        n0, n1 = self.nodes
        indptr, indices, data = slab.increment_rows(layout, dt, n0, n1)
        nloc, nglob = 2 * (n1 - n0), 2 * layout.nnodes
        mat = PETSc.Mat().createAIJ(size=((nloc, nglob), (nloc, nglob)),
                                    csr=(indptr.astype(PETSc.IntType),
                                         indices.astype(PETSc.IntType), data),
                                    comm=self.da.getComm())
        mat.assemble()
        try:
            mat.convert("sell")      # in place
        except PETSc.Error:
            pass
        return mat

    def _setup_pairs(self):
        n0, n1 = self.nodes
        P = len(self.pairs)
        nodes = np.zeros((P, 2), dtype=int)
        signs = np.zeros((P, 2))
        for i, p in enumerate(self.pairs):
            nodes[i, :len(p.nodes)] = p.nodes
            nodes[i, len(p.nodes):] = p.nodes[0]      # a wall pair: padding with sign 0
            signs[i, :len(p.nodes)] = p.signs
        self.pair_signs = signs
        self.pair_g0 = np.array([p.g0 for p in self.pairs])
        self.pair_w = np.array([p.penalty for p in self.pairs])
        self.pair_power = np.array([p.formulation == "power" for p in self.pairs], bool)
        padded = (2 * nodes[..., None] + np.arange(2)).ravel()         # (P, 2 nodes, 2 dofs)
        # E: the distinct pair dofs; `slot` maps the padded entries onto them.
        edofs, self.slot = np.unique(padded, return_inverse=True)
        self.edofs = edofs.astype(PETSc.IntType)
        self.eowned = (edofs >= 2 * n0) & (edofs < 2 * n1)
        self.elocal = edofs[self.eowned] - 2 * n0
        k = edofs.size
        self.gathered = PETSc.Vec().createSeq(k, comm=PETSc.COMM_SELF)
        iset = PETSc.IS().createGeneral(self.edofs, comm=PETSc.COMM_SELF)
        self.pair_scatter = PETSc.Scatter().create(self.X, iset, self.gathered, None)
        # E holds both dofs of every pair node: the per-node transforms act
        # within it.  Pair values x_E = VE z_E; contact rows enter as WE r.
        self.VE = np.kron(np.eye(k // 2), self.V)
        self.WE = np.kron(np.eye(k // 2), self.W)
        self.pair_u = np.zeros(k)        # u of the pair nodes, at their even dofs
        self.gn = np.zeros(P)
        self.C = np.zeros((k, k))        # contact block of the Jacobian on E (z space)
        self.contact_rhs = np.zeros(k)   # W r_c of the last slab
        self.has_pairs = P > 0

    def _gather(self, vec):
        """Values of vec at the pair dofs E, on every rank."""
        self.pair_scatter.scatter(vec, self.gathered, addv=PETSc.InsertMode.INSERT,
                                  mode=PETSc.ScatterMode.FORWARD)
        return self.gathered.getArray(readonly=True).copy()

    def _contact(self, X):
        """Kernel evaluation of all pairs at iterate X: (G, W, active)."""
        return self._contact_values(self.VE @ self._gather(X))

    def _contact_values(self, ve):
        """Kernel evaluation from the velocities at the pair dofs E."""
        v = ve[self.slot].reshape(-1, 2, 2)
        d = np.einsum("pk,pka->pa", self.pair_signs, v)
        return contact_integrals(self.gn, d[:, 0], d[:, 1], self.dt, self.pair_power)

    def contact_residual(self, G):
        """The contact part of the residual on the dofs E: R_{n_k}^a += -c_k w G_a."""
        vals = -(self.pair_signs * self.pair_w[:, None])[:, :, None] * G[:, None, :]
        return np.bincount(self.slot, vals.ravel(), minlength=self.edofs.size)

    def contact_block(self, W):
        """Its derivative C on E: dR_{n_k}^a / dv_{n_l}^b = c_k c_l w W_ab."""
        c = self.pair_signs
        block = (c[:, :, None, None, None] * c[:, None, None, :, None]
                 * self.pair_w[:, None, None, None, None] * W[:, None, :, None, :])
        slot = self.slot.reshape(-1, 2, 2)
        rows = np.broadcast_to(slot[:, :, :, None, None], block.shape)
        cols = np.broadcast_to(slot[:, None, None, :, :], block.shape)
        k = self.edofs.size
        return np.bincount((rows * k + cols).ravel(), block.ravel(),
                           minlength=k * k).reshape(k, k)

    def _unit(self, e, j):
        """e = the unit vector of pair dof number j (index into E)."""
        e.zeroEntries()
        if self.eowned[j]:
            e.setValue(self.edofs[j], 1.0)
        e.assemble()
        return e

    # -- solvers -----------------------------------------------------------
    def _setup_solvers(self):
        comm = self.da.getComm()
        # The linear solver of the slab matrix (options without prefix).
        ksp = PETSc.KSP().create(comm=comm)
        ksp.setOperators(self.A, self.A)
        ksp.setType("preonly")
        ksp.setTolerances(rtol=1e-12, atol=1e-50, max_it=1000)
        pc = ksp.getPC()
        if comm.getSize() > 1:
            # Measured at 1e6 elements on 2 ranks (bench/parallel.md): PETSc's LU
            # of the whole matrix on every rank beats MUMPS 20x and block Jacobi
            # 3x, and gives the one-rank solution bit for bit.
            pc.setType("redundant")
            opts = PETSc.Options()
            for key, val in (("redundant_pc_type", "lu"),
                             ("redundant_pc_factor_mat_solver_type", "petsc"),
                             ("redundant_pc_factor_mat_ordering_type", "natural")):
                if not opts.hasName(key):
                    opts.setValue(key, val)
        else:
            pc.setType("lu")
            pc.setFactorSolverType("petsc")
            pc.setFactorOrdering("natural")   # the block band is already optimal
        ksp.setFromOptions()       # the command line wins over the defaults above
        ksp.setUp()                # factors A, once per run
        self.ksp, self.pc = ksp, pc
        self.direct = ksp.getType() == "preonly"
        self.serial_direct = self.direct and comm.getSize() == 1
        opts = PETSc.Options()
        self.fd_jacobian = opts.getBool("vst_fd_jacobian", False)
        self.newton = opts.getString("vst_newton", "condensed")
        if self.newton not in ("condensed", "full"):
            raise ValueError(f"-vst_newton: 'condensed' or 'full', got {self.newton!r}")
        if self.newton == "condensed":
            self.condensed = _Condensed(self)
            self.snes = self.condensed.snes
            if self.has_pairs:
                self._setup_woodbury()
            ksp.viewFromOptions("-ksp_view")
            return
        # Full-space Newton: J = A + E C E^T as a shell, solved exactly by
        # the Woodbury PC on top of the linear solver.
        J = PETSc.Mat().createPython(self.A.getSizes(), context=_Jacobian(self), comm=comm)
        J.setUp()
        self.J = J
        self.snes = newton_snes(comm, self.formFunction, self.F, self.formJacobian, J,
                                _Woodbury(self), rtol=1e-10, dm=self.da)
        if self.has_pairs:
            self._setup_woodbury()
        ksp.viewFromOptions("-ksp_view")

    def _setup_woodbury(self):
        """Z = A^{-1} E and S = E^T Z, once per run."""
        e = self.X.duplicate()
        self.Z = []
        for j in range(self.edofs.size):
            z = self.X.duplicate()
            self._linear_solve(self._unit(e, j), z)
            self.Z.append(z)
        self.S = np.array([self._gather(z) for z in self.Z]).T.copy()
        self.S_velocity = self.VE @ self.S @ self.WE     # E^T A^{-1} E in (v^1, v^2)
        self.eye = np.eye(self.edofs.size)

    def describe(self):
        """One line naming the linear solver actually in use."""
        pc = self.pc
        what = pc.getType()
        if what in ("lu", "cholesky", "ilu", "icc"):
            what = f"{what} ({pc.getFactorSolverType()})"
        elif what == "redundant":
            inner = PETSc.Options().getString("redundant_pc_type", "lu")
            what = f"redundant ({inner} of the whole matrix on every rank)"
        return f"KSP {self.ksp.getType()}, PC {what}; Newton: SNES {self.snes.getType()}"

    def formFunction(self, snes, X, F):
        self.A.mult(X, F)
        F.axpy(-1.0, self.b)
        if self.has_pairs:
            G, _, _ = self._contact(X)
            F.getArray()[self.elocal] += (self.WE @ self.contact_residual(G))[self.eowned]

    def formJacobian(self, snes, X, J, P):
        if self.fd_jacobian:
            self.C = self._fd_contact_block(X)
            return
        _, W, _ = self._contact(X)
        self.C = self.WE @ self.contact_block(W) @ self.VE

    def _fd_contact_block(self, X):
        """C by central differences of formFunction in the pair dofs."""
        k = self.edofs.size
        C = np.zeros((k, k))
        Xp, Fp, Fm, e = X.copy(), self.F.duplicate(), self.F.duplicate(), X.duplicate()
        h = 1e-7 * max(1.0, X.norm(PETSc.NormType.INFINITY))
        for j in range(k):
            self._unit(e, j)
            cols = []
            for sign, out in ((1.0, Fp), (-1.0, Fm)):
                X.copy(Xp)
                Xp.axpy(sign * h, e)
                self.formFunction(self.snes, Xp, out)
                cols.append(self._gather(out))
            self.A.mult(e, Fp)
            C[:, j] = (cols[0] - cols[1]) / (2 * h) - self._gather(Fp)
        return C

    def rhs(self, forces, dirichlet):
        """Add the nodal force integrals of the slab to the running b and set
        the prescribed velocities.

        ``forces`` and ``dirichlet`` are (dofs, values) pairs of global dof
        numbers with their values in the velocity basis; entries not owned
        here are skipped.  Prescribed dofs come as both dofs of a node.
        """
        n0, n1 = self.nodes
        arr = self.b.getArray()
        self._loads = None
        dofs, vals = forces
        if dofs.size:
            nodes, per = _per_node(dofs, vals)
            own = (nodes >= n0) & (nodes < n1)
            idx = (2 * (nodes[own] - n0)[:, None] + np.arange(2)).ravel()
            arr[idx] += (per[own] @ self.W.T).ravel()
            self._loads = (idx, -(per[own] @ self.WT.T).ravel())   # for advance()
        dofs, vals = dirichlet
        if dofs.size:
            if dofs is not self._dirichlet[0]:      # the same dofs every slab
                own = (dofs >= 2 * n0) & (dofs < 2 * n1)
                self._dirichlet = (dofs, own, dofs[own] - 2 * n0)
            _, own, local = self._dirichlet
            arr[local] = (vals.reshape(-1, 2) @ self.Vinv.T).ravel()[own]

    def solve(self, slab_index):
        """Solve the slab for the current b; returns (newton its, linear its)."""
        if self.has_pairs:   # g^n = g0 - sum_k c_k u_k^n
            u = self.pair_u[self.slot].reshape(-1, 2, 2)[:, :, 0]
            self.gn = self.pair_g0 - np.einsum("pk,pk->p", self.pair_signs, u)
        self.linear_its = 0
        self._linear_solve(self.b, self.X, slab_index)
        newton = 0
        self.impulse = np.zeros(len(self.pairs))
        if self.has_pairs:
            self.contact_rhs[:] = 0.0
        if self.has_pairs and self._contact(self.X)[2].any():
            self.C[:] = 0.0
            if self.newton == "condensed":
                self.condensed.solve(self.X)
            else:
                self.snes.solve(None, self.X)
            reason = self.snes.getConvergedReason()
            if reason <= 0:
                raise SolveFailed(f"slab {slab_index}: SNES did not converge "
                                  f"({_reason_name(PETSc.SNES.ConvergedReason, reason)}"
                                  f" after {self.snes.getIterationNumber()} Newton "
                                  "iterations)")
            newton = self.snes.getIterationNumber()
            G, _, _ = self._contact(self.X)
            self.contact_rhs[:] = self.WE @ self.contact_residual(G)
            self.impulse = -self.pair_w * G.sum(axis=1)
        if not self._finite(self.X):
            raise SolveFailed(f"slab {slab_index}: the solution is not finite")
        self.its = (newton, self.linear_its)
        return self.its

    def _finite(self, X):
        """Whether X is finite.  On one rank its first entry says it: an LU
        solve carries a NaN or Inf anywhere in b or the factors into every
        entry of the backward sweep (0 * NaN is NaN), so no pass over X."""
        if not self.serial_direct:
            return np.isfinite(X.norm())
        x = X.getArray(readonly=True)
        return x.size == 0 or np.isfinite(x[0])

    def _linear_solve(self, b, x, slab_index=None):
        if self.direct:
            # KSPSolve of KSPPREONLY would first zero x (measured: 7 % of
            # a solve at 1e6 elements) and then apply the PC: do the latter.
            self.pc.apply(b, x)
            self.linear_its += 1
            return
        self.ksp.solve(b, x)
        reason = self.ksp.getConvergedReason()
        if reason < 0:
            where = f"slab {slab_index}: " if slab_index is not None else ""
            raise SolveFailed(f"{where}linear solve did not converge "
                              f"({_reason_name(PETSc.KSP.ConvergedReason, reason)})")
        self.linear_its += max(1, self.ksp.getIterationNumber())

    def advance(self):
        """Close the slab: b += G z (the running sum) minus the force terms,
        u += z_2 (slab.recurrence)."""
        # u first: the end of the backward sweep left z in cache
        np.add(self.u, self.X.getArray(readonly=True)[1::2], out=self.u)
        self.G.multAdd(self.X, self.b, self.b)
        if self._loads is not None:
            idx, corr = self._loads
            self.b.getArray()[idx] += corr
            self._loads = None
        if self.has_pairs:
            self.pair_u[0::2] += self._gather(self.X)[1::2]
            if self.contact_rhs.any():
                corr = (self.contact_rhs.reshape(-1, 2) @ self.carry.T).ravel()
                self.b.getArray()[self.elocal] += corr[self.eowned]

    def set_state(self, u, v):
        """Start from displacements u and velocities v (global node arrays):
        b = W R (u, v)."""
        n0, n1 = self.nodes
        y = self.Y.getArray().reshape(-1, 2)
        y[:, 0], y[:, 1] = u[n0:n1], v[n0:n1]
        self.R.mult(self.Y, self.b)
        self.u[:] = u[n0:n1]
        self._loads = None
        if self.has_pairs:
            self.pair_u[0::2] = u[self.edofs[0::2] // 2]

    def set_rhs_state(self, b):
        """Continue from a running right-hand side saved by rhs_state()
        (global array), after set_state: the restart is then bit for bit."""
        n0, n1 = self.nodes
        self.b.getArray()[:] = b[2 * n0:2 * n1]

    def _to_rank0(self, vec):
        if not hasattr(self, "_to_zero"):
            self._nat = self.da.createNaturalVec()
            self._to_zero, self._zero = PETSc.Scatter.toZero(self._nat)
        self.da.globalToNatural(vec, self._nat)
        self._to_zero.scatter(self._nat, self._zero, addv=PETSc.InsertMode.INSERT,
                              mode=PETSc.ScatterMode.FORWARD)
        if self.da.getComm().getRank() != 0:
            return None
        return self._zero.getArray(readonly=True).copy()

    def gather_state(self):
        """(u, v) of all nodes on rank 0 (None elsewhere); v = v^2 of the
        last slab."""
        y = self.Y.getArray().reshape(-1, 2)
        y[:, 0] = self.u
        y[:, 1] = self.X.getArray(readonly=True).reshape(-1, 2) @ self.V[1]
        y = self._to_rank0(self.Y)
        return None if y is None else (y[0::2].copy(), y[1::2].copy())

    def rhs_state(self):
        """The running right-hand side of all dofs on rank 0 (None
        elsewhere), between slabs."""
        return self._to_rank0(self.b)


def _per_node(dofs, vals):
    """Nodes of global dofs and their values as (nnodes, 2) arrays."""
    nodes, inv = np.unique(dofs // 2, return_inverse=True)
    per = np.zeros((nodes.size, 2))
    np.add.at(per, (inv, dofs % 2), vals)
    return nodes, per


class _Jacobian:
    """Shell matrix y = (A + E C E^T) x for the current contact block C."""

    def __init__(self, solver):
        self.s = solver

    def mult(self, mat, x, y):
        s = self.s
        s.A.mult(x, y)
        if s.has_pairs and s.C.any():
            y.getArray()[s.elocal] += (s.C @ s._gather(x))[s.eowned]


class _Woodbury:
    """Exact inverse of A + E C E^T from A's factors:
    y = z - Z (I + C S)^{-1} C E^T z,  z = A^{-1} r,  Z = A^{-1} E,  S = E^T Z."""

    def __init__(self, solver):
        self.s = solver

    def apply(self, pc, r, y):
        s = self.s
        s._linear_solve(r, y)
        if s.C.any():
            alpha = np.linalg.solve(s.eye + s.C @ s.S, s.C @ s._gather(y))
            y.maxpy(-alpha, s.Z)


class _Condensed:
    """Newton on the pair dofs only.  With x0 = A^{-1} b (the contact-free
    solve) the solution is x = x0 - Z c(s), s = E^T x, so s solves the
    k-dimensional system  r(s) = s - s0 + S c(s) = 0  (S = E^T Z), with
    Jacobian I + S C(s).  Same equations as the full-space Newton, at the
    cost of k vector updates instead of a solve per iteration.

    The k unknowns are known on every rank, so each rank runs this small SNES
    on COMM_SELF, redundantly and identically (no communication; parallel
    Python-side objects touched by one rank only would upset PETSc 3.18's
    collective garbage collection); ranks other than 0 cancel their monitors
    so that output appears once."""

    def __init__(self, solver):
        self.s = solver
        k = solver.edofs.size
        self.k, self.J = k, np.eye(k)
        self.vec = PETSc.Vec().createSeq(k, comm=PETSc.COMM_SELF)
        mat = PETSc.Mat().createPython((k, k), context=_Dense(self), comm=PETSc.COMM_SELF)
        mat.setUp()
        snes = newton_snes(PETSc.COMM_SELF, self.formFunction, self.vec.duplicate(),
                           self.formJacobian, mat, _Dense(self), rtol=1e-12)
        if solver.da.getComm().getRank() != 0:
            snes.cancelMonitor()
        self.snes = snes

    def residual(self, sv):
        G, _, _ = self.s._contact_values(sv)
        return sv - self.s0 + self.s.S_velocity @ self.s.contact_residual(G)

    def formFunction(self, snes, X, F):
        F.array = self.residual(X.getArray(readonly=True).copy())

    def formJacobian(self, snes, X, J, P):
        sv = X.getArray(readonly=True).copy()
        if self.s.fd_jacobian:      # cross-check: central differences of r(s)
            h = 1e-7 * max(1.0, np.abs(sv).max())
            self.J = np.array([(self.residual(sv + h * e) - self.residual(sv - h * e)) / (2 * h)
                               for e in np.eye(self.k)]).T
        else:
            _, W, _ = self.s._contact_values(sv)
            self.J = np.eye(self.k) + self.s.S_velocity @ self.s.contact_block(W)

    def solve(self, X):
        s = self.s
        self.s0 = s.VE @ s._gather(X)
        self.vec.array = self.s0
        self.snes.solve(None, self.vec)
        G, _, _ = s._contact_values(self.vec.getArray(readonly=True).copy())
        X.maxpy(-(s.WE @ s.contact_residual(G)), s.Z)


class _Dense:
    """The condensed Jacobian as a matrix (for -snes_test_jacobian) and its
    exact inverse as the preconditioner (k is small)."""

    def __init__(self, condensed):
        self.c = condensed

    def mult(self, mat, x, y):
        y.array = self.c.J @ x.getArray(readonly=True)

    def apply(self, pc, x, y):
        y.array = np.linalg.solve(self.c.J, x.getArray(readonly=True))
