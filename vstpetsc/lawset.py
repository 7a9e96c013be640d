"""The nonlinear laws of a model on the union of their nodes: the unknowns
of Newton are the velocities (v^1, v^2) of those nodes, interleaved
(s[2 j + a] for node j of the union).  Pure numpy."""

import numpy as np


class LawSet:
    """Assembles the laws' residuals and tangents on the union of their dofs."""

    def __init__(self, laws):
        self.laws = list(laws)
        parts = [law.nodes for law in self.laws]
        self.nodes = np.unique(np.concatenate(parts)).astype(int) if parts else \
            np.zeros(0, dtype=int)
        self.size = 2 * self.nodes.size
        self.slots = [(2 * np.searchsorted(self.nodes, law.nodes)[:, None]
                       + np.arange(2)).ravel() for law in self.laws]
        self.u = np.zeros(self.nodes.size)     # displacement of the nodes at t^n

    @property
    def dofs(self):
        """Global dof numbers of the unknowns."""
        return (2 * self.nodes[:, None] + np.arange(2)).ravel()

    def start_slab(self, dt):
        for law, slot in zip(self.laws, self.slots):
            law.start_slab(self.u[slot[0::2] // 2], dt)

    def residual(self, s):
        """(the laws' residual terms on the union's dofs, whether any is active)."""
        c = np.zeros(self.size)
        active = False
        for law, slot in zip(self.laws, self.slots):
            r, on = law.residual(s[slot].reshape(-1, 2))
            c[slot] += r.ravel()
            active |= on
        return c, active

    def tangent(self, s):
        C = np.zeros((self.size, self.size))
        for law, slot in zip(self.laws, self.slots):
            C[np.ix_(slot, slot)] += law.tangent(s[slot].reshape(-1, 2))
        return C

    def finish_slab(self, t0, dt):
        for law in self.laws:
            law.finish_slab(t0, dt)
