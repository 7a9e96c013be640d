"""The compiled Newton of 1-D penalty pairs and their Coulomb friction
(penalty_newton.c, coulomb.h): the same operations as
:class:`vstpetsc.line.reduced_newton.ReducedNewton`, so that from the same
start its answer is the Python one (bit for bit while at most one law acts
at a time; a pair with friction is two); and a whole slab of the pairs in
one call (:class:`PenaltySlab`, the default), whose products with small
matrices are plain loops instead of numpy's BLAS, so a run agrees with the
Python one to rounding."""

import ctypes

import numpy as np

from vstpetsc.kernels.coulomb import FrictionSlab
from vstpetsc.line.laws.friction import CoulombFriction
from vstpetsc.line.laws.penalty import PenaltyContact
from vstpetsc.line.reduced_newton import not_converged
from vstpetsc.native import library

MAX_LAWS = 32
_P = ctypes.c_void_p


class _Newton(ctypes.Structure):
    """The C struct Newton of penalty_newton.c, field for field."""

    _fields_ = [("laws", ctypes.c_int), ("max_it", ctypes.c_int), ("rtol", ctypes.c_double),
                ("atol", ctypes.c_double), ("dt", ctypes.c_double), ("S", _P), ("y0", _P),
                ("y", _P), ("gn", _P), ("w", _P), ("power", _P), ("f", _P), ("out", _P),
                ("integrals", _P), ("hit", _P), ("iterations", ctypes.c_int),
                ("norm", ctypes.c_double), ("kind", _P), ("partner", _P), ("friction", _P),
                ("stretch", _P), ("fslab", _P), ("unsettled", ctypes.c_int)]


class _Slab(ctypes.Structure):
    """The C struct Slab of penalty_newton.c, field for field."""

    _fields_ = [("nodes", ctypes.c_int), ("acted", ctypes.c_int), ("u", _P), ("node", _P),
                ("sign", _P), ("g0", _P), ("R0", _P), ("xE", _P), ("f_prev", _P),
                ("work", _P), ("ran", ctypes.c_int), ("serial", ctypes.c_int), ("x", _P),
                ("b", _P), ("local", _P), ("carry", _P), ("groups", ctypes.c_int),
                ("span", _P), ("first", _P), ("cols", _P), ("Z", _P), ("pieces", _P),
                ("ends", _P)]


def takes(laws):
    """Whether the C Newton can solve for these laws: penalty pairs (a
    ``penalty`` and a ``power`` flag each) and the Coulomb friction of a
    pair before it, at most MAX_LAWS."""
    seen = set()
    for law in laws:
        if type(law) is CoulombFriction and id(law.pair) not in seen:
            return False
        if type(law) not in (PenaltyContact, CoulombFriction):
            return False
        seen.add(id(law))
    return 0 < len(laws) <= MAX_LAWS


class Frictions:
    """The friction laws among a compiled Newton's laws, as the C reads
    them: each one's kind and pair, its constants, the wall's velocities
    and stretch of the slab (:meth:`load`), and its FrictionSlab back
    (:meth:`finish`).  The laws keep their state (stretch, slip): their
    finish_slab, values and restore are the Python path's."""

    INPUTS, OUTPUTS = 5, 10     # penalty_newton.c FRICTION_INPUTS, FRICTION_OUTPUTS

    def __init__(self, laws):
        L = len(laws)
        self.kind, self.partner = np.zeros(L, dtype=np.intc), np.full(L, -1, dtype=np.intc)
        self.inputs, self.stretch = np.zeros(self.INPUTS * L), np.zeros(L)
        self.fslab = np.zeros(self.OUTPUTS * L)
        self.laws = [(j, law) for j, law in enumerate(laws) if type(law) is CoulombFriction]
        where = {id(law): j for j, law in enumerate(laws)}
        for j, law in self.laws:
            self.kind[j], self.partner[j] = 1, where[id(law.pair)]
            self.inputs[self.INPUTS * j:self.INPUTS * j + 3] = law.mu, law.stiffness, \
                law.wall_sign

    def arrays(self):
        """The C struct's friction fields, in its order."""
        return (self.kind, self.partner, self.inputs, self.stretch, self.fslab)

    def load(self):
        """Each law's stretch at t^n and the wall's velocities at the slab's
        ends (its start_time's)."""
        for j, law in self.laws:
            self.stretch[j] = law.stretch
            self.inputs[self.INPUTS * j + 3:self.INPUTS * j + 5] = law.wall_v

    def finish(self, hit):
        """Each law's FrictionSlab of the last evaluation (None where its
        pair did not act), as its force() leaves it."""
        if not self.laws:
            return
        values, n = self.fslab.tolist(), self.OUTPUTS
        for j, law in self.laws:
            law.last = FrictionSlab(*values[n * j:n * j + n]) if hit[j] else None


