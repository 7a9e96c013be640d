"""Contact pairs and Coulomb friction in the hysteretic soil's compiled
Newton (hosted_laws.h, called by soil_newton.c): the arrays of the laws'
slab state it reads, and, after a slab, the laws' Python objects set from
its last evaluation as their own ``force`` would have left them (the same
operations: pair.h, coulomb.h), so that finishing the slab, its work and
its events are the laws' own code."""

import ctypes

import numpy as np

from vstpetsc.laws.coulomb import FrictionSlab
from vstpetsc.laws.friction import CoulombFriction
from vstpetsc.laws.penalty import PenaltyContact
from vstpetsc.native import bind

_P = ctypes.c_void_p


class _Hosted(ctypes.Structure):
    """The C struct HostedLaws of hosted_laws.h, field for field."""

    _fields_ = [("laws", ctypes.c_int), ("k", ctypes.c_int), ("dt", ctypes.c_double)] + \
        [(name, _P) for name in ("enode", "R0", "U", "kind", "normal_of", "power", "w", "mu",
                                 "gn", "wall", "zE", "y", "f", "out", "hit", "G", "normal",
                                 "pieces", "count", "slab", "rows", "jac", "kept")] + \
        [("failed", ctypes.c_int)]


def takes(laws):
    """Whether the compiled Newton evaluates these laws: penalty pairs and
    their friction."""
    return all(type(law) in (PenaltyContact, CoulombFriction) for law in laws)


class CompiledLaws:
    """The struct for ``hosted`` (a vstpetsc.petsc.hosted_laws.HostedLaws)."""

    def __init__(self, lib, hosted):
        laws = hosted.laws.laws
        self.hosted, self.laws = hosted, laws
        self.pairs = [j for j, law in enumerate(laws) if type(law) is PenaltyContact]
        self.frictions = [j for j, law in enumerate(laws) if type(law) is CoulombFriction]
        L, k = len(laws), hosted.laws.size
        index = {id(law): j for j, law in enumerate(laws)}
        ints = lambda values: np.ascontiguousarray(values, dtype=np.intc)
        floats = lambda values: np.ascontiguousarray(values, dtype=np.float64)
        pair = lambda law: type(law) is PenaltyContact
        self.keep = {
            "enode": np.ascontiguousarray(hosted.laws.nodes, dtype=np.int64),
            "R0": floats(hosted.R0), "U": floats(hosted.U),
            "kind": ints([0 if pair(law) else 1 for law in laws]),
            "normal_of": ints([0 if pair(law) else index[id(law.pair)] for law in laws]),
            "power": ints([pair(law) and law.power for law in laws]),
            "w": floats([law.penalty if pair(law) else law.stiffness for law in laws]),
            "mu": floats([0.0 if pair(law) else law.mu for law in laws]),
            "gn": np.zeros(L), "wall": np.zeros((L, 2)), "zE": np.zeros(k),
            "y": np.zeros(2 * L), "f": hosted.laws.f, "out": np.zeros((L, 6)),
            "hit": np.zeros(L, dtype=np.intc), "G": np.zeros((L, 6)),
            "normal": np.zeros((L, 3)), "pieces": np.zeros((L, 6)),
            "count": np.zeros(L, dtype=np.intc), "slab": np.zeros((L, 10)),
            "rows": np.zeros(k), "jac": hosted.jac, "kept": hosted.kept}
        self.s = bind(_Hosted(laws=L, k=k, dt=hosted.dt), self.keep)

    def prepare(self):
        """The laws' slab state (after their start_slab and start_time):
        the pairs' gaps, the frictions' stretches and walls."""
        gn, wall = self.keep["gn"], self.keep["wall"]
        for j in self.pairs:
            gn[j] = self.laws[j].gn
        for j in self.frictions:
            law = self.laws[j]
            gn[j] = law.stretch
            c, (v1, v2) = law.wall_sign, law.wall_v
            wall[j] = c * v1, c * v2
        self.s.failed = 0

    def finish(self):
        """After the Newton: each law as its last ``force`` left it, the
        HostedLaws' coordinates; whether any law acts."""
        keep = self.keep
        hit = keep["hit"].tolist()
        y = keep["y"]
        self.hosted.y = y.copy()
        for j in self.pairs:
            law = self.laws[j]
            law.pieces = None
            if hit[j]:
                law.last = tuple(keep["G"][j].tolist())
                law.rates = (float(y[2 * j]), float(y[2 * j + 1]))
                if law.power:       # (a seed pair's events: finish_slab finds them)
                    law.pieces = list(zip(*[iter(keep["pieces"][j, :2 * keep["count"][j]]
                                                 .tolist())] * 2))
            else:
                law.last = None
        for j in self.frictions:
            self.laws[j].last = FrictionSlab(*keep["slab"][j].tolist()) if hit[j] else None
        return any(hit)
