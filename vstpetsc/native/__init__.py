"""Compiled kernels: the plain Newton for penalty contact pairs in C
(penalty_newton.c), the same operations as
:class:`vstpetsc.reduced_newton.ReducedNewton` so the answer is the
Python one (bit for bit while at most one pair acts at a time).

`make install` builds ``libvstnative.so`` next to this file with the
system's C compiler; without it (a plain ``pip install``) :func:`library`
returns None and the Python Newton runs.  ``-vst_native 0`` turns it off.
"""

import ctypes
import os

import numpy as np

from vstpetsc.errors import SolveFailed

HERE = os.path.dirname(os.path.abspath(__file__))
LIBRARY = os.path.join(HERE, "libvstnative.so")
MAX_LAWS = 32
_loaded = []

_P = ctypes.c_void_p


class _Newton(ctypes.Structure):
    """The C struct Newton of penalty_newton.c, field for field."""

    _fields_ = [("laws", ctypes.c_int), ("max_it", ctypes.c_int), ("rtol", ctypes.c_double),
                ("atol", ctypes.c_double), ("dt", ctypes.c_double), ("S", _P), ("y0", _P),
                ("y", _P), ("gn", _P), ("w", _P), ("power", _P), ("f", _P), ("out", _P),
                ("integrals", _P), ("hit", _P), ("iterations", ctypes.c_int),
                ("norm", ctypes.c_double)]


def library():
    """The compiled kernels (None when not built)."""
    if not _loaded:
        lib = None
        if os.path.exists(LIBRARY):
            lib = ctypes.CDLL(LIBRARY)
            lib.vst_penalty_newton.argtypes = [_P, ctypes.c_int]
            lib.vst_penalty_newton.restype = ctypes.c_int
        _loaded.append(lib)
    return _loaded[0]


def takes(laws):
    """Whether the C Newton can solve for these laws: penalty pairs only
    (a ``penalty`` and a ``power`` flag each), at most MAX_LAWS."""
    from vstpetsc.laws.penalty import PenaltyContact

    return 0 < len(laws) <= MAX_LAWS and all(type(law) is PenaltyContact for law in laws)


class NativeNewton:
    """:class:`~vstpetsc.reduced_newton.ReducedNewton` for penalty pairs,
    its iteration in C; after :meth:`solve` the LawSet's ``f`` and every
    pair's ``last`` integrals are those of the last evaluation."""

    def __init__(self, lawset, S, rtol=1e-12, atol=1e-50, max_it=30):
        self.lib = library()
        self.lawset, self.laws = lawset, lawset.laws
        L = len(self.laws)
        self.S = np.ascontiguousarray(S, dtype=np.float64)
        self.y0, self.y, self.f = (np.zeros(2 * L) for _ in range(3))
        self.gn = np.zeros(L)
        self.w = np.array([law.penalty for law in self.laws], dtype=np.float64)
        self.power = np.array([law.power for law in self.laws], dtype=np.intc)
        self.out, self.integrals = np.zeros(6 * L), np.zeros(6 * L)
        self.hit = np.zeros(L, dtype=np.intc)
        self.max_it = max_it
        self.ctx = _Newton(L, max_it, rtol, atol, lawset.laws[0].dt if L else 0.0,
                           *(a.ctypes.data for a in (self.S, self.y0, self.y, self.gn, self.w,
                                                     self.power, self.f, self.out,
                                                     self.integrals, self.hit)), 0, 0.0)
        self.ref = ctypes.addressof(self.ctx)
        self.iterations = 0

    def solve(self, y0, slab_index, start=None):
        """y with r(y) = 0 from ``start`` (default y0), as ReducedNewton."""
        self.y0[:] = y0
        if start is not None:
            self.y[:] = start
        self.gn[:] = [law.gn for law in self.laws]
        code = self.lib.vst_penalty_newton(self.ref, start is not None)
        self.lawset.f[:] = self.f
        integrals, hit = self.integrals.tolist(), self.hit.tolist()
        for j, law in enumerate(self.laws):
            law.last = tuple(integrals[6 * j:6 * j + 6]) if hit[j] else None
        if code != 0:
            raise SolveFailed(f"slab {slab_index}: Newton did not converge (DIVERGED_MAX_IT "
                              f"after {self.max_it} Newton iterations, residual "
                              f"{self.ctx.norm:.3g})")
        self.iterations = self.ctx.iterations
        return self.y
