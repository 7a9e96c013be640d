"""The two ways vstpetsc.plane.contact_newton solves a Newton step
J dX = R, J = A_c + E D E^T with D the pairs' blocks f'(y) - W_c (4 x 4
per pair, zero for a pair closed and sticking), A_c factored once:

- "dense" (default up to DENSE_PAIRS pairs): Woodbury's identity with the
  pairs' coupling S = E^T A_c^-1 E (4m x 4m, rank 0's), formed once by
  4m solves with A_c:  dX = y - A_c^-1 E_K (I + D_K S_KK)^-1 D_K E_K^T y,
  y = A_c^-1 R, over the pairs K whose blocks are not zero: one solve
  with A_c and one dense solve of 4|K| unknowns a step, whatever |K|,
  with the columns A_c^-1 E kept (each rank its rows, up to COLUMNS_BYTES),
  else two solves.
- "krylov": GMRES on J applied matrix-free (A_c's product and the
  blocks), preconditioned by A_c's solver (FGMRES when that is itself
  iterative): nothing formed, but each iteration is a solve with A_c,
  and a pair that slides or opens changes J in rank 2 to 4, so the
  iterations grow with the pairs that change (bench/README.md).

``-vst_contact_steps dense|krylov`` picks one."""

import numpy as np
from petsc4py import PETSc

DENSE_PAIRS = 1000
# the columns A_c^-1 E (every rank its rows) are kept up to this many bytes a
# rank: a step then needs one solve with A_c, not two
COLUMNS_BYTES = 256 * 2 ** 20
ZERO = 1e-12                # a block below this times the springs' is a pair's rounding


def steps_for(newton):
    """The step kind for ``newton`` (a ContactNewton): the option's, else
    dense up to DENSE_PAIRS pairs."""
    opts = PETSc.Options()
    kind = opts.getString("vst_contact_steps", "dense" if newton.pairs.m <= DENSE_PAIRS
                          else "krylov")
    if kind not in ("dense", "krylov"):
        from vstpetsc.errors import InputError
        raise InputError(f"-vst_contact_steps: {kind!r} is not dense or krylov")
    return DenseSteps(newton) if kind == "dense" else KrylovSteps(newton)


def _land():
    from mpi4py import MPI
    return MPI.LAND


