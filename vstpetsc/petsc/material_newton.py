"""Newton on the whole slab for a hysteretic shear field (docs/nonlinear-soil.md).

With the soil's stress beyond the linear one as internal forces r(X) (the
Gauss sums of :func:`vstpetsc.materials.masing.slab_integrals`), the slab
equations are

    F(X) = A X - b + W r(V X) = 0,   J = A + W (dr/dv) V,

A the linear slab matrix (its factors are computed once per run).  A SNES
(prefix ``vst_``, every ``-snes_*`` option) solves them; each Newton step
is a KSP (prefix ``vst_newton_``) on J, a shell, preconditioned by A's
factors: GMRES by default (a few iterations: the soil softens J away from A
only by its tangent), ``-newton_ksp_type preonly`` for modified Newton (one
application of A's factors per step).  ``-vst_fd_jacobian`` replaces the
tangent by central differences of r along the Krylov direction.

Every rank gathers the soil's nodes and evaluates every soil element (the
state is the same on every rank).
"""

import math

import numpy as np
from petsc4py import PETSc

from vstpetsc import slab
from vstpetsc.petsc.newton import solve_checked
from vstpetsc.petsc.options import PREFIX
from vstpetsc.petsc.space import DofGather


# the tangent is factored anew after a Newton step that took more Krylov
# iterations than this, or reduced |F| by less than 1 / SLOW
REFRESH = 2
SLOW = 0.1


class SoilCoupling:
    """The soil's nodes in the solver's space: from the unknowns X to the
    elements' strain increments D (ne, 2), and element forces back to rows
    (an incidence matrix: +1 on an element's right node, -1 on its left)."""

    def __init__(self, soil, solver, fixed_nodes):
        self.soil, self.dt = soil, solver.dt
        nodes = soil.nodes
        dofs = (2 * nodes[:, None] + np.arange(2)).ravel()
        self.gather = DofGather(solver.X, dofs, solver.space.nodes)
        self.left = np.searchsorted(nodes, soil.left)
        self.right = self.left + 1
        self.n = nodes.size
        # rows of prescribed velocities are identities in A: no force there
        self.free = (~np.isin(nodes, fixed_nodes)).astype(float)[:, None]
        self.held = 1.0 - self.free
        self.V, self.W = solver.V, solver.W
        self.scale = (self.dt / soil.h)[:, None]            # D_b = dt (v_r^b - v_l^b) / h

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

    def support_work(self, element_forces, values):
        """The work of the supports that hold prescribed nodes against these
        forces over the slab: sum_a f^a v^a at those nodes (the reactions of
        the linear rows do not see them)."""
        if not self.held.any():
            return 0.0
        v = values.reshape(-1, 2) @ self.V.T
        return float(np.sum(self.node_forces(element_forces) * self.held * v))


