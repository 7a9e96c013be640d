"""The nonlinear laws of a model together.

Their nodes' velocities (v^1, v^2), interleaved, are the dofs E (s[2 j + a]
for node j of the union); each law sees two reduced coordinates
y = sum_k c_k s_k (docs: laws/base.py), so with P (2k x 2L, c_k on the law's
rows) y = P^T s and the laws' terms on E are c = P f(y).  Newton works on
the 2L coordinates y.  Pure numpy (and plain floats per law).
"""

import numpy as np

from vstpetsc.line.laws.base import Law


class LawSet:
    """The laws' dofs, P, and their terms and tangents."""

    def __init__(self, laws):
        self.laws = list(laws)
        parts = [law.nodes for law in self.laws]
        self.nodes = np.unique(np.concatenate(parts)).astype(int) if parts else \
            np.zeros(0, dtype=int)
        self.size = 2 * self.nodes.size              # dofs E
        self.reduced = 2 * len(self.laws)            # coordinates y
        self.P = np.zeros((self.size, self.reduced))
        self.node_index = []
        for j, law in enumerate(self.laws):
            idx = np.searchsorted(self.nodes, law.nodes)
            self.node_index.append(idx)
            for a in range(2):
                self.P[2 * idx + a, 2 * j + a] = law.signs
        # the laws that read the slab's start time (a Python call per law
        # and slab on the hot path otherwise: pile driving has a law per soil node)
        self.timed = [law for law in self.laws if type(law).start_time is not Law.start_time]
        self.finished = list(self.laws)              # the laws finish_slab calls
        self.u = np.zeros(self.nodes.size)           # displacement of the nodes at t^n
        self.f = np.zeros(self.reduced)              # the laws' terms of the last evaluation
        self.jac = np.zeros((self.reduced, self.reduced))

    @property
    def dofs(self):
        """Global dof numbers of E."""
        return (2 * self.nodes[:, None] + np.arange(2)).ravel()

    def start_slab(self, dt, t0):
        for law, idx in zip(self.laws, self.node_index):
            law.start_slab(self.u[idx], dt)
        for law in self.timed:
            law.start_time(t0)

    def acts(self, y):
        """Whether any law does anything in the slab at the coordinates y."""
        return any(law.acts(float(y[2 * j]), float(y[2 * j + 1]))
                   for j, law in enumerate(self.laws))

    def evaluate(self, y):
        """Fill ``f`` and the block-diagonal ``jac`` at the coordinates y;
        whether any law acts."""
        acting = False
        for j, law in enumerate(self.laws):
            out = law.force(float(y[2 * j]), float(y[2 * j + 1]))
            s = slice(2 * j, 2 * j + 2)
            if out is None:
                self.f[s] = 0.0
                self.jac[s, s] = 0.0
                continue
            acting = True
            self.f[s] = out[0], out[1]
            self.jac[s, s] = ((out[2], out[3]), (out[4], out[5]))
        return acting

    def residual(self, s):
        """The laws' terms on E for the velocities s on E, and whether any acts."""
        acting = self.evaluate(self.P.T @ s)
        return self.P @ self.f, acting

    def tangent(self, s):
        """d residual / d s on E (after ``residual`` at the same s)."""
        self.evaluate(self.P.T @ s)
        return self.P @ self.jac @ self.P.T

    def hand_over(self, laws):
        """Leave ``laws`` to a compiled path that keeps their state in
        arrays and finishes them itself
        (:class:`vstpetsc.line.native.smith_slab.SmithSlab`)."""
        taken = {id(law) for law in laws}
        self.finished = [law for law in self.finished if id(law) not in taken]

    def finish_slab(self, t0, dt):
        for law in self.finished:
            law.finish_slab(t0, dt)
