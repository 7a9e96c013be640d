"""Newton for slabs in which a nonlinear law is active.

The laws act on a few dofs E (both dofs of each of their nodes), so the
Jacobian differs from the slab matrix A only there: J = A + E C E^T with a
small dense block C.  With Z = A^{-1} E (k solves, once per run) and
S = E^T Z:

- :class:`Condensed` (default): with x0 = A^{-1} b (the law-free solve) the
  solution is x = x0 - Z c(s), where s = E^T x solves the k-dimensional
  r(s) = s - s0 + S c(s) = 0 (Jacobian I + S C(s)); no further solve with A.
- :class:`Full`: Newton on all unknowns; J is a shell matrix and each step
  is solved exactly by a Woodbury update of A's factors.

Unknowns and rows are mixed per node (slab.recurrence), the laws work in
(v^1, v^2): values at E are seen through VE (z to v) and the laws' rows
enter through WE.  ``formFunction``/``formJacobian`` only unwrap vectors and
call the numpy laws.  Every rank gathers E and takes the same decisions.
"""

import numpy as np
from petsc4py import PETSc

from vstpetsc.petsc.options import PREFIX
from vstpetsc.petsc.space import DofGather


def newton_snes(comm, function, F, jacobian, J, exact_inverse, rtol, dm=None):
    """A Newton SNES (prefix ``vst_``) whose linear step is one application
    of an exact inverse (a Python PC; its KSP has the prefix
    ``vst_newton_``).  Defaults are set here, then the options database has
    the last word."""
    snes = PETSc.SNES().create(comm=comm)
    snes.setOptionsPrefix(PREFIX)
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


