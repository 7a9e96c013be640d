"""Newton on the whole slab for a hysteretic shear field (docs/nonlinear-soil.md).

With the soil's stress beyond the linear one as internal forces r(X) (the
Gauss sums of :func:`vstpetsc.materials.masing.slab_integrals`), the slab
equations are

    F(X) = A X - b + W r(V X) = 0,   J = A + W (dr/dv) V,

A the linear slab matrix (its factors are computed once per run).  Each
slab starts from A^{-1} (b - W r_last), r_last the last slab's soil forces.

- :class:`PlainSoilNewton` (the default): Newton in a plain loop, each step one application of the LU factors of J
  (:class:`~vstpetsc.line.solver.soil_coupling.TangentFactors`), factored anew
  only when a step reduces |F| by less than 1/SLOW (the soil's tangent
  changes little from slab to slab except near reversals);
- :class:`SnesSoilNewton` (any ``-snes_*`` or ``-newton_*`` option,
  ``-vst_fd_jacobian``): a SNES (prefix ``vst_``) whose Krylov solve
  (prefix ``vst_newton_``, GMRES) on J, a shell, is preconditioned by the
  same factors;
  ``-newton_ksp_type preonly`` is modified Newton; ``-vst_fd_jacobian``
  takes J's soil part from central differences of r.

Every rank gathers the soil's nodes and evaluates every soil element (the
state is the same on every rank).
"""

import math

import numpy as np
from petsc4py import PETSc

from vstpetsc.errors import SolveFailed
from vstpetsc.line.solver.hosted_laws import HostedLaws
from vstpetsc.line.solver.law_solver import wants_snes
from vstpetsc.line.solver.newton import solve_checked
from vstpetsc.petsc.options import PREFIX
from vstpetsc.line.solver.soil_coupling import SoilCoupling, TangentFactors

# the tangent is factored anew after a Newton step that reduced |F| by less
# than 1 / SLOW or would need more than LAGGED such steps to converge, or
# (SNES) took more Krylov iterations than REFRESH
SLOW = 0.1
REFRESH = 2
LAGGED = 1
RTOL, MAX_IT = 1e-12, 50
# with contact laws in the Newton, a step that does not reduce |F| is
# halved down to this fraction (ReducedNewton's rule)
MIN_STEP = 1e-5


def slow(fnorm, last, target):
    """Whether factoring the tangent anew pays: the steps on the kept
    factors reduce |F| linearly, by fnorm / last each; fresh factors
    converge quadratically and cost less than a step (the compiled kernel
    writes the matrix with the residual).  Refactor when more than LAGGED
    steps would remain (bench/soil_cost.py: LAGGED 1, 2, 3, 5 took 3.2,
    3.7, 4.2, 5.3 steps a slab and 0.79, 0.80, 0.90, 0.93 ms)."""
    rate = fnorm / last
    if rate >= SLOW:
        return True
    return math.log(target / fnorm) / math.log(rate) > LAGGED