class MaterialNewton:
    """The SNES of slabs with a hysteretic soil."""

    def __init__(self, soil, solver, ops, fixed_nodes, fd_jacobian=False):
        self.soil, self.c = soil, SoilCoupling(soil, solver, fixed_nodes)
        self.factors = _Factors(self, solver, ops, fixed_nodes)
        self.A, self.linear, self.dt = solver.A, solver.linear, solver.dt
        self.fd_jacobian = fd_jacobian
        self.carry = solver.carry
        self.F = solver.X.duplicate()
        self.work_vec = solver.X.duplicate()
        J = PETSc.Mat().createPython(self.A.getSizes(), context=_Tangent(self),
                                     comm=solver.space.comm)
        J.setUp()
        self.J = J
        self.snes = self._snes(solver.space)
        self.rows = np.zeros(2 * self.c.n)          # the converged slab's W r
        self.dQ = None
        self.rate, self.last_fnorm = 0.0, 0.0
        self.iterations = 0

    def _snes(self, space):
        snes = PETSc.SNES().create(comm=space.comm)
        snes.setOptionsPrefix(PREFIX)
        snes.setDM(space.da)
        snes.setType("newtonls")
        snes.setFunction(self.formFunction, self.F)
        snes.setJacobian(self.formJacobian, self.J, self.J)
        snes.setTolerances(rtol=1e-12, atol=1e-50, stol=1e-14, max_it=50)
        snes.setConvergenceTest(self._converged)
        ksp = snes.getKSP()
        ksp.appendOptionsPrefix("newton_")
        ksp.setType("gmres")
        ksp.setTolerances(rtol=1e-10, atol=1e-50, max_it=20)
        # a step whose Krylov solve stalls on stale factors is still taken
        # (inexact Newton); the next step then factors the tangent anew
        snes.setMaxKSPFailures(1000)
        ksp.getPC().setType("python")
        ksp.getPC().setPythonContext(self.factors)
        # full steps unless asked otherwise: the residual is only piecewise
        # smooth (a branch meeting an older one kinks it), where a
        # backtracking search can stall on tiny steps
        opts, key = PETSc.Options(), PREFIX + "snes_linesearch_type"
        given = opts.hasName(key)
        if not given:
            opts.setValue(key, "basic")
        snes.setFromOptions()
        if not given:
            opts.delValue(key)
        return snes

    def _converged(self, snes, it, norms):
        """|F| <= max(atol, rtol (|b| + |W r|)): a relative decrease alone
        cannot be met when the start is already near the root."""
        rtol, atol, _, max_it = snes.getTolerances()
        fnorm = norms[2]
        # how much the last step reduced |F| (slow: stale factors)
        self.rate = fnorm / self.last_fnorm if it > 0 and self.last_fnorm > 0 else 0.0
        self.last_fnorm = fnorm
        R = snes.ConvergedReason
        if not math.isfinite(fnorm):
            return R.DIVERGED_FNORM_NAN
        if fnorm <= max(atol, rtol * (self.b_norm + np.linalg.norm(self.last_rows))):
            return R.CONVERGED_FNORM_ABS if fnorm <= atol else R.CONVERGED_FNORM_RELATIVE
        return R.DIVERGED_MAX_IT if it >= max_it else R.ITERATING

    def residual_rows(self, X, tangent):
        """W r(X) in gathered order (and dQ/dD kept when ``tangent``)."""
        values = self.c.gather(X)
        D = self.c.increments(values)
        Q, dQ = self.soil.slab(D[:, 0], D[:, 1], self.dt, tangent)
        if tangent:
            self.dQ = dQ
        self.evaluated = (values, D, Q)
        return self.c.rows(Q)

    def formFunction(self, snes, X, F):
        self.A.mult(X, F)
        F.axpy(-1.0, self.b)
        self.last_rows = self.residual_rows(X, not self.fd_jacobian)
        self.c.gather.add_rows(F, self.last_rows)
        self.X_at = X

    def formJacobian(self, snes, X, J, P):
        if not self.fd_jacobian and (snes.getKSP().getIterationNumber() > REFRESH
                                     or self.rate > SLOW):
            self.factors.refresh(self.dQ)
        if self.fd_jacobian:
            self.X_at = X.copy()
            self.h = 1e-7 * max(1.0, X.norm(PETSc.NormType.INFINITY))

    def solve(self, X, b, slab_index):
        """Newton from X (A^{-1} b) less A^{-1} of the last slab's soil
        forces (a predictor: they change little from slab to slab): X
        becomes the slab's solution; the soil's state moves to the slab end.
        Returns the iterations."""
        if self.rows.any():
            self.F.zeroEntries()
            self.c.gather.add_rows(self.F, self.rows)
            self.linear.solve(self.F, self.work_vec)
            X.axpy(-1.0, self.work_vec)
        self.b = b
        self.b_norm = b.norm()
        self.last_rows = np.zeros(2 * self.c.n)
        self.evaluated = (None, None, None)
        self.iterations = solve_checked(self.snes, X, slab_index)
        values = self.c.gather(X)
        if np.array_equal(values, self.evaluated[0]):   # SNES's last evaluation
            _, D, Q = self.evaluated
        else:
            D = self.c.increments(values)
            Q, _ = self.soil.slab(D[:, 0], D[:, 1], self.dt, tangent=False)
        self.rows = self.c.rows(Q)
        self.soil.support_work += self.c.support_work(Q, values)
        self.soil.finish(D[:, 0], D[:, 1], Q, self.dt)
        return self.iterations

    def advance(self, b):
        """The converged forces carried over in the running sum (as the
        laws' terms: b += W (T - I) W^{-1} (W r))."""
        self.c.gather.add_rows(b, (self.rows.reshape(-1, 2) @ self.carry.T).ravel())

    def describe(self):
        kind = self.snes.getKSP().getType()
        return f"; soil: SNES {self.snes.getType()} on all unknowns, steps by " \
               f"{'modified Newton (A factors)' if kind == 'preonly' else kind + ' on A factors'}"