class Coupling:
    """The laws' dofs E in the solver's space: gathers, transforms, and
    Z = A^{-1} E, S = E^T Z (computed once per run)."""

    def __init__(self, lawset, template, nodes, W, V, linear):
        self.lawset = lawset
        self.gather = DofGather(template, lawset.dofs, nodes)
        k = lawset.size
        self.VE = np.kron(np.eye(k // 2), V)
        self.WE = np.kron(np.eye(k // 2), W)
        self.eye = np.eye(k)
        self.Z = []
        e = template.duplicate()
        for j in range(k):
            z = template.duplicate()
            linear.solve(self.gather.unit(e, j), z)
            self.Z.append(z)
        self.S = np.array([self.gather(z) for z in self.Z]).T.copy()
        self.S_velocity = self.VE @ self.S @ self.WE     # E^T A^{-1} E in (v^1, v^2)

    def velocities(self, X):
        """(v^1, v^2) of the laws' nodes at iterate X."""
        return self.VE @ self.gather(X)


class Condensed:
    """Newton on the laws' dofs only (see the module docstring).

    The k unknowns are known on every rank, so each rank runs this small SNES
    on COMM_SELF, redundantly and identically (no communication; parallel
    Python-side objects touched by one rank only would upset PETSc 3.18's
    collective garbage collection); ranks other than 0 cancel their monitors
    so that output appears once."""

    def __init__(self, coupling, fd_jacobian, rank):
        self.c, self.laws = coupling, coupling.lawset
        self.fd_jacobian = fd_jacobian
        k = self.laws.size
        self.k, self.J = k, np.eye(k)
        self.vec = PETSc.Vec().createSeq(k, comm=PETSc.COMM_SELF)
        mat = PETSc.Mat().createPython((k, k), context=_Dense(self), comm=PETSc.COMM_SELF)
        mat.setUp()
        self.snes = newton_snes(PETSc.COMM_SELF, self.formFunction, self.vec.duplicate(),
                                self.formJacobian, mat, _Dense(self), rtol=1e-12)
        if rank != 0:
            self.snes.cancelMonitor()

    def residual(self, sv):
        c, _ = self.laws.residual(sv)
        return sv - self.s0 + self.c.S_velocity @ c

    def formFunction(self, snes, X, F):
        F.array = self.residual(X.getArray(readonly=True).copy())

    def formJacobian(self, snes, X, J, P):
        sv = X.getArray(readonly=True).copy()
        if self.fd_jacobian:      # cross-check: central differences of r(s)
            h = 1e-7 * max(1.0, np.abs(sv).max())
            self.J = np.array([(self.residual(sv + h * e) - self.residual(sv - h * e)) / (2 * h)
                               for e in np.eye(self.k)]).T
        else:
            self.J = np.eye(self.k) + self.c.S_velocity @ self.laws.tangent(sv)

    def solve(self, X, b):
        c = self.c
        self.s0 = c.velocities(X)
        self.vec.array = self.s0
        self.snes.solve(None, self.vec)
        res, _ = self.laws.residual(self.vec.getArray(readonly=True).copy())
        X.maxpy(-(c.WE @ res), c.Z)


class _Dense:
    """The condensed Jacobian as a matrix (for -snes_test_jacobian) and its
    exact inverse as the preconditioner (k is small)."""

    def __init__(self, condensed):
        self.c = condensed

    def mult(self, mat, x, y):
        y.array = self.c.J @ x.getArray(readonly=True)

    def apply(self, pc, x, y):
        y.array = np.linalg.solve(self.c.J, x.getArray(readonly=True))


class Full:
    """Newton on all unknowns: F(X) = A X - b + E WE c(VE E^T X), J = A +
    E C E^T (a shell), each step solved exactly by :class:`_Woodbury`."""

    def __init__(self, coupling, fd_jacobian, A, linear, space):
        self.c, self.laws = coupling, coupling.lawset
        self.fd_jacobian, self.A, self.linear = fd_jacobian, A, linear
        k = self.laws.size
        self.C = np.zeros((k, k))
        self.F = space.vector()
        J = PETSc.Mat().createPython(A.getSizes(), context=_Jacobian(self), comm=space.comm)
        J.setUp()
        self.J = J
        self.snes = newton_snes(space.comm, self.formFunction, self.F, self.formJacobian, J,
                                _Woodbury(self), rtol=1e-10, dm=space.da)

    def solve(self, X, b):
        self.b = b
        self.C[:] = 0.0
        self.snes.solve(None, X)

    def formFunction(self, snes, X, F):
        self.A.mult(X, F)
        F.axpy(-1.0, self.b)
        c, _ = self.laws.residual(self.c.velocities(X))
        self.c.gather.add_rows(F, self.c.WE @ c)

    def formJacobian(self, snes, X, J, P):
        if self.fd_jacobian:
            self.C = self._fd_block(X)
            return
        self.C = self.c.WE @ self.laws.tangent(self.c.velocities(X)) @ self.c.VE

    def _fd_block(self, X):
        """C by central differences of formFunction in the laws' dofs."""
        g = self.c.gather
        k = self.laws.size
        C = np.zeros((k, k))
        Xp, Fp, Fm, e = X.copy(), self.F.duplicate(), self.F.duplicate(), X.duplicate()
        h = 1e-7 * max(1.0, X.norm(PETSc.NormType.INFINITY))
        for j in range(k):
            g.unit(e, j)
            cols = []
            for sign, out in ((1.0, Fp), (-1.0, Fm)):
                X.copy(Xp)
                Xp.axpy(sign * h, e)
                self.formFunction(self.snes, Xp, out)
                cols.append(g(out))
            self.A.mult(e, Fp)
            C[:, j] = (cols[0] - cols[1]) / (2 * h) - g(Fp)
        return C


class _Jacobian:
    """Shell matrix y = (A + E C E^T) x for the current block C."""

    def __init__(self, full):
        self.f = full

    def mult(self, mat, x, y):
        f = self.f
        f.A.mult(x, y)
        if f.C.any():
            f.c.gather.add_rows(y, f.C @ f.c.gather(x))


class _Woodbury:
    """Exact inverse of A + E C E^T from A's factors:
    y = z - Z (I + C S)^{-1} C E^T z,  z = A^{-1} r,  Z = A^{-1} E,  S = E^T Z."""

    def __init__(self, full):
        self.f = full

    def apply(self, pc, r, y):
        f, c = self.f, self.f.c
        f.linear.solve(r, y)
        if f.C.any():
            alpha = np.linalg.solve(c.eye + f.C @ c.S, f.C @ c.gather(y))
            y.maxpy(-alpha, c.Z)
