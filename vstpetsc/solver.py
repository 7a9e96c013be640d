"""The slab solver on PETSc: a 1-D DMDA over all nodes (2 dof per node), the
constant slab matrix A factored once per run, and a SNES for slabs with
active contact.

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
        self.mat_type = PETSc.Options().getString("vst_mat_type", "baij")
        if self.mat_type not in ("baij", "aij"):
            raise ValueError(f"-vst_mat_type: 'baij' or 'aij', got {self.mat_type!r}")
        self.A = self._matrix(slab.impose_dirichlet(slab.slab_matrix(layout, dt),
                                                    dirichlet_dofs, 1.0))
        self.R = self._matrix(slab.impose_dirichlet(slab.rhs_operator(layout, dt),
                                                    dirichlet_dofs, 0.0))
        self.Q = self._matrix(slab.advance_blocks(layout.nnodes, dt), diagonal_only=True)
        self.Y = self.da.createGlobalVec()      # state (u^n, v^{n-})
        self.mask = self.Y.duplicate()
        self.mask.getArray().reshape(-1, 2)[:] = (1.0, 0.0)
        self.X = self.da.createGlobalVec()      # slab solution (v^{n+}, v^{(n+1)-})
        self.b = self.X.duplicate()
        self.F = self.X.duplicate()
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
        self.gn = np.zeros(P)
        self.C = np.zeros((k, k))        # contact block of the Jacobian on E
        self.has_pairs = P > 0

    def _gather(self, vec):
        """Values of vec at the pair dofs E, on every rank."""
        self.pair_scatter.scatter(vec, self.gathered, addv=PETSc.InsertMode.INSERT,
                                  mode=PETSc.ScatterMode.FORWARD)
        return self.gathered.getArray(readonly=True).copy()

    def _contact(self, X):
        """Kernel evaluation of all pairs at iterate X: (G, W, active)."""
        return self._contact_values(self._gather(X))

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
            F.getArray()[self.elocal] += self.contact_residual(G)[self.eowned]

    def formJacobian(self, snes, X, J, P):
        if self.fd_jacobian:
            self.C = self._fd_contact_block(X)
            return
        _, W, _ = self._contact(X)
        self.C = self.contact_block(W)

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
        """b = R Y, plus nodal force integrals and prescribed velocities.

        ``forces`` and ``dirichlet`` are (dofs, values) pairs of global dof
        numbers; entries not owned here are skipped.
        """
        self.R.mult(self.Y, self.b)
        n0, n1 = self.nodes
        arr = self.b.getArray()
        for (dofs, vals), add in ((forces, True), (dirichlet, False)):
            own = (dofs >= 2 * n0) & (dofs < 2 * n1)
            if add:
                np.add.at(arr, dofs[own] - 2 * n0, vals[own])
            else:
                arr[dofs[own] - 2 * n0] = vals[own]

    def solve(self, slab_index):
        """Solve the slab for the current b; returns (newton its, linear its)."""
        if self.has_pairs:   # g^n = g0 - sum_k c_k u_k^n
            u = self._gather(self.Y)[self.slot].reshape(-1, 2, 2)[:, :, 0]
            self.gn = self.pair_g0 - np.einsum("pk,pk->p", self.pair_signs, u)
        self.linear_its = 0
        self._linear_solve(self.b, self.X, slab_index)
        newton = 0
        self.impulse = np.zeros(len(self.pairs))
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
            self.impulse = self.impulses()
        if not np.isfinite(self.X.norm()):
            raise SolveFailed(f"slab {slab_index}: the solution is not finite")
        self.its = (newton, self.linear_its)
        return self.its

    def _linear_solve(self, b, x, slab_index=None):
        self.ksp.solve(b, x)
        reason = self.ksp.getConvergedReason()
        if reason < 0:
            where = f"slab {slab_index}: " if slab_index is not None else ""
            raise SolveFailed(f"{where}linear solve did not converge "
                              f"({_reason_name(PETSc.KSP.ConvergedReason, reason)})")
        self.linear_its += max(1, self.ksp.getIterationNumber())

    def impulses(self):
        """Contact impulse J of each pair over the last slab (compressive
        positive)."""
        G, _, _ = self._contact(self.X)
        return -self.pair_w * G.sum(axis=1)

    def advance(self):
        """Y <- (u^n + dt/2 (v^1 + v^2), v^2), as mask * Y + Q X."""
        self.Y.pointwiseMult(self.Y, self.mask)
        self.Q.multAdd(self.X, self.Y, self.Y)

    def set_state(self, u, v):
        """Set the owned part of the state from global node arrays."""
        n0, n1 = self.nodes
        y = self.Y.getArray().reshape(-1, 2)
        y[:, 0], y[:, 1] = u[n0:n1], v[n0:n1]

    def gather_state(self):
        """(u, v) of all nodes on rank 0 (None elsewhere)."""
        if not hasattr(self, "_to_zero"):
            self._nat = self.da.createNaturalVec()
            self._to_zero, self._zero = PETSc.Scatter.toZero(self._nat)
        self.da.globalToNatural(self.Y, self._nat)
        self._to_zero.scatter(self._nat, self._zero, addv=PETSc.InsertMode.INSERT,
                              mode=PETSc.ScatterMode.FORWARD)
        if self.da.getComm().getRank() != 0:
            return None
        y = self._zero.getArray(readonly=True).reshape(-1, 2)
        return y[:, 0].copy(), y[:, 1].copy()


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
        return sv - self.s0 + self.s.S @ self.s.contact_residual(G)

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
            self.J = np.eye(self.k) + self.s.S @ self.s.contact_block(W)

    def solve(self, X):
        s = self.s
        self.s0 = s._gather(X)
        self.vec.array = self.s0
        self.snes.solve(None, self.vec)
        G, _, _ = s._contact_values(self.vec.getArray(readonly=True).copy())
        X.maxpy(-(s.contact_residual(G)), s.Z)


class _Dense:
    """The condensed Jacobian as a matrix (for -snes_test_jacobian) and its
    exact inverse as the preconditioner (k is small)."""

    def __init__(self, condensed):
        self.c = condensed

    def mult(self, mat, x, y):
        y.array = self.c.J @ x.getArray(readonly=True)

    def apply(self, pc, x, y):
        y.array = np.linalg.solve(self.c.J, x.getArray(readonly=True))
