"""The end of a slab with numpy and PETSc, on any number of ranks: the
displacements, the envelopes, the running sum b += G z and the end
velocities for output.  :class:`vstpetsc.line.native.closing.SlabClose` does
the same in compiled code (and sums the state's energies too); this path
runs with ``-vst_native 0`` or without the compiled library, and is the
reference the compiled one is tested against."""

import numpy as np


from vstpetsc.line import bands
from vstpetsc.line.solver.space import DofGather


class SlabEnd:
    """The end of a slab of ``solver`` (a SlabSolver), on its own arrays."""

    def __init__(self, solver, ops):
        self.solver = solver
        n0, n1 = solver.space.nodes
        self.G = Increment(ops, solver.dt, solver.space, solver.x)
        self.ghost = DofGather(solver.X, [2 * n1 + 1] if solver.envelope.ghost else [],
                               (n0, n1))
        self._z, self._V1 = solver.x.reshape(-1, 2), solver.V[1].copy()
        self._v2 = np.zeros(n1 - n0)

    def close(self):
        """u += z_2, the envelopes and b += G z."""
        self._state()
        self.G.add_to(self.solver.X, self.solver.br)

    def _state(self):
        s = self.solver
        np.add(s.u, s.x[1::2], out=s.u)
        if not s.serial:                     # collective, also without a ghost
            ghost = self.ghost(s.X)
            if s.envelope.ghost:
                s.u_ghost[0] += ghost[0]
        s.envelope.update(s.u, s.u_ghost[0])

    def velocities(self):
        """v = z_1 V_1[0] + z_2 V_1[1] into the solver's v, in two ufuncs, not
        BLAS (which may fuse the multiply-add), so that every path has the
        same bits."""
        z, V1, v = self._z, self._V1, self.solver.v
        np.multiply(z[:, 0], V1[0], out=v)
        np.multiply(z[:, 1], V1[1], out=self._v2)
        np.add(v, self._v2, out=v)

    def energies(self):
        """None: the LineEnergyBook sums the state's energies."""
        return None


class Increment:
    """The running-sum increment b += G z in the difference form of
    bands.increment_bands, on this rank's rows: numpy on the ghosted local
    vector of the DMDA (several ranks) or on z itself (one rank), with
    slab_close.c's operations in its order (elementwise ufuncs, each
    rounded), so that every path and every number of ranks gives the same
    bits."""

    def __init__(self, ops, dt, space, x):
        n0, n1 = space.nodes
        nl = n1 - n0
        band = bands.increment_bands(ops, dt, n0, n1)                   # (nl, 2, 3)
        self.left, self.diag, self.right = (band[:, :, j].copy() for j in range(3))
        self.first = 1 if n0 == 0 else 0              # owned rows with a left neighbour
        self.last = nl - 1 if n1 == ops.m_diag.size else nl   # ... with a right one
        self.space, self.x = space, x
        self.local = space.da.createLocalVec() if space.comm.getSize() > 1 else None
        self.offset = 1 if self.local is not None and n0 > 0 else 0    # a left ghost node
        self.s, self.t = np.zeros((nl, 2)), np.zeros((nl, 2))

    def _z(self, X):
        """z of the owned nodes with their neighbours, (nodes, 2)."""
        if self.local is None:
            return self.x.reshape(-1, 2)
        self.space.da.globalToLocal(X, self.local)
        return self.local.getArray(readonly=True).reshape(-1, 2)

    def add_to(self, X, b):
        """b += G X (b: this rank's array of the running sum)."""
        z_all, o = self._z(X), self.offset
        s, t, f, last = self.s, self.t, self.first, self.last
        z = z_all[o:o + s.shape[0]]
        s[:] = 0.0
        np.subtract(z_all[o - 1 + f:o - 1 + s.shape[0]], z[f:], out=t[f:])
        np.multiply(self.left[f:], t[f:], out=t[f:])
        s[f:] += t[f:]
        np.multiply(self.diag, z, out=t)
        s += t
        np.subtract(z_all[o + 1:o + 1 + last], z[:last], out=t[:last])
        np.multiply(self.right[:last], t[:last], out=t[:last])
        s[:last] += t[:last]
        rows = b.reshape(-1, 2)
        rows += s
