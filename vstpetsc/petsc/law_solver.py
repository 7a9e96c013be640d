"""The nonlinear laws inside a slab: whether any is active for the law-free
solution, Newton when one is (:mod:`vstpetsc.petsc.newton`), and what their
converged terms leave in the running right-hand side."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.errors import SolveFailed
from vstpetsc.lawset import LawSet
from vstpetsc.petsc.linear import reason_name
from vstpetsc.petsc.newton import Condensed, Coupling, Full


class LawSolver:
    """The model's nonlinear laws on the solver's space (``active`` False
    when there are none)."""

    def __init__(self, model, options, solver):
        self.laws = LawSet(model.nonlinear)
        self.active = self.laws.size > 0
        self.newton = None
        self.rhs = np.zeros(self.laws.size)     # W r_laws of the last slab
        self.work = 0.0                         # c . v the laws took, summed
        if self.active:
            space = solver.space
            self.coupling = Coupling(self.laws, solver.X, space.nodes, solver.W, solver.V,
                                     solver.linear)
            self.newton = Condensed(self.coupling, options.fd_jacobian,
                                    space.comm.getRank()) \
                if options.newton == "condensed" else \
                Full(self.coupling, options.fd_jacobian, solver.A, solver.linear, space)

    def solve(self, X, b, dt, slab_index):
        """Newton if a law is active for the law-free solution X (updated in
        place); returns the Newton iterations."""
        self.laws.start_slab(dt)
        _, active = self.laws.residual(self.coupling.velocities(X))
        self.rhs[:] = 0.0
        if not active:
            return 0
        self.newton.solve(X, b)
        snes = self.newton.snes
        reason = snes.getConvergedReason()
        if reason <= 0:
            raise SolveFailed(f"slab {slab_index}: SNES did not converge "
                              f"({reason_name(PETSc.SNES.ConvergedReason, reason)}"
                              f" after {snes.getIterationNumber()} Newton iterations)")
        s = self.coupling.velocities(X)
        c, _ = self.laws.residual(s)
        self.rhs[:] = self.coupling.WE @ c
        self.work += float(c @ s)
        return snes.getIterationNumber()

    def advance(self, X, b, carry):
        """Close the slab: the laws' displacements, their terms carried over
        in the running sum b (``carry`` = W (T - I) W^-1 per node)."""
        self.laws.u += self.coupling.gather(X)[1::2]
        if self.rhs.any():
            self.coupling.gather.add_rows(b, (self.rhs.reshape(-1, 2) @ carry.T).ravel())

    def set_state(self, u):
        self.laws.u[:] = u[self.laws.nodes]
