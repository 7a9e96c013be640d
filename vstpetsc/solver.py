"""The slab solver on PETSc: a 1-D DMDA over all nodes (2 dof per node), the
constant slab matrix factored once, and a SNES for slabs with active contact.

Per slab: one application of the factors gives the contact-free solution; if
no pair's gap goes negative anywhere in the slab for it, that is the answer
(it satisfies the full nonlinear equations exactly).  Otherwise Newton (SNES)
starts from it, with the Jacobian J = A + contact blocks and the factored A
as preconditioner of a Krylov method: the contact blocks are a low-rank
change, so GMRES absorbs them in a few iterations and A is never refactored.

``formFunction`` and ``formJacobian`` only unwrap vectors and call the numpy
kernels of :mod:`vstpetsc.contact`.
"""

import numpy as np
from petsc4py import PETSc

from vstpetsc import slab
from vstpetsc.contact import contact_integrals

DIRECT_PCS = ("lu", "cholesky")


class SolveFailed(RuntimeError):
    """The nonlinear or linear solve of a slab did not converge."""


def _reason_name(cls, code):
    for name in dir(cls):
        if not name.startswith("_") and getattr(cls, name) == code:
            return name
    return str(code)


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
        n = layout.nnodes
        self.da = PETSc.DMDA().create(
            dim=1, sizes=(n,), dof=2, stencil_width=1, comm=comm,
            ownership_ranges=None if ownership is None else (tuple(ownership),))
        self.da.setUp()
        (n0, n1), = self.da.getRanges()
        self.nodes = (n0, n1)
        dirichlet_dofs = np.asarray(dirichlet_dofs, dtype=int)
        self.A = self._matrix(slab.impose_dirichlet(slab.slab_matrix(layout, dt),
                                                    dirichlet_dofs, 1.0))
        self.R = self._matrix(slab.impose_dirichlet(slab.rhs_operator(layout, dt),
                                                    dirichlet_dofs, 0.0))
        self.J = self.A.duplicate(copy=True)
        self.Y = self.da.createGlobalVec()      # state (u^n, v^{n-})
        self.X = self.da.createGlobalVec()      # slab solution (v^{n+}, v^{(n+1)-})
        self.b = self.X.duplicate()
        self.F = self.X.duplicate()
        self.its = (0, 0)
        self._setup_pairs()
        self._setup_solvers()

    # -- assembly ----------------------------------------------------------
    def _matrix(self, blocks):
        n0, n1 = self.nodes
        indptr, indices, data = slab.block_rows_csr(blocks, n0, n1)
        nloc, nglob = 2 * (n1 - n0), 2 * blocks.shape[0]
        mat = PETSc.Mat().createAIJ(size=((nloc, nglob), (nloc, nglob)), bsize=2,
                                    csr=(indptr.astype(PETSc.IntType),
                                         indices.astype(PETSc.IntType), data),
                                    comm=self.da.getComm())
        mat.assemble()
        return mat

    def _setup_pairs(self):
        """Pairs touching this rank's nodes, and a scatter of their dofs."""
        n0, n1 = self.nodes
        mine = [p for p in self.pairs if any(n0 <= k < n1 for k in p.nodes)]
        self.local_pairs = [self.pairs.index(p) for p in mine]
        P = len(mine)
        nodes = np.zeros((P, 2), dtype=int)
        signs = np.zeros((P, 2))
        for i, p in enumerate(mine):
            nodes[i, :len(p.nodes)] = p.nodes
            nodes[i, len(p.nodes):] = p.nodes[0]  # padding, sign 0
            signs[i, :len(p.nodes)] = p.signs
        self.pair_nodes, self.pair_signs = nodes, signs
        self.pair_g0 = np.array([p.g0 for p in mine])
        self.pair_w = np.array([p.penalty for p in mine])
        self.pair_form = [p.formulation for p in mine]
        dofs = (2 * nodes[..., None] + np.arange(2)).ravel()            # (P, 2, 2) flat
        self.pair_dofs = dofs
        self.pair_owned = (dofs >= 2 * n0) & (dofs < 2 * n1)
        self.pair_local = dofs - 2 * n0
        self.gathered = PETSc.Vec().createSeq(dofs.size, comm=PETSc.COMM_SELF)
        iset = PETSc.IS().createGeneral(dofs.astype(PETSc.IntType), comm=PETSc.COMM_SELF)
        self.pair_scatter = PETSc.Scatter().create(self.X, iset, self.gathered, None)
        self.gn = np.zeros(P)
        self.has_pairs = len(self.pairs) > 0
        # Per local pair: its dofs, which of them are owned rows here, and A's
        # entries in that block, so that J = A + contact block is rewritten
        # in full at every Jacobian evaluation (no drift, no refactoring).
        self.pair_blocks = []
        for p in mine:
            dofs_p = (2 * np.asarray(p.nodes)[:, None] + np.arange(2)).ravel().astype(PETSc.IntType)
            own = (dofs_p >= 2 * n0) & (dofs_p < 2 * n1)
            a_vals = self.A.getValues(dofs_p[own], dofs_p) if own.any() else None
            self.pair_blocks.append((dofs_p, own, a_vals, np.outer(p.signs, p.signs)))

    def _gather_pairs(self, vec):
        """Values of vec at the pair dofs, shaped (P, 2 nodes, 2 dofs)."""
        self.pair_scatter.scatter(vec, self.gathered, addv=PETSc.InsertMode.INSERT,
                                  mode=PETSc.ScatterMode.FORWARD)
        return self.gathered.getArray(readonly=True).reshape(-1, 2, 2)

    def _contact(self, X):
        """Kernel evaluation for the local pairs at iterate X."""
        v = self._gather_pairs(X)
        d = np.einsum("pk,pka->pa", self.pair_signs, v)
        return contact_integrals(self.gn, d[:, 0], d[:, 1], self.dt, self.pair_form)

    # -- solvers -----------------------------------------------------------
    def _setup_solvers(self):
        comm = self.da.getComm()
        snes = PETSc.SNES().create(comm=comm)
        snes.setDM(self.da)
        snes.setType("newtonls")
        snes.setFunction(self.formFunction, self.F)
        snes.setJacobian(self.formJacobian, self.J, self.A)
        snes.setTolerances(rtol=1e-10, atol=1e-50, stol=1e-14, max_it=30)
        ksp = snes.getKSP()
        ksp.setType("gmres")
        ksp.setTolerances(rtol=1e-12, atol=1e-50, max_it=200)
        pc = ksp.getPC()
        pc.setType("lu")
        if comm.getSize() > 1:
            pc.setFactorSolverType("mumps")
        else:
            pc.setFactorSolverType("petsc")
            pc.setFactorOrdering("rcm")
        snes.setFromOptions()      # the command line wins over the defaults above
        self.fd_jacobian = PETSc.Options().getBool("vst_fd_jacobian", False)
        ksp.setOperators(self.J, self.A)
        ksp.setUp()                # factors A once
        self.snes, self.ksp, self.pc = snes, ksp, pc
        self.direct = pc.getType() in DIRECT_PCS
        ksp.viewFromOptions("-ksp_view")

    def describe(self):
        """One line naming the linear solver actually in use."""
        pc = self.pc
        if pc.getType() in DIRECT_PCS:
            what = f"{pc.getType()} ({pc.getFactorSolverType()})"
        else:
            what = pc.getType()
        return f"{self.ksp.getType()}/{what}, SNES {self.snes.getType()}"

    def formFunction(self, snes, X, F):
        self.A.mult(X, F)
        F.axpy(-1.0, self.b)
        if self.local_pairs:
            G, _, _ = self._contact(X)
            vals = -(self.pair_signs * self.pair_w[:, None])[:, :, None] * G[:, None, :]
            f = F.getArray()
            own = self.pair_owned
            np.add.at(f, self.pair_local[own], vals.ravel()[own])

    def formJacobian(self, snes, X, J, P):
        if self.fd_jacobian:
            return self._fd_jacobian(X, J)
        if self.local_pairs:
            _, W, _ = self._contact(X)
            # dR_{n_k}^a / dv_{n_l}^b = c_k c_l w W_ab  (pairs are few: not a per-node loop)
            for i, (dofs, own, a_vals, cc) in enumerate(self.pair_blocks):
                if own.any():
                    block = np.kron(cc, self.pair_w[i] * W[i])
                    J.setValues(dofs[own], dofs, a_vals + block[own])
        J.assemble()

    def _fd_jacobian(self, X, J):
        """Columns of the pair dofs by central differences of formFunction
        (the cross-check of the hand-written tangent, -vst_fd_jacobian).
        Every other column of J is A's, and contact only touches these."""
        n0, n1 = self.nodes
        dofs = sorted({2 * k + a for p in self.pairs for k in p.nodes for a in (0, 1)})
        Xp, Fp, Fm = X.copy(), self.F.duplicate(), self.F.duplicate()
        h = 1e-7 * max(1.0, X.norm(PETSc.NormType.INFINITY))
        for j in dofs:
            for sign, out in ((1.0, Fp), (-1.0, Fm)):
                X.copy(Xp)
                if n0 <= j // 2 < n1:
                    Xp.setValue(j, sign * h, addv=PETSc.InsertMode.ADD_VALUES)
                Xp.assemble()
                self.formFunction(self.snes, Xp, out)
            node = j // 2
            rows = np.arange(2 * max(node - 1, n0), 2 * min(node + 2, n1), dtype=PETSc.IntType)
            if rows.size:
                col = (Fp.getArray(readonly=True) - Fm.getArray(readonly=True)) / (2 * h)
                J.setValues(rows, [j], col[rows - 2 * n0][:, None])
        J.assemble()

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
        if self.local_pairs:   # g^n = g0 - sum_k c_k u_k^n
            u = self._gather_pairs(self.Y)[:, :, 0]
            self.gn = self.pair_g0 - np.einsum("pk,pk->p", self.pair_signs, u)
        if self.direct:
            self.pc.apply(self.b, self.X)
            linear = 1
        else:
            self.ksp.setOperators(self.A, self.A)
            self.ksp.solve(self.b, self.X)
            self._check_ksp(slab_index)
            linear = self.ksp.getIterationNumber()
            self.ksp.setOperators(self.J, self.A)
        newton = 0
        if self.has_pairs and self._any_active():
            self.snes.solve(None, self.X)
            reason = self.snes.getConvergedReason()
            if reason <= 0:
                raise SolveFailed(f"slab {slab_index}: SNES did not converge "
                                  f"({_reason_name(PETSc.SNES.ConvergedReason, reason)}"
                                  f" after {self.snes.getIterationNumber()} Newton "
                                  "iterations)")
            newton = self.snes.getIterationNumber()
            linear += self.snes.getLinearSolveIterations()
        if not np.isfinite(self.X.norm()):
            raise SolveFailed(f"slab {slab_index}: the solution is not finite")
        self.its = (newton, linear)
        return self.its

    def _check_ksp(self, slab_index):
        reason = self.ksp.getConvergedReason()
        if reason < 0:
            raise SolveFailed(f"slab {slab_index}: linear solve did not converge "
                              f"({_reason_name(PETSc.KSP.ConvergedReason, reason)})")

    def _any_active(self):
        active = False
        if self.local_pairs:
            active = bool(self._contact(self.X)[2].any())
        return self.da.getComm().tompi4py().allreduce(active, op=_MPI_LOR())

    def impulses(self):
        """Contact impulse J of each pair over the last slab (compressive
        positive), summed to every rank."""
        out = np.zeros(len(self.pairs))
        if self.local_pairs:
            G, _, _ = self._contact(self.X)
            J = -self.pair_w * G.sum(axis=1)
            # a pair evaluated on two ranks is counted by the owner of its first node
            n0, n1 = self.nodes
            first = self.pair_nodes[:, 0]
            keep = (first >= n0) & (first < n1)
            out[np.asarray(self.local_pairs)[keep]] = J[keep]
        return self.da.getComm().tompi4py().allreduce(out)

    def advance(self):
        """Y <- (u^n + dt/2 (v^1 + v^2), v^2)."""
        y = self.Y.getArray().reshape(-1, 2)
        x = self.X.getArray(readonly=True).reshape(-1, 2)
        y[:, 0] += 0.5 * self.dt * (x[:, 0] + x[:, 1])
        y[:, 1] = x[:, 1]

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


def _MPI_LOR():
    from mpi4py import MPI
    return MPI.LOR
