"""Body forces (a nodal vector p times a history h(t)) on the running
right-hand side: per slab b += p (x) W (int T_a h dt) on the two rows of
every node, carried over by -p (x) W T (...) like every force; a constant h
gives (T - I) F = 0 and is added once (docs/loads.md section 3)."""

import numpy as np


class FieldTerms:
    """The vectors of the body forces of ``loads`` (a SlabLoads), as p on
    the first and on the second rows of each node."""

    def __init__(self, space, loads, W, V, dt):
        self.space, self.W, self.V, self.dt = space, W, V, dt
        self.WT = W @ np.array([[0.0, 1.0], [0.0, 1.0]])
        self.varying = [self._rows(f.vector) for f in loads.varying]
        self.constant = [(self._rows(f.vector), float(f.history.f[0])) for f in loads.constant]
        self.open = None           # integrals of the open slab, for advance()

    def _rows(self, p):
        n0, n1 = self.space.nodes
        first, second = self.space.vector(), self.space.vector()
        first.getArray()[0::2] = p[n0:n1]
        second.getArray()[1::2] = p[n0:n1]
        return first, second

    def _add(self, b, rows, coef):
        b.axpy(coef[0], rows[0])
        b.axpy(coef[1], rows[1])

    def fold(self, b):
        """Add the constant body forces to the running sum, once."""
        for rows, g in self.constant:
            self._add(b, rows, self.W @ (0.5 * self.dt * g * np.ones(2)))

    def add(self, b, integrals):
        """The slab's body forces with a history (integrals (m, 2))."""
        self.open = integrals
        for rows, h in zip(self.varying, integrals):
            self._add(b, rows, self.W @ h)

    def carry(self, b):
        """Close the slab: -W T (int T_a h) on the running sum."""
        if self.open is not None:
            for rows, h in zip(self.varying, self.open):
                self._add(b, rows, -(self.WT @ h))

    def work(self, X):
        """int v^T f dt over the slab of every body force (collective)."""
        total = 0.0
        terms = list(zip(self.varying, self.open if self.open is not None else []))
        terms += [(rows, 0.5 * self.dt * g * np.ones(2)) for rows, g in self.constant]
        for rows, h in terms:
            pz = np.array([X.dot(rows[0]), X.dot(rows[1])])     # p . z_1, p . z_2
            total += float(h @ (self.V @ pz))                   # sum_a h_a p . v^a
        return total
