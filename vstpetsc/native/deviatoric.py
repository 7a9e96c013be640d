"""The compiled slab integrals of the plane-strain MKZ-Masing law
(deviatoric.c): one call for every point's Q, dQ/dD and decisions; the
same operations as :func:`vstpetsc.materials.deviatoric_slab.slab_integrals`,
which stays the reference (``-vst_native 0``; tests/test_deviatoric_native.py
holds the two to rounding)."""

import ctypes

import numpy as np

from vstpetsc.materials import deviatoric as dv
from vstpetsc.materials import deviatoric_slab as ds
from vstpetsc.materials.masing import DEPTH, WG, XG

_P = ctypes.c_void_p
_DOUBLES = ("G", "gref", "beta", "s", "K", "xg", "wg", "eps", "dev", "sc", "ss", "k", "n0",
            "virgin", "D1", "D2", "fturned", "freverses", "fcut", "fkc", "fk", "Q", "dQ",
            "turned", "reverses", "cut", "kc", "kk", "eps_c", "s_c")


class _Slab(ctypes.Structure):
    """The C struct DeviatoricSlab of deviatoric.h, field for field."""

    _fields_ = [("n", ctypes.c_long), ("depth", ctypes.c_int), ("dt", ctypes.c_double)] + \
        [(name, _P) for name in _DOUBLES]


class NativePath:
    """What the compiled kernel decided for a slab: the Decisions, the turn
    point (strain, stress deviator) and the motion; commit() moves the
    law's state to the slab end as SlabPath.commit does."""

    def __init__(self, law, D1, D2, out, motion):
        self.law, self.D1, self.D2, self.motion = law, D1, D2, motion
        self.turned, self.reverses, self.cut = out["turned"], out["reverses"], out["cut"]
        self.kc, self.kk = out["kc"], out["kk"]
        self.eps_c, self.s_c = out["eps_c"], out["s_c"]

    def decisions(self):
        return ds.Decisions(self.turned, self.reverses, self.cut, self.kc[:, None],
                            [self.kk[:, 0], self.kk[:, 1]])

    def commit(self):
        start = self.law.pushed(self.turned)
        second = ds.second_stack(start, self.reverses, self.kc, self.eps_c, self.s_c)
        return ds.commit_end(self.law, second, self.D1, self.D2, self.motion)


class NativeSlabIntegrals:
    """slab_integrals(law, D1, D2, dt, motion, tangent, frozen) by ``lib``
    (the library of vstpetsc.native) for laws of n points."""

    def __init__(self, lib):
        lib.vst_deviatoric_slab.argtypes = [_P]
        lib.vst_deviatoric_slab.restype = ctypes.c_int
        self.lib = lib
        self.gauss = (np.ascontiguousarray(XG), np.ascontiguousarray(WG))

    def __call__(self, law, D1, D2, dt, motion=None, tangent=True, frozen=None):
        n = D1.shape[0]
        D1, D2 = np.ascontiguousarray(D1), np.ascontiguousarray(D2)
        n0, virgin = ds.slab_heading(law, dv.deviator(D1), dv.deviator(D2), motion)
        out = {"Q": np.zeros((n, 2, 3)), "dQ": np.zeros((n, 2, 3, 2, 3)) if tangent else None,
               "turned": np.zeros(n, dtype=bool), "reverses": np.zeros(n, dtype=bool),
               "cut": np.zeros(n), "kc": np.zeros(n, dtype=np.int64),
               "kk": np.zeros((n, 2, XG.size), dtype=np.int64),
               "eps_c": np.zeros((n, 3)), "s_c": np.zeros((n, 3))}
        bb = law.backbone
        keep = {"G": bb.G[:, 0], "gref": bb.gamma_ref[:, 0], "beta": bb.beta[:, 0],
                "s": bb.s[:, 0], "K": law.K, "xg": self.gauss[0], "wg": self.gauss[1],
                "eps": law.eps, "dev": law.dev, "sc": law.stack.c, "ss": law.stack.s,
                "k": law.stack.k, "n0": n0, "virgin": virgin, "D1": D1, "D2": D2}
        if frozen is not None:
            keep.update(fturned=frozen.turned, freverses=frozen.reverses, fcut=frozen.cut,
                        fkc=frozen.kc[:, 0], fk=np.stack(frozen.k, axis=1))
        keep = {name: np.ascontiguousarray(a, dtype=_dtype(a)) for name, a in keep.items()}
        slab = _Slab(n=n, depth=DEPTH, dt=dt)
        for name, a in list(keep.items()) + list(out.items()):
            if a is not None:
                setattr(slab, name, a.ctypes.data)
        if self.lib.vst_deviatoric_slab(ctypes.byref(slab)):
            raise RuntimeError("vst_deviatoric_slab: stack deeper than the kernel's buffers")
        motion_out = ds.slab_motion(dv.deviator(D1), dv.deviator(D2), n0)
        return out["Q"], out["dQ"], NativePath(law, D1, D2, out, motion_out)


def _dtype(a):
    """The C type a field's array is given as: flags bytes, depths longs."""
    a = np.asarray(a)
    if a.dtype == bool:
        return np.uint8
    return np.int64 if a.dtype.kind in "iu" else float