def _pair_vector(pairs, j):
    """E e_j on the pairs' dofs (m, 8): coordinate j = 4 p + (d1, d2, q1, q2)."""
    f = np.zeros((pairs.m, 4))
    f[j // 4, j % 4] = 1.0
    return pairs.to_dofs(f)


class DenseSteps:
    """Woodbury's steps with the pairs' dense coupling S."""

    def __init__(self, newton):
        self.newton = newton
        nw, pairs = newton, newton.pairs
        self.u, self.v = nw.A_c.createVecLeft(), nw.A_c.createVecLeft()
        rank0 = nw.comm.getRank() == 0
        n = 4 * pairs.m
        self.S = np.zeros((n, n)) if rank0 else None
        # the columns A_c^-1 E e_j, each rank its rows, when they fit in the budget
        local = self.u.getLocalSize()
        budget = nw.comm.tompi4py().allreduce(local * n * 8 <= COLUMNS_BYTES, op=_land())
        self.Z = np.empty((n, local)) if budget else None     # rows: contiguous picks
        for j in range(n):
            self.v.zeroEntries()
            nw.dofs.add(_pair_vector(pairs, j) if rank0 else None, self.v)
            nw.inner.solve(self.v, self.u)
            if self.Z is not None:
                self.Z[j] = self.u.getArray(readonly=True)
            z = nw.dofs.gather(self.u)
            if rank0:
                self.S[:, j] = pairs.coordinates(z).ravel()

    def solve(self, R, dx):
        """dx = J^-1 R; returns the solves with A_c it took."""
        nw = self.newton
        nw.inner.solve(R, dx)
        z = nw.dofs.gather(dx)
        w = self._correction(z) if z is not None else None
        if self.Z is not None:             # A_c^-1 E_K w from the kept columns
            K, w = nw.comm.tompi4py().bcast(w, root=0)
            if K.size:
                dx.setArray(dx.getArray(readonly=True) - w @ self.Z[K])
            return 1
        self.v.zeroEntries()
        nw.dofs.add(nw.pairs.to_dofs(w[1]) if w is not None else None, self.v)
        nw.inner.solve(self.v, self.u)
        dx.axpy(-1.0, self.u)
        return 2

    def _correction(self, z):
        """(the columns K of the pairs' coordinates that change, w) with
        w = (I + D_K S_KK)^-1 D_K y_K: (columns, w on them) when the
        columns are kept, else (columns, w (m, 4) on every pair)."""
        pairs = self.newton.pairs
        dn, dtan, cross = self.newton.blocks
        D = np.zeros((pairs.m, 4, 4))
        D[:, 0:2, 0:2], D[:, 2:4, 2:4], D[:, 2:4, 0:2] = dn, dtan, cross
        scale = max(float(np.abs(pairs.spring_n).max(initial=0.0)),
                    float(np.abs(pairs.spring_t).max(initial=0.0))) * float(np.abs(pairs.hk).max())
        K = np.flatnonzero(np.abs(D).reshape(pairs.m, -1).max(axis=1) > ZERO * scale)
        rows = (4 * K[:, None] + np.arange(4)).ravel()
        w = np.zeros(rows.size)
        if K.size:
            DK = D[K]
            y = pairs.coordinates(z)[K]
            DS = np.einsum("kab,kbj->kaj", DK, self.S[rows][:, rows].reshape(K.size, 4, -1))
            M = np.eye(rows.size) + DS.reshape(rows.size, rows.size)
            w = np.linalg.solve(M, np.einsum("kab,kb->ka", DK, y).ravel())
        if self.Z is not None:
            return rows, w
        every = np.zeros((pairs.m, 4))
        every[K] = w.reshape(-1, 4)
        return rows, every


class _Jacobian:
    """J = A_c + E D E^T, matrix-free (petsc4py's python Mat)."""

    def __init__(self, newton):
        self.newton = newton

    def mult(self, mat, x, y):
        nw = self.newton
        nw.A_c.mult(x, y)
        z = nw.dofs.gather(x)
        values = nw.pairs.apply_difference(z, *nw.blocks) if z is not None else None
        nw.dofs.add(values, y)


class _Preconditioner:
    """A_c's own solver as GMRES's preconditioner (petsc4py's python PC)."""

    def __init__(self, inner):
        self.inner = inner

    def apply(self, pc, x, y):
        self.inner.solve(x, y)


class KrylovSteps:
    """GMRES steps preconditioned by A_c's solver (options prefix
    ``vst_contact_``)."""

    def __init__(self, newton):
        nw = newton
        J = PETSc.Mat().createPython(nw.A_c.getSizes(), context=_Jacobian(nw), comm=nw.comm)
        J.setUp()
        self.ksp = PETSc.KSP().create(comm=nw.comm)
        self.ksp.setOptionsPrefix("vst_contact_")
        self.ksp.setOperators(J)
        self.ksp.setType("gmres" if nw.inner.getType() == "preonly" else "fgmres")
        self.ksp.setTolerances(rtol=1e-12, atol=0.0, max_it=1000)
        self.ksp.setGMRESRestart(200)
        pc = self.ksp.getPC()
        pc.setType("python")
        pc.setPythonContext(_Preconditioner(nw.inner))
        self.ksp.setFromOptions()

    def solve(self, R, dx):
        from vstpetsc.errors import SolveFailed

        self.ksp.solve(R, dx)
        if self.ksp.getConvergedReason() < 0:
            raise SolveFailed(f"the interfaces' Newton step did not converge "
                              f"({self.ksp.getConvergedReason()})")
        return self.ksp.getIterationNumber()
