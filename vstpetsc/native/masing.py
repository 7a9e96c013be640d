"""The compiled slab integrals of a hysteretic soil (masing.c): one call
for every element's Q, dQ/dD and, when closing the slab, its end state;
the same operations as :func:`vstpetsc.materials.masing.slab_integrals`,
which stays the reference (``-vst_native 0``)."""

import ctypes

import numpy as np

from vstpetsc.materials import masing

_P = ctypes.c_void_p


class _Slab(ctypes.Structure):
    """The C struct MasingSlab of masing.c, field for field."""

    _fields_ = [("ne", ctypes.c_long), ("depth", ctypes.c_int), ("dt", ctypes.c_double)] + \
        [(name, _P) for name in ("G", "gref", "beta", "s", "area", "keh", "xg", "wg", "gamma",
                                 "tau", "dir", "sg", "st", "k", "D", "Q", "dQ", "gamma1",
                                 "tau1", "dir1", "sg1", "st1", "k1")] + \
        [("n", ctypes.c_long)] + \
        [(name, _P) for name in ("left", "scale", "free", "V", "W", "values", "rows", "blocks",
                                 "pbase", "pdata")] + \
        [("nb", ctypes.c_long)] + [(name, _P) for name in ("slots", "pcoef")]


def _ptr(a):
    """The address of ``a``'s data (a c_void_p field takes the int)."""
    return a.ctypes.data


