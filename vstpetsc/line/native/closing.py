"""The end of a slab in compiled code (slab_close.c): the displacements,
end velocities, elongations, their envelopes, the state's energies and
the running sum b += G z in three vectorised loops, where the Python path
makes a dozen numpy calls and a PETSc product (each ~1 us at 100
elements, and one memory pass each at 10 000).  On several ranks each
rank closes its own nodes; the z of the nodes just beyond its ends come
from the neighbours through a halo (a PETSc scatter of four numbers,
built by the solver: no PETSc here)."""

import ctypes

import numpy as np


from vstpetsc.line import bands
from vstpetsc.native import bind, library

_P = ctypes.c_void_p
_D = ctypes.c_double


class _Close(ctypes.Structure):
    """The C struct Close of slab_close.c, field for field."""

    _fields_ = [("nodes", ctypes.c_int), ("x", _P), ("b", _P), ("left", _P), ("diag", _P),
                ("right", _P), ("v1", _D), ("v2", _D), ("u", _P), ("v", _P),
                ("d", _P), ("lo", _P), ("hi", _P), ("m_diag", _P), ("m_off", _P),
                ("stiffness", _P), ("kinetic", _D), ("strain", _D), ("z_left", _P),
                ("z_right", _P), ("u_right", _P)]


def _doubles(a):
    return np.ascontiguousarray(a, dtype=np.float64)


class SlabClose:
    """The compiled end of a slab for ``solver`` (a SlabSolver),
    :class:`vstpetsc.line.solver.slab_end.SlabEnd`'s methods: it updates the
    solver's own arrays in place (u, v, the envelope's elongations and
    bounds, b, the u of the next rank's first node).  ``halo`` (several
    ranks): refreshed by calling it (collective), its ``z_left`` and
    ``z_right`` (None where the mesh ends) then hold the z of nodes n0 - 1
    and n1."""

    def __init__(self, lib, solver, ops, halo=None):
        n0, n1 = solver.space.nodes
        band = bands.increment_bands(ops, solver.dt, n0, n1)            # (nl, 2, 3)
        env = solver.envelope
        # strain 1/2 sum (-k_off) d^2 over the pairs of owned nodes
        self.arrays = {"x": solver.x, "b": solver.br, "u": solver.u, "v": solver.v,
                       "d": env.buf, "lo": env.lo, "hi": env.hi,
                       **{name: _doubles(band[:, :, j]).ravel()        # per dof row
                          for j, name in enumerate(("left", "diag", "right"))},
                       **{name: _doubles(a) for name, a in (
                           ("m_diag", ops.m_diag[n0:n1]), ("m_off", ops.m_off[n0:n1 - 1]),
                           ("stiffness", -ops.k_off[n0:n1 - 1]))}}
        self.halo = halo
        if halo is not None:
            self.arrays.update({name: a for name, a in (
                ("z_left", halo.z_left), ("z_right", halo.z_right),
                ("u_right", solver.u_ghost if halo.z_right is not None else None))
                if a is not None})
        v1, v2 = solver.V[1]
        # the arrays the struct points into live as long as it does (arrays)
        self.ctx = bind(_Close(nodes=n1 - n0, v1=v1, v2=v2), self.arrays)
        self.lib, self.ref = lib, ctypes.addressof(self.ctx)

    @classmethod
    def of(cls, solver, ops, use, halo=None):
        """The compiled close of ``solver`` when ``use`` and the library is
        built (on several ranks with ``halo``); None otherwise."""
        lib = library() if use else None
        return None if lib is None else cls(lib, solver, ops, halo)

    def close(self):
        """u += z_2, v = V_1 z, the elongations and their envelopes, the
        state's energies and b += G z, in one call (after the halo's
        exchange on several ranks)."""
        if self.halo is not None:
            self.halo()
        self.lib.vst_close(self.ref)

    def velocities(self):
        """Nothing: v is formed by every close."""

    def energies(self):
        """(kinetic, strain) energy at the end of the last closed slab; None
        on several ranks (each rank's sums are partial)."""
        if self.halo is not None:
            return None
        return self.ctx.kinetic, self.ctx.strain
