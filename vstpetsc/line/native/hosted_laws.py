"""Contact pairs and Coulomb friction in the hysteretic soil's compiled
Newton (hosted_laws.h, called by soil_newton.c): the arrays of the laws'
slab state it reads, and, after a slab, the laws' Python objects set from
its last evaluation as their own ``force`` would have left them (the same
operations: law_forces.h, shared with the laws' own compiled Newton), so
that finishing the slab, its work and its events are the laws' own code."""

import ctypes

import numpy as np

from vstpetsc.line.laws.friction import CoulombFriction
from vstpetsc.line.laws.penalty import PenaltyContact
from vstpetsc.line.native.penalty import Frictions
from vstpetsc.native import bind

_P = ctypes.c_void_p


class _LawForces(ctypes.Structure):
    """The C struct LawForces of law_forces.h, field for field."""

    _fields_ = [("laws", ctypes.c_int), ("dt", ctypes.c_double)] + \
        [(name, _P) for name in ("gn", "w", "power", "out", "integrals", "hit", "kind",
                                 "partner", "friction", "stretch", "fslab")] + \
        [("unsettled", ctypes.c_int)]


class _Hosted(ctypes.Structure):
    """The C struct HostedLaws of hosted_laws.h, field for field."""

    _fields_ = [("f", _LawForces), ("k", ctypes.c_int)] + \
        [(name, _P) for name in ("enode", "R0", "U", "zE", "y", "fy", "rows", "jac", "kept")]


def takes(laws):
    """Whether the compiled Newton evaluates these laws: penalty pairs and
    their friction."""
    return all(type(law) in (PenaltyContact, CoulombFriction) for law in laws)


class CompiledLaws:
    """The struct for ``hosted`` (a vstpetsc.line.solver.hosted_laws.HostedLaws)."""

    def __init__(self, lib, hosted):
        laws = hosted.laws.laws
        self.hosted, self.laws = hosted, laws
        self.pairs = [(j, law) for j, law in enumerate(laws) if type(law) is PenaltyContact]
        self.frictions = Frictions(laws)
        L, k = len(laws), hosted.laws.size
        self.gn = np.zeros(L)
        self.hit = np.zeros(L, dtype=np.intc)
        self.integrals = np.zeros((L, 6))
        self.keep = {
            "gn": self.gn, "hit": self.hit, "integrals": self.integrals, "out": np.zeros((L, 6)),
            # a friction law's entries unused (its pair's are read)
            "w": np.array([getattr(law, "penalty", 0.0) for law in laws], dtype=np.float64),
            "power": np.array([getattr(law, "power", 0) for law in laws], dtype=np.intc),
            **dict(zip(("kind", "partner", "friction", "stretch", "fslab"),
                       self.frictions.arrays())),
            "enode": np.ascontiguousarray(hosted.laws.nodes, dtype=np.int64),
            "R0": np.ascontiguousarray(hosted.R0), "U": np.ascontiguousarray(hosted.U),
            "zE": np.zeros(k), "y": np.zeros(2 * L), "fy": hosted.laws.f,
            "rows": np.zeros(k), "jac": hosted.jac, "kept": hosted.kept}
        self.s = bind(_Hosted(k=k), self.keep)
        self.s.f = bind(_LawForces(laws=L, dt=hosted.dt), self.keep)

    def prepare(self):
        """The laws' slab state (after their start_slab and start_time):
        the pairs' gaps, the frictions' stretches and walls."""
        for j, law in self.pairs:
            self.gn[j] = law.gn
        self.frictions.load()
        self.s.f.unsettled = 0

    def finish(self):
        """After the Newton: each law as its last ``force`` left it, the
        HostedLaws' coordinates; whether any law acts."""
        hit = self.hit.tolist()
        y = self.keep["y"]
        self.hosted.y = y.copy()
        for j, law in self.pairs:
            law.pieces = None           # (finish_slab finds the pair's events)
            if hit[j]:
                law.last = tuple(self.integrals[j].tolist())
                law.rates = (float(y[2 * j]), float(y[2 * j + 1]))
            else:
                law.last = None
        self.frictions.finish(hit)
        return any(hit)