class _Tangent:
    """y = J x = A x + W (dr/dv) V x, from the element tangents dQ/dD of the
    last function evaluation (or central differences of r)."""

    def __init__(self, newton):
        self.n = newton

    def mult(self, mat, x, y):
        n, c = self.n, self.n.c
        n.A.mult(x, y)
        if n.fd_jacobian:
            c.gather.add_rows(y, self._fd(x))
            return
        D = c.increments(c.gather(x))
        forces = np.einsum("eab,eb->ea", n.dQ, D)
        c.gather.add_rows(y, c.rows(forces))

    def _fd(self, x):
        n = self.n
        h = n.h / max(1e-300, x.norm(PETSc.NormType.INFINITY))
        out = []
        for sign in (1.0, -1.0):
            n.X_at.copy(n.work_vec)
            n.work_vec.axpy(sign * h, x)
            out.append(n.residual_rows(n.work_vec, False))
        return (out[0] - out[1]) / (2.0 * h)


class _Factors:
    """The preconditioner: A's factors until the Krylov iterations grow,
    then (on one rank) the LU factors of the assembled tangent, refreshed
    whenever a step took more than :data:`REFRESH` iterations: the soil's
    tangent changes little from slab to slab except near reversals."""

    def __init__(self, newton, solver, ops, fixed_nodes):
        self.n, self.linear = newton, solver.linear
        self.fresh = False
        self.refreshes = 0
        self.P = None
        if solver.space.comm.getSize() > 1:      # A's (parallel) factors only
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
        # where each soil element's four blocks sit in the block CSR data
        slot = lambda row, col: indptr[row] + np.searchsorted(indices[indptr[row]:indptr[row + 1]], col)
        gl = newton.soil.left
        self.at = {key: np.array([slot(r, c) for r, c in pairs], dtype=int)
                   for key, pairs in (("ll", zip(gl, gl)), ("lr", zip(gl, gl + 1)),
                                      ("rr", zip(gl + 1, gl + 1)), ("rl", zip(gl + 1, gl)))}
        c = newton.c
        self.lf = c.free[c.left, 0][:, None, None]
        self.rf = c.free[c.right, 0][:, None, None]
        self.scale = (solver.dt / newton.soil.h)[:, None, None]
        self.W, self.V = solver.W, solver.V

    def refresh(self, dQ):
        """Factor A + W (dr/dv) V for the element tangents dQ."""
        if self.P is None:
            return
        B = self.W @ (self.scale * dQ) @ self.V
        data, at = self.data, self.at
        data[...] = self.base
        left, right = self.lf * B, self.rf * B
        data[at["ll"]] += left
        data[at["lr"]] -= left
        data[at["rr"]] += right
        data[at["rl"]] -= right
        self.P.setValuesBlockedCSR(*self.csr, data.ravel())
        self.P.assemble()
        self.lu.setUp()
        self.fresh = True
        self.refreshes += 1

    def apply(self, pc, r, y):
        if self.fresh:
            self.lu.apply(r, y)
        else:
            self.linear.solve(r, y)


def of(model, solver, options, fixed_nodes):
    """The Newton of ``model``'s soil, or None without one."""
    soil = getattr(model, "soil", None)
    if soil is None:
        return None
    if model.nonlinear:
        from vstpetsc.errors import InputError
        raise InputError("body.shear_law: a hysteretic soil together with contact, friction "
                         "or soil-spring laws in one case is not supported yet")
    soil.native = None
    if options.native:
        from vstpetsc import native

        lib = native.library()
        if lib is not None and hasattr(lib, "vst_masing_slab"):
            from vstpetsc.native.masing import NativeMasing

            soil.native = NativeMasing(lib, soil)
    return MaterialNewton(soil, solver, model.ops, fixed_nodes, options.fd_jacobian)