class SoilNewton:
    """What both Newtons share: the start, the convergence test, closing
    the slab (the soil's state, the supports' work) and the carry."""

    def __init__(self, soil, solver, laws=None):
        self.soil = soil
        self.laws = laws           # HostedLaws: contact pairs in the same Newton, or None
        self.law_norm = 0.0        # |the laws' rows| at the last evaluation
        self.c = SoilCoupling(soil, solver)
        self.factors = None          # the tangent's factors (each Newton makes its own)
        self.A, self.linear, self.dt = solver.A, solver.linear, solver.dt
        self.carry = solver.carry
        self.F, self.step = solver.X.duplicate(), solver.X.duplicate()
        # one rank: the plain loop reads X and writes F through numpy arrays
        self.X_array = solver.x
        self.F_plain, self.F_array = solver.space.array_vector()
        self.rows = np.zeros(2 * self.c.n)          # the converged slab's W r
        self.evaluated = None
        self.iterations = 0

    def start(self, X, b, slab_index):
        """X -= A^{-1} W r_last (the predictor; the laws' likewise); the
        scale of the test."""
        if self.laws is not None:
            self.laws.start(slab_index)
        if self.rows.any():
            self.F.zeroEntries()
            self.c.gather.add_rows(self.F, self.rows)
            self.linear.solve(self.F, self.step)
            X.axpy(-1.0, self.step)
        self.b = b
        self.b_norm = b.norm()
        self.ax_norm = None
        self.evaluated = None

    def function(self, X, F, tangent, arrays=None):
        """F = A X - b + W r(X); returns the rows W r and the blocks;
        ``arrays``: (X's, F's) numpy arrays (one rank) to read and write
        the soil's dofs without a scatter."""
        self.A.mult(X, F)
        first = self.ax_norm is None
        if first:
            # the test's scale includes |A X| and the elements' own forces:
            # where they cancel at a node (quasi-static loading) F cannot
            # fall below their rounding (the slab's first iterate suffices)
            self.ax_norm = F.norm()
        F.axpy(-1.0, self.b)
        local = self.c.local
        values = self.c.gather(X) if arrays is None else np.take(arrays[0], local)
        rows, blocks, D, Q = self.c.residual(values, tangent)
        if arrays is None:
            self.c.gather.add_rows(F, rows)
        else:
            arrays[1][local] += rows
        self.evaluated = (values, D, Q, rows)
        if self.laws is not None:
            law_rows = self.laws.rows(X, tangent, None if arrays is None else arrays[0])
            self.laws.add(F, law_rows, None if arrays is None else arrays[1])
            self.law_norm = float(np.sqrt(law_rows.dot(law_rows)))
        if first:
            soil = self.soil
            self.element_norm = self.dt * float(np.linalg.norm(
                soil.ke_h * (np.abs(soil.state.gamma) + np.abs(D[:, 0]) + np.abs(D[:, 1]))))
        return rows, blocks

    def tolerance(self, rows, rtol=RTOL, atol=0.0):
        """The |F| a converged slab reaches."""
        scale = self.b_norm + self.ax_norm + self.element_norm + self.rows_norm(rows) + \
            self.law_norm
        return max(atol, rtol * scale)

    def converged(self, fnorm, rows, rtol=RTOL, atol=0.0):
        return fnorm <= self.tolerance(rows, rtol, atol)

    def rows_norm(self, rows):
        return float(np.sqrt(rows.dot(rows)))

    def close(self, X, at_solution=False):
        """X is the slab's solution: the soil's state moves to the slab end
        (``at_solution``: the compiled loop's last evaluation was at X)."""
        values = self.evaluated[0] if at_solution else self.c.gather(X)
        # the compiled kernel's last call at X closes the slab; the numpy
        # reference evaluates X once more (its path object is the state's
        # next one, and a finite-difference Jacobian may have moved it)
        native = self.soil.native is not None
        if at_solution or (native and self.evaluated is not None
                           and np.array_equal(values, self.evaluated[0])):
            _, D, Q, rows = self.evaluated
        else:
            rows, _, D, Q = self.c.residual(values, tangent=False)
        self.rows[...] = rows
        self.soil.support_work += self.c.support_work(Q, values)
        self.soil.finish(D[:, 0], D[:, 1], Q, self.dt)
        if self.laws is not None:
            self.laws.converged()

    def state(self):
        """What the next slab starts from, for a restart: the last slab's
        rows, whether factors of the tangent are in use and its blocks
        (the soil's, then the hosted laws')."""
        f = self.factors
        laws = () if self.laws is None else self.laws.kept.ravel()
        return np.concatenate([self.rows, [float(f.fresh)], f.blocks.ravel(), laws])

    def restore(self, state):
        n, ne = self.rows.size, self.factors.blocks.size
        self.rows[:] = state[:n]
        if self.laws is not None:
            self.laws.restore_blocks(state[n + 1 + ne:])
        if state[n]:
            self.factors.refresh(state[n + 1:n + 1 + ne].reshape(-1, 2, 2))

    def advance(self, b):
        """The converged forces carried over in the running sum (as the
        laws' terms: b += W (T - I) W^{-1} (W r))."""
        self.c.gather.add_rows(b, (self.rows.reshape(-1, 2) @ self.carry.T).ravel())


