"""Newton for slabs in which a nonlinear law acts.

The laws act on a few dofs E, through 2L reduced coordinates y = P^T s
(:mod:`vstpetsc.line.lawset`), so the Jacobian differs from the slab matrix A
only there: J = A + E C E^T.  With Z = A^{-1} E (2L solves of combined
columns, once per run) and S = P^T E^T A^{-1} E P (in the velocity basis):

- condensed (default): with x0 = A^{-1} b (the law-free solve) the solution
  is x = x0 - Z P f(y), where y solves the 2L-dimensional
  r(y) = y - y0 + S f(y) = 0 with Jacobian I + S f'(y).
  :class:`vstpetsc.line.reduced_newton.ReducedNewton` runs this Newton in plain
  floats (2 unknowns a pair);
  :class:`SnesCondensed` hands the same system to a SNES (for
  ``-vst_fd_jacobian`` and SNES monitors and line searches);
- :class:`Full` (``-vst_newton full``): SNES on all unknowns, J a shell
  matrix and each step solved exactly by a Woodbury update of A's factors.

Unknowns and rows are mixed per node (slab.recurrence): values at E are
seen through VE (z to v) and the laws' rows enter through WE.  Every rank
gathers E and takes the same decisions.
"""

import math

import numpy as np
from petsc4py import PETSc

