"""Body forces (a nodal vector p times a history h(t)) on the running
right-hand side: per slab b += p (x) W (int T_a h dt) on the two rows of
every node, carried over by -p (x) W T (...) like every force; a constant h
gives (T - I) F = 0 and is added once (docs/loads.md section 3).

The additions are numpy ufuncs on the local array, not VecAXPY: BLAS axpy
kernels round a fused main loop and a scalar tail differently, so an
entry's result would depend on where it falls in a rank's array, and runs
on different numbers of ranks would differ in the last bits."""

import numpy as np


class FieldTerms:
    """The body forces of ``loads`` (a SlabLoads), each as the local part of
    its nodal vector p."""

    def __init__(self, space, loads, W, V, dt):
        n0, n1 = space.nodes
        self.W, self.V, self.dt = W, V, dt
        self.WT = W @ np.array([[0.0, 1.0], [0.0, 1.0]])
        self.varying = [f.vector[n0:n1].copy() for f in loads.varying]
        self.constant = [(f.vector[n0:n1].copy(), float(f.history.f[0])) for f in loads.constant]
        self.open = None           # integrals of the open slab, for advance()
        self.active = bool(self.varying or self.constant)

    @staticmethod
    def _add(arr, p, coef):
        rows = arr.reshape(-1, 2)
        rows[:, 0] += p * coef[0]
        rows[:, 1] += p * coef[1]

    def fold(self, arr):
        """Add the constant body forces to the running sum (its local
        array), once."""
        for p, g in self.constant:
            self._add(arr, p, self.W @ (0.5 * self.dt * g * np.ones(2)))

    def add(self, arr, integrals):
        """The slab's body forces with a history (integrals (m, 2))."""
        self.open = integrals
        for p, h in zip(self.varying, integrals):
            self._add(arr, p, self.W @ h)

    def carry(self, arr):
        """Close the slab: -W T (int T_a h) on the running sum."""
        if self.open is not None:
            for p, h in zip(self.varying, self.open):
                self._add(arr, p, -(self.WT @ h))

    def work(self, x):
        """This rank's share of int v^T f dt over the slab of every body
        force (x: the local array of the slab's unknowns z)."""
        terms = list(zip(self.varying, self.open if self.open is not None else []))
        terms += [(p, 0.5 * self.dt * g * np.ones(2)) for p, g in self.constant]
        if not terms:
            return 0.0
        z = x.reshape(-1, 2)
        total = 0.0
        for p, h in terms:
            pz = np.array([p @ z[:, 0], p @ z[:, 1]])          # p . z_1, p . z_2
            total += float(h @ (self.V @ pz))                   # sum_a h_a p . v^a
        return total