class PlainSoilNewton(SoilNewton):
    """Newton in a plain loop; tolerances from ``-snes_rtol``, ``-snes_atol``
    and ``-snes_max_it`` as the laws' plain Newton reads them."""

    def __init__(self, soil, solver, laws=None):
        super().__init__(soil, solver, laws)
        opts = PETSc.Options()
        self.rtol = opts.getReal(PREFIX + "snes_rtol", RTOL)
        self.atol = opts.getReal(PREFIX + "snes_atol", 0.0)
        self.max_it = opts.getInt(PREFIX + "snes_max_it", MAX_IT)
        self.compiled = self._compiled(solver)
        if self.compiled is None:
            self.factors = TangentFactors(self.c, solver, laws)

    def _compiled(self, solver):
        """The compiled loop (one rank, the compiled kernel), or None; it
        then holds the factors."""
        native = self.soil.native
        if native is None or solver.space.comm.getSize() > 1 or \
                not hasattr(native.lib, "vst_soil_newton"):
            return None
        from vstpetsc.line.native import hosted_laws

        if self.laws is not None and not hosted_laws.takes(self.laws.laws.laws):
            return None
        from vstpetsc.line.native.soil_newton import CompiledSoilNewton

        compiled = CompiledSoilNewton(native.lib, self, native, solver,
                                      (self.rtol, self.atol, SLOW, LAGGED, self.max_it,
                                       MIN_STEP))
        self.factors = compiled
        self.b_array = solver.br
        return compiled

    def _solve_compiled(self, X, slab_index):
        if self.laws is not None:
            self.laws.start(slab_index)
            self.laws.native.prepare()
        its, converged, fnorm = self.compiled.solve(self.b_array, self.X_array, self.dt)
        if not converged:
            raise SolveFailed(f"slab {slab_index}: the soil's Newton did not converge in "
                              f"{its} iterations (|F| = {fnorm:.3g})")
        native = self.soil.native
        self.evaluated = (native.values, native.D, native.Q, native.rows)
        self.iterations = its
        self.close(X, at_solution=True)
        return its

    def solve(self, X, b, slab_index):
        if self.compiled is not None:
            return self._solve_compiled(X, slab_index)
        self.start(X, b, slab_index)
        last = 0.0
        F = self.F_plain
        arrays = None if self.c.local is None else (self.X_array, self.F_array)
        tangent, lam = True, 1.0
        for it in range(self.max_it + 1):
            rows, blocks = self.function(X, F, tangent, arrays)
            fnorm = F.norm()
            if not math.isfinite(fnorm):
                raise SolveFailed(f"slab {slab_index}: the soil's Newton diverged (|F| = {fnorm})")
            target = self.tolerance(rows, self.rtol, self.atol)
            if fnorm <= target:
                break
            if it == self.max_it:
                raise SolveFailed(f"slab {slab_index}: the soil's Newton did not converge in "
                                  f"{self.max_it} iterations (|F| = {fnorm:.3g})")
            if self.laws is not None and it > 0 and fnorm >= last and lam > MIN_STEP:
                # a law switched within the step (contact, stick or slip):
                # half the step back (|F| is only piecewise smooth there)
                lam *= 0.5
                X.axpy(lam, self.step)
                tangent = True
                continue
            lam = 1.0
            if blocks is not None and (not self.factors.fresh
                                       or (it > 0 and slow(fnorm, last, target))):
                self.factors.refresh(blocks, self.c.tangent_data())
            # a step that converges quadratically from here ends the slab:
            # its residual needs no tangent
            tangent = not (it > 0 and fnorm * (fnorm / last) < 0.01 * target)
            last = fnorm
            self.factors.solve(F, self.step)
            X.axpy(-1.0, self.step)
        self.iterations = it
        self.close(X)
        return it

    def describe(self):
        where = ", compiled" if self.compiled is not None else ""
        laws = "" if self.laws is None else " with the contact laws' rows"
        return f"; soil: Newton on all unknowns{laws}{where}, LU of the tangent (refreshed " \
               "when slow)"


