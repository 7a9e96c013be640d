"""The nonlinear laws inside a slab: whether any acts for the law-free
solution, Newton when one does (:mod:`vstpetsc.line.solver.newton`), and what
their converged terms leave in the running right-hand side."""

import numpy as np
from petsc4py import PETSc

from vstpetsc import native

from vstpetsc.line.native import penalty as penalty_native
from vstpetsc.line.native import smith_slab
from vstpetsc.line.lawset import LawSet
from vstpetsc.line.solver.influence import LawInfluence
from vstpetsc.line.solver.newton import Coupling, Full, SnesCondensed
from vstpetsc.petsc.options import PREFIX
from vstpetsc.line.reduced_newton import ManyLawNewton, ReducedNewton

MANY = 4        # laws from which the plain Newton does its linear algebra in numpy

# ReducedNewton reads these itself; any other -snes_* option (a monitor, a
# line search, -snes_test_jacobian) asks for PETSc's SNES.
PLAIN_OPTIONS = ("snes_rtol", "snes_atol", "snes_stol", "snes_max_it")


def wants_snes():
    """Whether the run's options name a SNES feature the plain Newton lacks."""
    names = PETSc.Options().getAll()
    return any(n.startswith((PREFIX + "snes_", PREFIX + "newton_")) and
               n[len(PREFIX):] not in PLAIN_OPTIONS for n in names)


