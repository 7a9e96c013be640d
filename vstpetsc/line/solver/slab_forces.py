"""The nodal forces and prescribed velocities of the open slab on the
running right-hand side (docs/loads.md sections 2 and 3): a force enters
it as W F and leaves it, when the slab closes, as -W T F; a prescribed
velocity replaces its node's rows (the force that holds it, the reaction,
is carried by :class:`vstpetsc.line.solver.reactions.Reactions`)."""

import numpy as np

from vstpetsc.spacetime import slab


class SlabForces:
    """The slab's nodal forces and prescribed velocities on this rank's
    rows of the running sum (its local array).

    Parameters
    ----------
    nodes : (n0, n1), this rank's nodes
    W, V : the solver's mixing of rows and unknowns (slab.recurrence)
    reactions : Reactions or None (every constrained node fixed)
    """

    def __init__(self, nodes, W, V, reactions):
        self.nodes, self.W, self.V, self.reactions = nodes, W, V, reactions
        self.WT = W @ slab.CARRY
        self.Vinv = np.linalg.inv(V)
        self.open = None           # (local dofs, -W T f, f) of the open slab
        self._cache = {}

    def add(self, arr, forces):
        """Add the slab's nodal force integrals (nodes, values (n, 2)),
        global node numbers (nodes not owned are skipped)."""
        self.open = None
        nodes, per = forces
        if nodes.size:
            idx, own = self._rows(nodes)
            arr[idx] += (per[own] @ self.W.T).ravel()
            self.open = (idx, -(per[own] @ self.WT.T).ravel(), per[own])

    def prescribe(self, arr, velocities):
        """Set the prescribed velocities (nodes, values (n, 2) in the
        velocity basis) on their rows, after every term of the slab's
        right-hand side is in (the reactions keep those rows first)."""
        nodes, vals = velocities
        if nodes.size:
            idx, own = self._rows(nodes)
            if self.reactions is not None:
                self.reactions.hold(arr)
                arr[idx] = (vals @ self.Vinv.T)[own].ravel()
            else:                              # fixed nodes: zero velocities
                arr[idx] = 0.0

    def carry(self, arr):
        """Close the slab: the forces' -W T F on the running sum."""
        if self.open is not None:
            arr[self.open[0]] += self.open[1]
            self.open = None

    def work(self, x):
        """This rank's share of the forces' work over the slab (x: the
        local array of the slab's unknowns z)."""
        if self.open is None:
            return 0.0
        idx, _, per = self.open
        return float(np.sum(per * (x[idx].reshape(-1, 2) @ self.V.T)))

    def _rows(self, nodes):
        """(local dofs of the owned ones among ``nodes``, their mask), cached
        per node array (the loads' and constraints' nodes never change)."""
        key = id(nodes)
        if key not in self._cache:
            n0, n1 = self.nodes
            own = (nodes >= n0) & (nodes < n1)
            self._cache[key] = ((2 * (nodes[own] - n0)[:, None] + np.arange(2)).ravel(), own)
        return self._cache[key]