class SnesSoilNewton(SoilNewton):
    """The SNES of slabs with a hysteretic soil."""

    def __init__(self, soil, solver, fd_jacobian=False, laws=None):
        super().__init__(soil, solver, laws)
        self.factors = TangentFactors(self.c, solver, laws)
        self.fd_jacobian = fd_jacobian
        self.blocks = None
        J = PETSc.Mat().createPython(self.A.getSizes(), context=_Tangent(self),
                                     comm=solver.space.comm)
        J.setUp()
        self.J = J
        self.snes = self._snes(solver.space)
        self.rate, self.last_fnorm = 0.0, 0.0

    def _snes(self, space):
        snes = PETSc.SNES().create(comm=space.comm)
        snes.setOptionsPrefix(PREFIX)
        snes.setDM(space.da)
        snes.setType("newtonls")
        snes.setFunction(self.formFunction, self.F.duplicate())
        snes.setJacobian(self.formJacobian, self.J, self.J)
        snes.setTolerances(rtol=RTOL, atol=1e-50, stol=1e-14, max_it=MAX_IT)
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
        """:meth:`SoilNewton.converged` with the SNES's tolerances."""
        rtol, atol, _, max_it = snes.getTolerances()
        fnorm = norms[2]
        self.rate = fnorm / self.last_fnorm if it > 0 and self.last_fnorm > 0 else 0.0
        self.last_fnorm = fnorm
        R = snes.ConvergedReason
        if not math.isfinite(fnorm):
            return R.DIVERGED_FNORM_NAN
        if self.converged(fnorm, self.last_rows, rtol, atol):
            return R.CONVERGED_FNORM_ABS if fnorm <= atol else R.CONVERGED_FNORM_RELATIVE
        return R.DIVERGED_MAX_IT if it >= max_it else R.ITERATING

    def formFunction(self, snes, X, F):
        self.last_rows, blocks = self.function(X, F, not self.fd_jacobian)
        if blocks is not None:
            self.blocks = blocks.copy()

    def formJacobian(self, snes, X, J, P):
        if self.fd_jacobian:
            self.X_at = X.copy()
            self.h = 1e-7 * max(1.0, X.norm(PETSc.NormType.INFINITY))
        elif snes.getKSP().getIterationNumber() > REFRESH or self.rate > SLOW:
            self.factors.refresh(self.blocks, self.c.tangent_data())

    def solve(self, X, b, slab_index):
        self.start(X, b, slab_index)
        self.last_rows = np.zeros(2 * self.c.n)
        self.iterations = solve_checked(self.snes, X, slab_index)
        self.close(X)
        return self.iterations

    def residual_rows(self, X):
        """W r at X (for the finite-difference tangent)."""
        return self.c.residual(self.c.gather(X), tangent=False)[0]

    def describe(self):
        kind = self.snes.getKSP().getType()
        steps = "modified Newton" if kind == "preonly" else kind
        return f"; soil: SNES {self.snes.getType()} on all unknowns, steps by {steps} " \
               "on the tangent's factors"


class _Tangent:
    """y = J x = A x + W (dr/dv) V x, from the element blocks of the last
    function evaluation (or central differences of r)."""

    def __init__(self, newton):
        self.n = newton

    def mult(self, mat, x, y):
        n, c = self.n, self.n.c
        n.A.mult(x, y)
        laws = n.laws
        if n.fd_jacobian:
            soil_rows, law_rows = self._fd(x)
            c.gather.add_rows(y, soil_rows)
            if laws is not None:
                laws.add(y, law_rows)
            return
        c.gather.add_rows(y, c.tangent_rows(n.blocks, c.gather(x)))
        if laws is not None:
            laws.add(y, laws.tangent_rows(laws.c.gather(x)))

    def _fd(self, x):
        """The soil's and the laws' rows of J x by central differences."""
        n = self.n
        h = n.h / max(1e-300, x.norm(PETSc.NormType.INFINITY))
        out = []
        for sign in (1.0, -1.0):
            n.X_at.copy(n.step)
            n.step.axpy(sign * h, x)
            laws = None if n.laws is None else n.laws.rows(n.step, tangent=False)
            out.append((n.residual_rows(n.step), laws))
        soil = (out[0][0] - out[1][0]) / (2.0 * h)
        laws = None if n.laws is None else (out[0][1] - out[1][1]) / (2.0 * h)
        return soil, laws


def of(model, solver, options):
    """The Newton of ``model``'s soil, or None without one."""
    soil = getattr(model, "soil", None)
    if soil is None:
        return None
    soil.native = None
    if options.native:
        from vstpetsc import native

        lib = native.library()
        if lib is not None and hasattr(lib, "vst_masing_residual"):
            from vstpetsc.native.masing import NativeMasing

            soil.native = NativeMasing(lib, soil)
    laws = HostedLaws(solver.nonlinear, solver) if solver.nonlinear.hosted else None
    if not options.fd_jacobian and not wants_snes():
        return PlainSoilNewton(soil, solver, laws)
    return SnesSoilNewton(soil, solver, options.fd_jacobian, laws)
