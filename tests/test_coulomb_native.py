"""The compiled Coulomb slab kernel (vstpetsc/native/coulomb.h) is
kernels/coulomb.py friction_integrals bit for bit: the same floating-point
operations in the same order, built without fused multiply-adds
(tests/agreement.py), on many random slabs of every kind (stick, slip
either way, reversals, a gap that opens or closes and opens inside the
slab, the seed's slab-mean force on one piece, a start stretch beyond the
limit)."""

import ctypes

import numpy as np

from test_coulomb_kernel import DT, EY, KT, MU, N0, SY, bounce, opening, quadratic
from vstpetsc import native
from vstpetsc.kernels import coulomb
from vstpetsc.kernels.coulomb import friction_integrals

_D = ctypes.POINTER(ctypes.c_double)


def compiled(e_n, s1, s2, dt, k_t, mu, normal, pieces):
    """The C kernel's FrictionSlab (ArithmeticError as the Python's)."""
    lib = native.library()
    fn = lib.vst_coulomb_slab
    fn.argtypes = [ctypes.c_double] * 6 + [_D, _D, ctypes.c_int, _D]
    n = np.array(normal, dtype=float)
    p = np.array([x for piece in pieces for x in piece] or [0.0], dtype=float)
    out = np.zeros(10)
    code = fn(e_n, s1, s2, dt, k_t, mu, *(a.ctypes.data_as(_D) for a in (n, p)),
              len(pieces), out.ctypes.data_as(_D))
    if code:
        raise ArithmeticError("coulomb: friction switches did not settle in a slab")
    return coulomb.FrictionSlab(*out.tolist())


def random_slab(rng):
    """(kind, e_n, s1, s2, normal, pieces) of one random slab."""
    kind = rng.choice(["whole", "opening", "bounce", "seed", "beyond"])
    sign = rng.choice([-1.0, 1.0])
    if kind == "whole":
        normal, pieces = quadratic(rng)
    elif kind == "opening":
        normal, pieces = opening(rng)
    elif kind == "bounce":
        normal, pieces = bounce(rng)
    else:                        # the seed's mean force: constant on one piece
        normal, pieces = (N0 * rng.uniform(0.1, 2.0), 0.0, 0.0), [(0.0, 1.0)]
    limit = MU * max(normal[0], 0.0) / KT
    e_n = limit * rng.uniform(-1.0, 1.0)
    if kind == "beyond":         # projected onto the start limit: released energy
        e_n = sign * limit * rng.uniform(1.01, 3.0)
    elif rng.random() < 0.3:     # on the limit, pressed on or unloading
        e_n = sign * limit
    s = SY * rng.choice([0.1, 1.0, 5.0]) * rng.normal(0.0, 1.0, 2)
    if rng.random() < 0.2:
        s[1] = -s[0]             # reversal inside the slab
    return str(kind), e_n, float(s[0]), float(s[1]), normal, pieces


def test_compiled_kernel_is_the_python_bit_for_bit(rng):
    seen = set()
    for _ in range(20000):
        kind, e_n, s1, s2, normal, pieces = random_slab(rng)
        args = (e_n, s1, s2, DT, KT, MU, normal, pieces)
        want = friction_integrals(*args)
        got = compiled(*args)
        assert got == want, (kind, args, want, got)
        # what the slab exercised, so that every branch is known to be compared
        seen.add(kind)
        seen.add("slip+" if want.slip > 0.0 else "slip-" if want.slip < 0.0 else "stick")
        if want.released > 0.0:
            seen.add("released")
        if len(pieces) != 1 or pieces[0] != (0.0, 1.0):
            seen.add("partial")
    assert seen >= {"whole", "opening", "bounce", "seed", "beyond", "slip+", "slip-", "stick",
                    "released", "partial"}, seen


def test_compiled_kernel_on_degenerate_slabs():
    """No pieces, no motion, no friction, a rounding-negative N at an
    opening root: still the Python's bits."""
    slabs = [(0.0, SY, -SY, (N0, 0.0, 0.0), []),
             (EY, 0.0, 0.0, (N0, 0.0, 0.0), [(0.0, 1.0)]),
             (0.0, 0.0, 0.0, (6153.3304639988855, -46793.024621636374, 19786.197931696963),
              [(0.0, 0.1397604442188071)]),
             (-EY, 2.0 * SY, SY, (N0, -N0, 0.0), [(0.0, 0.5), (0.7, 1.0)])]
    for e_n, s1, s2, normal, pieces in slabs:
        for mu in (0.0, MU):
            args = (e_n, s1, s2, DT, KT, mu, normal, pieces)
            assert compiled(*args) == friction_integrals(*args)