class NativeMasing:
    """Q and dQ of a :class:`vstpetsc.materials.soil.HystereticSoil`'s
    slab by ``lib``; its state arrays are read in place (and written when
    closing a slab)."""

    def __init__(self, lib, soil):
        for name in ("vst_masing_slab", "vst_masing_residual"):
            getattr(lib, name).argtypes = [_P]
            getattr(lib, name).restype = None
        self.lib, self.soil = lib, soil
        bb = soil.backbone
        n = soil.elements.size
        # contiguous copies kept alive for the struct
        self.params = [np.ascontiguousarray(a, dtype=float).ravel()
                       for a in (bb.G, bb.gamma_ref, bb.beta, bb.s, soil.A, soil.ke_h)]
        self.gauss = (np.ascontiguousarray(masing.XG), np.ascontiguousarray(masing.WG))
        self.D = np.zeros((n, 2))
        self.Q, self.dQ = np.zeros((n, 2)), np.zeros((n, 2, 2))
        self.s = _Slab(ne=n, depth=masing.DEPTH)
        for name, arr in zip(("G", "gref", "beta", "s", "area", "keh"), self.params):
            setattr(self.s, name, _ptr(arr))
        self.s.xg, self.s.wg = _ptr(self.gauss[0]), _ptr(self.gauss[1])
        self.s.D, self.s.Q = _ptr(self.D), _ptr(self.Q)
        self.dQ_ptr = _ptr(self.dQ)
        self._state = None
        # two sets of end-state arrays, used in turn (the state holds one)
        self.buffers = [(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros((n, masing.DEPTH)),
                         np.zeros((n, masing.DEPTH)), np.zeros(n, dtype=np.int64))
                        for _ in range(2)]
        self.addresses = [tuple(_ptr(a) for a in buffers) for buffers in self.buffers]
        self.turn = 0
        self.data = None

    def bind_residual(self, left, scale, free, V, W, n):
        """The solver's side of :meth:`residual`: each element's left node
        among the n gathered nodes, dt / h, the free nodes, V and W."""
        self.coupling = [np.ascontiguousarray(left, dtype=np.int64),
                         np.ascontiguousarray(scale, dtype=float),
                         np.ascontiguousarray(free, dtype=float),
                         np.ascontiguousarray(V, dtype=float).ravel(),
                         np.ascontiguousarray(W, dtype=float).ravel()]
        for name, arr in zip(("left", "scale", "free", "V", "W"), self.coupling):
            setattr(self.s, name, _ptr(arr))
        self.s.n = n
        self.rows = np.zeros(2 * n)
        self.blocks = np.zeros((self.D.shape[0], 2, 2))
        self.values = np.zeros(2 * n)
        self.s.rows, self.s.blocks, self.s.values = (_ptr(a) for a in (self.rows, self.blocks,
                                                                       self.values))
        self.s.pdata = None

    def residual(self, values, dt, tangent):
        """(rows W r, element blocks or None, D, Q) at the gathered unknowns
        (copies), as SoilCoupling.residual computes them in numpy."""
        self.values[:] = values
        self._bind_state()
        self.s.dt = dt
        self.s.dQ = self.dQ_ptr if tangent else None
        self.s.gamma1 = None
        self.s.pdata = None if self.data is None else _ptr(self.data)
        self.lib.vst_masing_residual(ctypes.byref(self.s))
        # the kernel's own buffers, valid until the next call: the rows and
        # blocks are used before it (the factors copy the blocks they
        # keep), and closing a slab reads the last call's D and Q
        return self.rows, (self.blocks if tangent else None), self.D, self.Q

    def prepare(self, dt):
        """Ready the struct for the compiled Newton's kernel calls."""
        self._bind_state()
        self.s.dt = dt
        self.s.dQ = self.dQ_ptr
        self.s.gamma1 = None
        self.s.pdata = None

    def tangent_data(self):
        """The tangent's block CSR data of the last residual with the
        tangent (None unless bind_tangent_data was called)."""
        return self.data

    def _bind_state(self):
        """Point the struct at the state's arrays (again only when the
        state holds new ones: after a slab closes; then they are one of
        the two sets of end-state buffers, whose addresses are kept)."""
        if self._state is not None and self._state[0] == self.soil.version:
            return
        st = self.soil.state
        # finish() hands the state all six arrays of one set at once
        for buffers, addresses in zip(self.buffers, self.addresses):
            if st.gamma is buffers[0]:
                kept = buffers
                break
        else:
            arrays = (st.gamma, st.tau, st.direction, st.stack.g, st.stack.t, st.stack.k)
            kept = tuple(np.ascontiguousarray(a) for a in arrays)
            addresses = tuple(_ptr(a) for a in kept)
        self._state = (self.soil.version, kept)
        s = self.s
        s.gamma, s.tau, s.dir, s.sg, s.st, s.k = addresses

    def bind_tangent_data(self, base, slots, coef):
        """Let every residual with the tangent also write the tangent's
        block CSR data (``data``): ``base`` plus each element's blocks at
        ``slots`` (4, ne; -1 elsewhere) times ``coef`` (4, ne)."""
        self.pkeep = [np.ascontiguousarray(base, dtype=float),
                      np.ascontiguousarray(slots, dtype=np.int64),
                      np.ascontiguousarray(coef, dtype=float)]
        self.data = np.zeros_like(self.pkeep[0])
        self.s.pbase, self.s.slots, self.s.pcoef = (_ptr(a) for a in self.pkeep)
        self.s.nb = self.pkeep[0].size // 4
        self.s.pdata = _ptr(self.data)

    def finish(self, D1, D2, dt):
        """The state at the slab end for the solution D1, D2: (Q, gamma,
        tau, direction, stack g, stack t, depth), into the pair of buffers
        the state does not hold."""
        self.D[:, 0], self.D[:, 1] = D1, D2
        self._bind_state()
        self.s.dt = dt
        self.s.dQ = None
        self.turn = 1 - self.turn
        out = self.buffers[self.turn]
        s = self.s
        s.gamma1, s.tau1, s.dir1, s.sg1, s.st1, s.k1 = self.addresses[self.turn]
        self.lib.vst_masing_slab(ctypes.byref(s))
        self.s.gamma1 = None
        return (self.Q,) + out          # (Q: the kernel's buffer, until its next call)
