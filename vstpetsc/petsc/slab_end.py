"""The end of a slab with numpy and PETSc, on any number of ranks: the
displacements, the envelopes, the running sum b += G z and the end
velocities for output.  On one rank :class:`vstpetsc.native.closing.SlabClose`
does the same in compiled code (and sums the state's energies too)."""

import numpy as np

from vstpetsc.petsc.matrices import Increment
from vstpetsc.petsc.space import DofGather


class SlabEnd:
    """The end of a slab of ``solver`` (a SlabSolver), on its own arrays."""

    def __init__(self, solver, ops):
        self.solver = solver
        n0, n1 = solver.space.nodes
        self.G = Increment(ops, solver.dt, solver.space, solver.b)
        self.ghost = DofGather(solver.X, [2 * n1 + 1] if solver.envelope.ghost else [],
                               (n0, n1))
        self._z, self._V1 = solver.x.reshape(-1, 2), solver.V[1].copy()
        self._v2 = np.zeros(n1 - n0)

    def close(self):
        """u += z_2, the envelopes and b += G z."""
        self._state()
        self.G.add_to(self.solver.X, self.solver.b)

    def _state(self):
        s = self.solver
        np.add(s.u, s.x[1::2], out=s.u)
        if not s.serial:                     # collective, also without a ghost
            ghost = self.ghost(s.X)
            if s.envelope.ghost:
                s.u_ghost += ghost[0]
        s.envelope.update(s.u, s.u_ghost)

    def velocities(self):
        """v = z_1 V_1[0] + z_2 V_1[1] into the solver's v, in two ufuncs, not
        BLAS (which may fuse the multiply-add), so that every path has the
        same bits."""
        z, V1, v = self._z, self._V1, self.solver.v
        np.multiply(z[:, 0], V1[0], out=v)
        np.multiply(z[:, 1], V1[1], out=self._v2)
        np.add(v, self._v2, out=v)

    def energies(self):
        """None: the EnergyBook sums the state's energies."""
        return None
