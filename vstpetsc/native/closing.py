"""The end of a slab on one rank in compiled code (slab_close.c): the
displacements, end velocities, elongations, their envelopes and the
state's energies in one pass over the nodes, and the running sum
b += G z in another, where the Python path makes a dozen numpy calls
and a PETSc product (each ~1 us at 100 elements, and one memory pass
each at 10 000)."""

import ctypes

import numpy as np

from vstpetsc import slab
from vstpetsc.native import library

_P = ctypes.c_void_p


class _Close(ctypes.Structure):
    """The C struct Close of slab_close.c, field for field."""

    _fields_ = [("nodes", ctypes.c_int), ("x", _P), ("b", _P), ("band", _P),
                ("v1", ctypes.c_double), ("v2", ctypes.c_double), ("u", _P), ("v", _P),
                ("d", _P), ("lo", _P), ("hi", _P), ("m_diag", _P), ("m_off", _P),
                ("stiffness", _P), ("kinetic", ctypes.c_double), ("strain", ctypes.c_double)]


class SlabClose:
    """The compiled end of a slab for ``solver`` (a SlabSolver on one rank),
    :class:`vstpetsc.petsc.slab_end.SlabEnd`'s methods: it updates the
    solver's own arrays in place (u, v, the envelope's elongations and
    bounds, b)."""

    def __init__(self, lib, solver, ops):
        n = ops.m_diag.size
        self.band = slab.increment_bands(ops, solver.dt, 0, n)
        self.m_off = np.ascontiguousarray(ops.m_off, dtype=np.float64)
        self.m_diag = np.ascontiguousarray(ops.m_diag, dtype=np.float64)
        self.stiffness = np.ascontiguousarray(-ops.k_off, dtype=np.float64)
        env = solver.envelope
        arrays = (solver.x, solver.br, self.band)
        self.ctx = _Close(n, *(a.ctypes.data for a in arrays), *solver.V[1],
                          *(a.ctypes.data for a in (solver.u, solver.v, env.buf, env.lo, env.hi,
                                                    self.m_diag, self.m_off, self.stiffness)),
                          0.0, 0.0)
        # the arrays the struct points into live as long as it does
        self._keep = (solver.x, solver.br, solver.u, solver.v, env.buf, env.lo, env.hi)
        self.lib, self.ref = lib, ctypes.addressof(self.ctx)

    @classmethod
    def of(cls, solver, ops, use):
        """The compiled close of ``solver`` when ``use`` and the library is
        built and the solver runs on one rank; None otherwise."""
        lib = library() if use and solver.serial else None
        return None if lib is None else cls(lib, solver, ops)

    def state(self):
        """u += z_2, v = V_1 z, the elongations and their envelopes."""
        self.lib.vst_close_state(self.ref)

    def add_increment(self):
        """b += G z."""
        self.lib.vst_band_add(self.ref)

    def velocities(self):
        """Nothing: v is formed by every close."""

    def energies(self):
        """(kinetic, strain) energy at the end of the last closed slab."""
        return self.ctx.kinetic, self.ctx.strain
