"""The end of a slab on one rank in compiled code (slab_close.c): the
displacements, end velocities, elongations, their envelopes, the
state's energies and the running sum b += G z in three vectorised
loops, where the Python path makes a dozen numpy calls and a PETSc
product (each ~1 us at 100 elements, and one memory pass each at
10 000)."""

import ctypes

import numpy as np

from vstpetsc import slab
from vstpetsc.native import library

_P = ctypes.c_void_p
_D = ctypes.c_double


class _Close(ctypes.Structure):
    """The C struct Close of slab_close.c, field for field."""

    _fields_ = [("nodes", ctypes.c_int), ("x", _P), ("b", _P), ("left", _P), ("diag", _P),
                ("right", _P), ("v1", _D), ("v2", _D), ("u", _P), ("v", _P),
                ("d", _P), ("lo", _P), ("hi", _P), ("m_diag", _P), ("m_off", _P),
                ("stiffness", _P), ("kinetic", _D), ("strain", _D)]


def _doubles(a):
    return np.ascontiguousarray(a, dtype=np.float64)


class SlabClose:
    """The compiled end of a slab for ``solver`` (a SlabSolver on one rank),
    :class:`vstpetsc.petsc.slab_end.SlabEnd`'s methods: it updates the
    solver's own arrays in place (u, v, the envelope's elongations and
    bounds, b)."""

    def __init__(self, lib, solver, ops):
        n0, n1 = solver.space.nodes
        band = slab.increment_bands(ops, solver.dt, n0, n1)       # (owned nodes, 2, 3)
        rows = [_doubles(band[:, :, j]).ravel() for j in range(3)]    # per dof row
        # strain 1/2 sum (-k_off) d^2 of the owned pairs
        energy = [_doubles(a) for a in (ops.m_diag[n0:n1], ops.m_off[n0:n1 - 1],
                                        -ops.k_off[n0:n1 - 1])]
        env = solver.envelope
        self._keep = (solver.x, solver.br, *rows, solver.u, solver.v, env.buf, env.lo,
                      env.hi, *energy)
        p = [a.ctypes.data for a in self._keep]
        self.ctx = _Close(n1 - n0, *p[:5], *solver.V[1], *p[5:], 0.0, 0.0)
        # the arrays the struct points into live as long as it does (_keep)
        self.lib, self.ref = lib, ctypes.addressof(self.ctx)

    @classmethod
    def of(cls, solver, ops, use):
        """The compiled close of ``solver`` when ``use`` and the library is
        built and the solver runs on one rank; None otherwise."""
        lib = library() if use and solver.serial else None
        return None if lib is None else cls(lib, solver, ops)

    def close(self):
        """u += z_2, v = V_1 z, the elongations and their envelopes, the
        state's energies and b += G z, in one call."""
        self.lib.vst_close(self.ref)

    def velocities(self):
        """Nothing: v is formed by every close."""

    def energies(self):
        """(kinetic, strain) energy at the end of the last closed slab."""
        return self.ctx.kinetic, self.ctx.strain


class GhostedClose(SlabClose):
    """The compiled end of a slab on one of several ranks, over its owned
    nodes (slab_close.c's vst_close_ghosted): the neighbouring ranks' end
    nodes come by ``gather`` (a DofGather of their four dofs, collective),
    the pair that ends on the next rank's node takes its displacement
    (the solver's ``u_ghost``).  The same bits as the numpy path
    (:class:`vstpetsc.petsc.slab_end.SlabEnd`) on any number of ranks; the
    energies are the EnergyBook's."""

    def __init__(self, lib, solver, ops, gather):
        super().__init__(lib, solver, ops)
        n0, n1 = solver.space.nodes
        self.has_left, self.has_right = int(n0 > 0), int(n1 < ops.m_diag.size)
        self.solver, self.gather = solver, gather
        self.ghost = np.zeros(5)          # z before, z after, u after
        self.ghost_ref = self.ghost.ctypes.data

    @classmethod
    def of(cls, solver, ops, use, gather):
        """The compiled close of ``solver`` on one of several ranks when
        ``use`` and the library is built (None otherwise); ``gather()``
        makes the DofGather of :meth:`ghost_dofs`."""
        lib = library() if use and not solver.serial else None
        if lib is None:
            return None
        return cls(lib, solver, ops, gather(cls.ghost_dofs(solver, ops.m_diag.size)))

    @staticmethod
    def ghost_dofs(solver, nnodes):
        """The global dofs of the nodes before and after this rank's."""
        n0, n1 = solver.space.nodes
        before = [2 * n0 - 2, 2 * n0 - 1] if n0 > 0 else []
        after = [2 * n1, 2 * n1 + 1] if n1 < nnodes else []
        return before + after

    def close(self):
        values, g, s = self.gather(self.solver.X), self.ghost, self.solver
        if self.has_left:
            g[0:2] = values[0:2]
        if self.has_right:
            g[2:4] = values[-2:]
            s.u_ghost += values[-1]
            g[4] = s.u_ghost
        self.lib.vst_close_ghosted(self.ref, self.ghost_ref, self.has_left, self.has_right)

    def energies(self):
        """None: the EnergyBook sums the state's energies over the ranks."""
        return None
