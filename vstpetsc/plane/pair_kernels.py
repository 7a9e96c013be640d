"""The slab terms of every interface node pair at once (interface.md,
[[interface]]): along each pair's normal the 1-D penalty pair
(vstpetsc.kernels.gap.pair_integrals), along its tangent, with friction, the
1-D Coulomb slab kernel (vstpetsc.kernels.coulomb.friction_integrals) whose
limit follows that normal force: the power penalty's N = k max(0, -g)
inside the slab, the seed's slab mean.

``evaluate`` returns per pair the OUT numbers of native/plane_pairs.c
(its comment lists them): compiled, one call for all pairs, when the
native library is built; else the same kernels in Python, a loop over the
pairs (what the compiled loop is held to in tests/test_plane_pair_laws.py).
"""

import ctypes

import numpy as np

from vstpetsc.errors import SolveFailed
from vstpetsc.kernels.coulomb import friction_integrals, penalty_normal
from vstpetsc.kernels.gap import gap_coefficients, pair_integrals

OUT = 18
F_N, W_N, F_T, W_T = slice(0, 2), slice(2, 6), slice(6, 8), slice(8, 12)
IMPULSE, STRETCH, SLIP, DISSIPATED, SHEAR, ACTED = 12, 13, 14, 15, 16, 17

_P = ctypes.c_void_p


class _Pairs(ctypes.Structure):
    """The C struct PlanePairs of plane_pairs.c, field for field."""

    _fields_ = [("m", ctypes.c_int), ("power", ctypes.c_int), ("dt", ctypes.c_double),
                ("gap", _P), ("y", _P), ("w", _P), ("kt", _P), ("mu", _P), ("stretch", _P),
                ("out", _P)]


def _compiled():
    from vstpetsc import native

    lib = native.library()
    if lib is None:
        return None
    fn = lib.vst_plane_pairs
    fn.argtypes, fn.restype = [_P], ctypes.c_int
    return fn


def _ptr(a):
    return a.ctypes.data_as(_P)


class PairKernels:
    """The kernels of ``m`` pairs of one formulation (``power``) with
    per-pair penalty ``w``, tangential stiffness ``kt`` (0: no friction)
    and coefficient ``mu``; ``compiled`` False forces the Python loop."""

    def __init__(self, w, kt, mu, dt, power, compiled=True):
        self.w, self.kt, self.mu = (np.ascontiguousarray(a, dtype=float) for a in (w, kt, mu))
        self.dt, self.power = float(dt), bool(power)
        self.m = self.w.size
        self.out = np.zeros((self.m, OUT))
        self.fn = _compiled() if compiled else None
        # the compiled call's arguments bound once to buffers of their own (a
        # struct a call cost 40 us: 0.5 s of a 1 m rockfill dam's 1.5 s run)
        self.gap, self.y, self.stretch = np.zeros(self.m), np.zeros((self.m, 4)), \
            np.zeros(self.m)
        if self.fn is not None:
            self.struct = _Pairs(self.m, int(self.power), self.dt, *(_ptr(a) for a in (
                self.gap, self.y, self.w, self.kt, self.mu, self.stretch, self.out)))
            self.args = ctypes.byref(self.struct)

    def evaluate(self, gap, y, stretch):
        """(m, OUT) for the gaps at the slab's start ``gap`` (m,), the pair
        coordinates ``y`` (m, 4) and the stretches ``stretch`` (m,)."""
        self.gap[:], self.y[:], self.stretch[:] = gap, y, stretch
        if self.fn is None:
            return self._python(self.gap, self.y, self.stretch)
        code = self.fn(self.args)
        if code:
            raise SolveFailed(f"interface pair {code - 1}: the friction's stick-slip "
                              "switches did not settle in the slab")
        return self.out

    def _python(self, gap, y, stretch):
        out = self.out
        out[:] = 0.0
        for p in range(self.m):
            out[p] = one_pair(gap[p], *y[p], stretch[p], self.w[p], self.kt[p], self.mu[p],
                              self.dt, self.power)
        return out


def one_pair(gap, d1, d2, q1, q2, stretch, w, kt, mu, dt, power):
    """The OUT numbers of one pair (plane_pairs.c's one_pair)."""
    o = np.zeros(OUT)
    G = pair_integrals(float(gap), float(d1), float(d2), dt, power)
    if G is None:
        return o
    o[F_N] = -w * G[0], -w * G[1]
    o[W_N] = [w * g for g in G[2:]]
    o[IMPULSE], o[ACTED] = -w * (G[0] + G[1]), 1.0
    if kt <= 0.0:
        return o
    if power:
        normal, pieces = penalty_normal(*gap_coefficients(float(gap), float(d1), float(d2), dt),
                                        w)
    else:
        normal, pieces = (-w * (G[0] + G[1]) / dt, 0.0, 0.0), [(0.0, 1.0)]
    try:
        f = friction_integrals(float(stretch), -float(q1), -float(q2), dt, kt, mu, normal,
                               pieces)
    except ArithmeticError as exc:
        raise SolveFailed(f"interface pair: {exc}") from None
    o[F_T] = f.f1, f.f2
    o[W_T] = -f.d11, -f.d12, -f.d21, -f.d22
    o[STRETCH], o[SLIP] = f.stretch, f.slip
    o[DISSIPATED], o[SHEAR] = f.dissipation + f.released, f.f1 + f.f2
    return o
