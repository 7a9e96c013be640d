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
        band = slab.increment_bands(ops, solver.dt, 0, ops.m_diag.size)   # (n, 2, 3)
        rows = [_doubles(band[:, :, j]).ravel() for j in range(3)]    # per dof row
        # strain 1/2 sum (-k_off) d^2
        energy = [_doubles(a) for a in (ops.m_diag, ops.m_off, -ops.k_off)]
        env = solver.envelope
        self._keep = (solver.x, solver.br, *rows, solver.u, solver.v, env.buf, env.lo,
                      env.hi, *energy)
        p = [a.ctypes.data for a in self._keep]
        self.ctx = _Close(ops.m_diag.size, *p[:5], *solver.V[1], *p[5:], 0.0, 0.0)
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