class NativeNewton:
    """:class:`~vstpetsc.line.reduced_newton.ReducedNewton` for penalty pairs,
    its iteration in C; after :meth:`solve` the LawSet's ``f`` and every
    pair's ``last`` integrals are those of the last evaluation."""

    def __init__(self, lawset, S, rtol=1e-12, atol=1e-50, max_it=30):
        self.lib = library()
        self.lawset, self.laws = lawset, lawset.laws
        L = len(self.laws)
        self.S = np.ascontiguousarray(S, dtype=np.float64)
        self.y0, self.y = np.zeros(2 * L), np.zeros(2 * L)
        self.f = lawset.f             # the C Newton writes the LawSet's terms itself
        self.gn = np.zeros(L)
        # a friction law's entries unused (its pair's are read)
        self.w = np.array([getattr(law, "penalty", 0.0) for law in self.laws], dtype=np.float64)
        self.power = np.array([getattr(law, "power", 0) for law in self.laws], dtype=np.intc)
        self.frictions = Frictions(self.laws)
        self.pairs = [(j, law) for j, law in enumerate(self.laws)
                      if type(law) is not CoulombFriction]
        self.out, self.integrals = np.zeros(6 * L), np.zeros(6 * L)
        self.hit = np.zeros(L, dtype=np.intc)
        self.max_it = max_it
        self.ctx = _Newton(L, max_it, rtol, atol, lawset.laws[0].dt,
                           *(a.ctypes.data for a in (self.S, self.y0, self.y, self.gn, self.w,
                                                     self.power, self.f, self.out,
                                                     self.integrals, self.hit)), 0, 0.0,
                           *(a.ctypes.data for a in self.frictions.arrays()), 0)
        self.ref = ctypes.addressof(self.ctx)
        self.iterations = 0

    def solve(self, y0, slab_index, start=None):
        """y with r(y) = 0 from ``start`` (default y0), as ReducedNewton."""
        self.y0[:] = y0
        if start is not None:
            self.y[:] = start
        self.gn[:] = [getattr(law, "gn", 0.0) for law in self.laws]
        self.frictions.load()
        code = self.lib.vst_penalty_newton(self.ref, start is not None)
        return self._finish(code, slab_index)

    def _finish(self, code, slab_index, ends=None):
        """The outputs of the C Newton into the LawSet and the pairs (with
        ``ends``, PenaltySlab's, their gaps at t^n and pieces too)."""
        integrals, hit, y = self.integrals.tolist(), self.hit.tolist(), self.y.tolist()
        gn, count = (self.gn.tolist(), self.pieces.tolist()) if ends else (None, None)
        self.frictions.finish(hit)
        for j, law in self.pairs:
            if gn:
                law.gn = gn[j]
            if hit[j]:      # the converged rates: the pair's events (finish_slab)
                law.last = tuple(integrals[6 * j:6 * j + 6])
                law.rates = (y[2 * j], y[2 * j + 1])
                # PenaltySlab gives its pieces of the slab, else finish_slab finds them
                law.pieces = [(ends[6 * j + 2 * i], ends[6 * j + 2 * i + 1])
                              for i in range(count[j])] if ends else None
            else:
                law.last = law.pieces = None
        if code == 3:
            raise ArithmeticError("coulomb: friction switches did not settle in a slab")
        if code != 0:
            raise not_converged(slab_index, self.max_it, self.ctx.norm)
        self.iterations = self.ctx.iterations
        return self.y