from vstpetsc.errors import SolveFailed
from vstpetsc.line.solver.linear import reason_name
from vstpetsc.petsc.options import PREFIX
from vstpetsc.line.solver.space import DofGather


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
    """The laws' dofs E and coordinates y in the solver's space, and the
    run-constant pieces of the condensed system."""

    def __init__(self, lawset, template, nodes, W, V, linear, carry, array=None):
        self.lawset = lawset
        self.gather = DofGather(template, lawset.dofs, nodes)
        k, P = lawset.size, lawset.P
        self.V = V
        self.VE = np.kron(np.eye(k // 2), V)
        self.WE = np.kron(np.eye(k // 2), W)
        self.eye = np.eye(k)
        e = template.duplicate()
        self.Z = []
        for j in range(k):
            z = template.duplicate()
            linear.solve(self.gather.unit(e, j), z)
            self.Z.append(z)
        self.S = np.array([self.gather(z) for z in self.Z]).T.copy()     # E^T A^-1 E (z)
        S_velocity = self.VE @ self.S @ self.WE
        self.S_red = P.T @ S_velocity @ P
        self.R0 = P.T @ self.VE                 # y = R0 x_E
        combine = self.WE @ P                   # Z combined: A^-1 E WE P
        self.Zred = []
        for j in range(P.shape[1]):
            z = template.duplicate()
            z.maxpy(combine[:, j], self.Z)
            self.Zred.append(z)
        self.carry_rows = np.kron(np.eye(k // 2), carry) @ combine
        # one rank holds every dof: read them straight from the solution's
        # ``array`` (on several ranks every rank takes part in the gather,
        # whoever owns the dofs)
        serial = template.getComm().getSize() == 1 and array is not None
        self.local = self.gather.local if serial else None
        self.local_z2 = None if self.local is None else self.local[1::2].copy()
        self.array = array

    def velocities(self, X):
        """(v^1, v^2) of the laws' nodes at iterate X (on every rank)."""
        return (self.gather(X).reshape(-1, 2) @ self.V.T).ravel()

    def node_velocities(self, X):
        """velocities() for X the solver's own solution (read in place on
        one rank)."""
        return (self.unknowns(X).reshape(-1, 2) @ self.V.T).ravel()

    def coordinates(self, X):
        """The reduced coordinates y at X (on every rank)."""
        return self.R0 @ self.unknowns(X)

    def unknowns(self, X, out=None):
        """The unknowns z at the laws' dofs (into ``out`` when given), on
        every rank."""
        if self.local is not None:           # one rank: read X directly
            return np.take(self.array, self.local, out=out)
        if out is None:
            return self.gather(X)
        out[:] = self.gather(X)
        return out

    def increments(self, X):
        """z_2 (the displacement increments) of the laws' nodes at X."""
        if self.local is not None:
            return self.array[self.local_z2]
        return self.gather(X)[1::2]


class SnesCondensed:
    """The condensed system r(y) = y - y0 + S f(y) in a SNES on COMM_SELF,
    run redundantly and identically on every rank (ranks other than 0
    cancel their monitors); with ``fd_jacobian`` its Jacobian comes from
    central differences of r."""

    def __init__(self, coupling, fd_jacobian, rank):
        self.c, self.laws = coupling, coupling.lawset
        self.fd_jacobian = fd_jacobian
        k = self.laws.reduced
        self.k, self.J = k, np.eye(k)
        self.vec = PETSc.Vec().createSeq(k, comm=PETSc.COMM_SELF)
        mat = PETSc.Mat().createPython((k, k), context=_Dense(self), comm=PETSc.COMM_SELF)
        mat.setUp()
        self.snes = newton_snes(PETSc.COMM_SELF, self.formFunction, self.vec.duplicate(),
                                self.formJacobian, mat, _Dense(self), rtol=1e-12)
        self.snes.setConvergenceTest(self._converged)
        if rank != 0:
            self.snes.cancelMonitor()
        self.iterations = 0

    def _converged(self, snes, it, norms):
        """ReducedNewton's test (in 2-norms): |r| <= max(atol, rtol (|y0| + |S f|)),
        with the SNES's tolerances (the options database has the last word).
        A relative decrease alone cannot be met when the start is already
        near the root (a warm start), the residual then at rounding level."""
        rtol, atol, _, max_it = snes.getTolerances()
        fnorm = norms[2]
        R = snes.ConvergedReason
        if not math.isfinite(fnorm):
            return R.DIVERGED_FNORM_NAN
        scale = np.linalg.norm(self.y0) + np.linalg.norm(self.c.S_red @ self.laws.f)
        if fnorm <= max(atol, rtol * scale):
            return R.CONVERGED_FNORM_ABS if fnorm <= atol else R.CONVERGED_FNORM_RELATIVE
        return R.DIVERGED_MAX_IT if it >= max_it else R.ITERATING

    def residual(self, y):
        self.laws.evaluate(y)
        return y - self.y0 + self.c.S_red @ self.laws.f

    def formFunction(self, snes, X, F):
        F.array = self.residual(X.getArray(readonly=True).copy())

    def formJacobian(self, snes, X, J, P):
        y = X.getArray(readonly=True).copy()
        if self.fd_jacobian:
            h = 1e-7 * max(1.0, np.abs(y).max())
            self.J = np.array([(self.residual(y + h * e) - self.residual(y - h * e)) / (2 * h)
                               for e in np.eye(self.k)]).T
        else:
            self.residual(y)
            self.J = np.eye(self.k) + self.c.S_red @ self.laws.jac

    def solve(self, y0, slab_index, start=None):
        self.y0 = y0
        if start is not None:               # as in ReducedNewton.solve
            self.laws.evaluate(start)
            if not self.laws.f.any():
                start = None
        self.vec.array = y0 if start is None else start
        self.iterations = solve_checked(self.snes, self.vec, slab_index)
        y = self.vec.getArray(readonly=True).copy()
        self.laws.evaluate(y)
        return y


def solve_checked(snes, vec, slab_index):
    """Solve with ``snes`` from ``vec``; its Newton iterations, or
    SolveFailed naming the slab."""
    snes.solve(None, vec)
    reason, iterations = snes.getConvergedReason(), snes.getIterationNumber()
    if reason <= 0:
        raise SolveFailed(f"slab {slab_index}: SNES did not converge "
                          f"({reason_name(PETSc.SNES.ConvergedReason, reason)}"
                          f" after {iterations} Newton iterations)")
    return iterations


class _Dense:
    """A small Jacobian as a matrix (for -snes_test_jacobian) and its exact
    inverse as the preconditioner."""

    def __init__(self, owner):
        self.o = owner

    def mult(self, mat, x, y):
        y.array = self.o.J @ x.getArray(readonly=True)

    def apply(self, pc, x, y):
        y.array = np.linalg.solve(self.o.J, x.getArray(readonly=True))


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
        self.iterations = 0

    def solve_full(self, X, b, slab_index):
        self.b = b
        self.C[:] = 0.0
        self.iterations = solve_checked(self.snes, X, slab_index)

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