class LawSolver:
    """The model's nonlinear laws on the solver's space (``active`` False
    when there are none)."""

    def __init__(self, model, options, solver):
        self.laws = LawSet(model.nonlinear)
        self.active = self.laws.reduced > 0
        self.newton = None
        self.hosted = False
        self.f = np.zeros(self.laws.reduced)      # the laws' terms of the last slab
        self.acted = False
        # f . y the laws took, summed per energy term ("contact", "soil")
        self.keys = [getattr(law, "energy_key", "contact") for law in self.laws.laws]
        # laws whose work goes to several terms (friction: dissipated,
        # stored, the wall's), named by their energy_keys
        self.splits = [getattr(law, "work_terms", None) for law in self.laws.laws]
        split_keys = [k for law in self.laws.laws for k in getattr(law, "energy_keys", ())]
        self.work = dict.fromkeys(["contact", *self.keys, *split_keys], 0.0)
        # laws whose work on one of their nodes is reported ("transferred")
        self.heads = [(j, -law.signs[law.transfer_node],
                       int(self.laws.node_index[j][law.transfer_node]))
                      for j, law in enumerate(self.laws.laws)
                      if getattr(law, "transfer_node", None) is not None]
        if self.heads:
            self.work["transferred"] = 0.0
        if not self.active:
            return
        space = solver.space
        self.coupling = Coupling(self.laws, solver.X, space.nodes, solver.W, solver.V,
                                 solver.linear, solver.carry, solver.x)
        self.influence = LawInfluence(self.coupling.Zred, solver.x, space)
        # a hysteretic soil's Newton takes the laws' rows (hosted_laws.py)
        self.hosted = getattr(model, "soil", None) is not None
        if self.hosted:
            return
        if options.newton == "full":
            self.newton = Full(self.coupling, options.fd_jacobian, solver.A, solver.linear,
                               space)
        elif options.fd_jacobian or wants_snes():
            self.newton = SnesCondensed(self.coupling, options.fd_jacobian,
                                        space.comm.getRank())
        else:
            opts = PETSc.Options()
            tolerances = dict(rtol=opts.getReal(PREFIX + "snes_rtol", 1e-12),
                              atol=opts.getReal(PREFIX + "snes_atol", 1e-50),
                              max_it=opts.getInt(PREFIX + "snes_max_it", 30))
            compiled = options.native and native.library() is not None
            if compiled and smith_slab.takes(self.laws, space.comm.getSize()):
                # Smith soil: the whole slab compiled, steps on A's bands
                # (or on a dense S for few laws on many nodes)
                self.newton = self._smith_slab(solver, tolerances)
            elif compiled and penalty_native.takes(self.laws.laws):
                # the whole slab of the pairs in one compiled call
                self.newton = penalty_native.PenaltySlab(self.laws, self.coupling.S_red,
                                                 self.coupling.R0, self.f, **tolerances)
            else:
                kind = ManyLawNewton if len(self.laws.laws) > MANY else ReducedNewton
                self.newton = kind(self.laws, self.coupling.S_red, **tolerances)

    def _smith_slab(self, solver, tolerances):
        """The compiled slab for laws with Smith nodes (it finishes them
        itself), its steps with the dense S where that is cheaper."""
        dense = smith_slab.dense_is_cheaper(len(self.laws.laws), solver.x.size // 2)
        slab = smith_slab.SmithSlab(native.library(), self.laws, solver, self.f, self.keys,
                                    self.heads, self.coupling.S_red if dense else None,
                                    **tolerances)
        self.laws.hand_over(slab.bank.laws)
        return slab

    def solve(self, X, b, dt, slab_index):
        """Newton if a law acts for the law-free solution X (updated in
        place); returns the Newton iterations."""
        if isinstance(self.newton, penalty_native.PenaltySlab):
            return self._solve_compiled(X, b, dt, slab_index)
        if isinstance(self.newton, smith_slab.SmithSlab):
            return self._solve_smith(dt, slab_index)
        laws = self.laws
        laws.start_slab(dt, (slab_index - 1) * dt)
        y0 = self.coupling.coordinates(X)
        if not laws.acts(y0):
            # the laws' last evaluation must be at this slab (finish_slab
            # reads it); after a slab without Newton it already gave nothing
            if self.acted:
                laws.evaluate(y0)
            self.acted = False
            return 0
        if isinstance(self.newton, Full):
            self.newton.solve_full(X, b, slab_index)
            y = laws.P.T @ self.coupling.velocities(X)
            laws.evaluate(y)
        else:
            start = y0 - self.coupling.S_red @ self.f if self.acted else None
            y = self.newton.solve(y0, slab_index, start)
            self.influence.subtract(laws.f)
        self.f[:] = laws.f
        self.acted = True
        self._book_at(y)
        return self.newton.iterations

    def took(self, y, acting):
        """The slab's terms and work after a soil's Newton that hosts the
        laws converged at the coordinates y (their last evaluation)."""
        self.f[:] = self.laws.f
        self.acted = acting
        if acting:
            self._book_at(y)

    def _book_at(self, y):
        """The work f . y of each law at the coordinates y into its terms."""
        f, y = self.f.tolist(), list(map(float, y))
        self._book([f[2 * j] * y[2 * j] + f[2 * j + 1] * y[2 * j + 1]
                    for j in range(len(self.keys))])

    def _book(self, works):
        """Add each law's work f . y of the slab to its energy term (a
        friction law's split by its work_terms)."""
        for key, split, work in zip(self.keys, self.splits, works):
            if split is None:
                self.work[key] += work
            else:
                for part, value in split(work):
                    self.work[part] += value

    def _solve_compiled(self, X, b, dt, slab_index):
        """solve() for penalty pairs and their friction: one call for the
        slab's start, test, guess, Newton and work
        (:class:`vstpetsc.line.native.penalty.PenaltySlab`); on one rank it
        reads X and subtracts the pairs' influence itself."""
        step = self.newton
        if not step.bound:
            step.bind(self.coupling, self.influence, b.getArray())
        if not step.serial:
            self.coupling.unknowns(X, step.xE)
        t0 = (slab_index - 1) * dt
        for law in self.laws.timed:     # the walls' shear velocities (LawSet.start_slab)
            law.start_time(t0)
        if not step.run(self.acted, slab_index):
            self.acted = False
            return 0
        if not step.serial:
            self.influence.subtract(step.f)
        self.acted = True               # (the call wrote the slab's terms into self.f)
        self._book(step.work.tolist())
        return step.iterations

    def _solve_smith(self, dt, slab_index):
        """solve() through the compiled slab (:class:`SmithSlab`)."""
        step = self.newton
        if not step.run(self.acted, dt, (slab_index - 1) * dt, slab_index):
            self.acted = False
            return 0
        if step.dense:                  # the terms into X on their columns' spans
            self.influence.subtract(step.f)
        self.f[:] = step.f
        self.acted = True
        for key, work in step.work_terms():
            self.work[key] += work
        return step.iterations

    def advance(self, X, b):
        """Close the slab: the laws' displacements, their terms carried over
        in the running sum b."""
        if isinstance(self.newton, smith_slab.SmithSlab):
            transferred = self.newton.advance(self.acted)
            if self.acted and self.heads:
                self.work["transferred"] += transferred
            return
        if isinstance(self.newton, penalty_native.PenaltySlab) and self.newton.serial:
            self.newton.advance(self.acted)      # bound to the solver's arrays
        else:
            self.laws.u += self.coupling.increments(X)
            if self.acted:
                self.coupling.gather.add_rows(b, self.coupling.carry_rows @ self.f)
        if self.acted and self.heads:
            self._transfer(X)

    def _transfer(self, X):
        """The slab's work of the marked laws on their node: the node
        feels -c f^a, so its work is -c (f1 v^1 + f2 v^2)."""
        s = self.coupling.node_velocities(X)
        for j, sign, i in self.heads:
            self.work["transferred"] += sign * (self.f[2 * j] * s[2 * i]
                                                + self.f[2 * j + 1] * s[2 * i + 1])

    def describe(self):
        """The Newton in use, for the run header."""
        return describe_newton(self.newton, self.laws.reduced)

    def state(self):
        """[acted, f]: what the next slab's Newton starts from (a restart
        continues bit for bit only with it)."""
        return np.concatenate([[float(self.acted)], self.f])

    def set_newton_state(self, state):
        if state.size == self.f.size + 1:
            self.acted = bool(state[0])
            self.f[:] = state[1:]

    def set_state(self, u):
        self.laws.u[:] = u[self.laws.nodes]


def describe_newton(newton, reduced):
    """The laws' Newton for the run header (``reduced``: their coordinates)."""
    if newton is None:
        return ""
    if isinstance(newton, smith_slab.SmithSlab):
        how = "a dense S" if newton.dense else "the slab matrix's bands"
        return (f"; Newton: plain, compiled, on the laws' {reduced} coordinates"
                f" (steps on {how})")
    if isinstance(newton, penalty_native.NativeNewton):
        return f"; Newton: plain, compiled, on the laws' {reduced} coordinates"
    if isinstance(newton, ReducedNewton):      # ManyLawNewton too
        return f"; Newton: plain, on the laws' {reduced} coordinates"
    where = "all unknowns" if isinstance(newton, Full) else \
        f"the laws' {reduced} coordinates"
    return f"; Newton: SNES {newton.snes.getType()} on {where}"
