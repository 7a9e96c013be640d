"""The hysteretic soil's Newton on one rank in one compiled call
(soil_newton.c): the steps of
:class:`vstpetsc.line.solver.material_newton.PlainSoilNewton` on the slab
matrix's block bands, whose LU is the block Thomas algorithm."""

import ctypes

import numpy as np

from vstpetsc.native import bind

_P = ctypes.c_void_p


class _Newton(ctypes.Structure):
    """The C struct SoilNewton of soil_newton.c, field for field."""

    _fields_ = [("N", ctypes.c_long)] + \
        [(name, _P) for name in ("A", "J", "Minv", "Cp", "Ainv", "ACp", "F", "y", "node",
                                 "rfree", "gleft", "m")] + \
        [(name, ctypes.c_double) for name in ("rtol", "atol", "slow", "lagged")] + \
        [("max_it", ctypes.c_int), ("fresh", ctypes.c_int), ("rows_last", _P),
         ("kept_blocks", _P), ("iterations", ctypes.c_int), ("converged", ctypes.c_int),
         ("fnorm", ctypes.c_double), ("laws", _P), ("min_step", ctypes.c_double)]


class CompiledSoilNewton:
    """The compiled loop for ``newton`` (a PlainSoilNewton on one rank with
    the compiled kernel ``native``); it stands in for the newton's factors
    too (``fresh``, ``blocks``, ``refresh``)."""

    def __init__(self, lib, newton, native, solver, tolerances):
        for name in ("vst_soil_newton", "vst_soil_refresh", "vst_soil_factor_a"):
            getattr(lib, name).restype = None
        lib.vst_soil_newton.argtypes = [_P, _P, _P]
        lib.vst_soil_refresh.argtypes = lib.vst_soil_factor_a.argtypes = [_P]
        self.lib, self.native = lib, native
        c, soil = newton.c, newton.soil
        A = np.ascontiguousarray(solver.matrix_blocks())
        N = A.shape[0]
        self.keep = {
            "A": A,
            "J": np.zeros((N, 3, 2, 2)), "Minv": np.zeros((N, 2, 2)), "Cp": np.zeros((N, 2, 2)),
            "Ainv": np.zeros((N, 2, 2)), "ACp": np.zeros((N, 2, 2)),
            "F": np.zeros(2 * N), "y": np.zeros(2 * N),
            "node": np.ascontiguousarray(soil.nodes, dtype=np.int64),
            "rfree": np.ascontiguousarray(np.column_stack([c.free[c.left, 0], c.free[c.right, 0]])),
            "gleft": np.ascontiguousarray(soil.left, dtype=np.int64)}
        self.rows_last = newton.rows                   # updated in place by the newton
        self.blocks = np.zeros((soil.left.size, 2, 2))
        self.s = _Newton(N=N, rtol=tolerances[0], atol=tolerances[1], slow=tolerances[2],
                         lagged=tolerances[3], max_it=tolerances[4], fresh=0,
                         min_step=tolerances[5])
        bind(self.s, self.keep)
        self.s.m = ctypes.addressof(native.s)
        self.s.rows_last, self.s.kept_blocks = self.rows_last.ctypes.data, self.blocks.ctypes.data
        if newton.laws is not None:         # the contact laws in the same Newton
            self.hosted = newton.laws.compile(lib)
            self.s.laws = ctypes.addressof(self.hosted)
        lib.vst_soil_factor_a(ctypes.byref(self.s))

    @property
    def fresh(self):
        return bool(self.s.fresh)

    def refresh(self, blocks, data=None):
        """Factor A + the tangent of ``blocks`` (a restart's)."""
        self.native.blocks[...] = blocks
        self.lib.vst_soil_refresh(ctypes.byref(self.s))

    def solve(self, b, X, dt):
        """Newton in place on X (one rank's arrays); (iterations, converged,
        |F|)."""
        self.native.prepare(dt)
        self.lib.vst_soil_newton(ctypes.byref(self.s), b.ctypes.data, X.ctypes.data)
        return self.s.iterations, bool(self.s.converged), self.s.fnorm