class PenaltySlab(NativeNewton):
    """A whole slab of penalty pairs in one call (the LawSolver's start,
    coordinates, test, start guess, Newton and work sums): the same steps
    as the Python ones, equal to rounding (the products with R0 and S are
    plain loops here, BLAS in numpy)."""

    def __init__(self, lawset, S, R0, f_prev, **kw):
        super().__init__(lawset, S, **kw)
        L = len(self.laws)
        node = np.full(2 * L, -1, dtype=np.intc)
        sign = np.zeros(2 * L)
        for j, idx in enumerate(lawset.node_index):
            node[2 * j:2 * j + idx.size] = idx
            sign[2 * j:2 * j + idx.size] = self.laws[j].signs
        self.node, self.sign = node, sign
        self.g0 = np.array([getattr(law, "g0", 0.0) for law in self.laws], dtype=np.float64)
        self.R0 = np.ascontiguousarray(R0, dtype=np.float64)
        self.xE = np.zeros(self.R0.shape[1])
        # the caller's terms of the previous slab, read in place (and a slab's
        # that acts written there)
        self.f_prev, self.work = f_prev, np.zeros(L)
        self.u = lawset.u                      # updated in place by the LawSolver
        self.slab = _Slab(lawset.nodes.size, 0, *(a.ctypes.data for a in (
            self.u, node, sign, self.g0, self.R0, self.xE, self.f_prev, self.work)), 0)
        self.slab_ref = ctypes.addressof(self.slab)
        self.bound = self.serial = False
        # each pair's pieces of the slab where it acts (its finish_slab's)
        self.pieces, self.ends = np.zeros(L, dtype=np.intc), np.zeros(6 * L)
        self.slab.pieces, self.slab.ends = self.pieces.ctypes.data, self.ends.ctypes.data

    def bind(self, coupling, influence, b):
        """On one rank (``coupling.local`` set): the calls read x_E from the
        solver's array, subtract the pairs' influence (``influence``, a
        LawInfluence) and close the slab (:meth:`advance`) on it and on
        ``b`` (the running right-hand side's array) themselves."""
        self.bound = True
        if coupling.local is None:
            return
        ints = [np.ascontiguousarray(a, dtype=np.intc) for a in (
            coupling.local, [i for span in influence.spans for i in span],
            np.cumsum([0] + [cols.size for *_, cols in influence.groups]),
            np.concatenate([cols for *_, cols in influence.groups] or [[]]))]
        carry = np.ascontiguousarray(coupling.carry_rows, dtype=np.float64)
        Z = (ctypes.c_void_p * len(influence.columns))(
            *(z.ctypes.data for z in influence.columns))
        # the arrays the struct points into live as long as it does
        self._bound = (ints, carry, Z, coupling.array, b, influence.columns)
        slab = self.slab
        slab.x, slab.b = coupling.array.ctypes.data, b.ctypes.data
        slab.local, slab.span, slab.first, slab.cols = (a.ctypes.data for a in ints)
        slab.carry, slab.groups, slab.Z = carry.ctypes.data, len(influence.groups), \
            ctypes.addressof(Z)
        slab.serial = 1
        self.serial = True

    def advance(self, acted):
        """After :meth:`bind`: the pairs' displacements += z_2, and b
        += carry f (their terms carried over) when ``acted``."""
        self.lib.vst_penalty_advance(self.ref, self.slab_ref, int(acted))

    def run(self, acted, slab_index):
        """Solve the slab for the unknowns in ``xE`` (filled by the caller,
        or read from x after :meth:`bind`) from the terms ``f_prev`` of the
        previous slab: whether a pair acts; the LawSet's ``f`` and
        ``f_prev``, the pairs' ``last`` integrals and pieces, ``y`` and
        ``work`` are then the slab's."""
        self.slab.acted = acted
        self.frictions.load()
        code = self.lib.vst_penalty_slab(self.ref, self.slab_ref)
        if self.slab.ran:
            self._finish(code, slab_index, self.ends.tolist())
            return True
        gn = self.gn.tolist()
        for j, law in self.pairs:          # the pairs' start_slab
            law.gn = gn[j]
        if acted:                  # the laws' last evaluation: nothing in this slab
            for law in self.laws:
                law.last = None
        return False
