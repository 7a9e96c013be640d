"""What the laws prescribe per slab: nodal force integrals, body forces and
velocities.

Loads and constraints never move, so their nodes are sorted out once; the
histories are evaluated for blocks of slabs at a time (vectorized, exact
integrals), and a slab reads its row.  Body forces with a constant history
are added to the running right-hand side once (docs/loads.md section 3).
Pure numpy.
"""

import numpy as np

from vstpetsc.line.laws.base import FieldLoad
from vstpetsc.spacetime.blocks import Blocks


class SlabLoads:
    """``SlabLoads(laws, dt).slab(k)`` gives, for slab k ((k-1) dt, k dt]:

    - forces: (nodes, values (n, 2)), ``int T_a f dt`` summed per node
      (nodes sorted, each once);
    - velocities: (nodes, values (n, 2)), (v^1, v^2) of constrained nodes;
    - fields: (m, 2) ``int T_a h dt`` of the m body forces with a history
      (``varying``); those with a constant value are ``constant``.
    """

    def __init__(self, laws, dt):
        self.dt = dt
        loads = [load for law in laws for load in law.loads()]
        self.fields = [f for f in loads if isinstance(f, FieldLoad)]
        self.loads = [f for f in loads if not isinstance(f, FieldLoad)]
        self.varying = [f for f in self.fields if not f.history.is_constant]
        self.constant = [f for f in self.fields if f.history.is_constant]
        self.constraints = [c for law in laws for c in law.constraints()]
        nodes = np.array([load.node for load in self.loads], dtype=int)
        self.force_nodes, self.force_slot = np.unique(nodes, return_inverse=True)
        self.fixed_nodes = np.array([c.node for c in self.constraints], dtype=int)
        self.all_fixed = all(c.history is None for c in self.constraints)
        self.blocks = Blocks(self._evaluate)

    def _evaluate(self, k0, k1):
        """(forces (K, n, 2), velocities (K, m, 2), fields (K, f, 2)) of
        slabs k0+1 .. k1."""
        count, dt = k1 - k0, self.dt
        forces = np.zeros((count, self.force_nodes.size, 2))
        for i, load in enumerate(self.loads):
            forces[:, self.force_slot[i]] += load.weight * load.history.slab_integrals(dt, k0, k1)
        ends = dt * np.arange(k0, k1 + 1)
        velocities = np.zeros((count, self.fixed_nodes.size, 2))
        for i, c in enumerate(self.constraints):
            if c.history is not None:
                values = c.history(ends)
                velocities[:, i, 0], velocities[:, i, 1] = values[:-1], values[1:]
        fields = np.zeros((count, len(self.varying), 2))
        for i, f in enumerate(self.varying):
            fields[:, i] = f.history.slab_integrals(dt, k0, k1)
        return forces, velocities, fields

    def slab(self, k):
        """((force nodes, values), (constrained nodes, values), fields) of slab k."""
        (forces, velocities, fields), i = self.blocks.at(k)
        return ((self.force_nodes, forces[i]), (self.fixed_nodes, velocities[i]), fields[i])

    def __call__(self, t0, t1):
        """The slab (t0, t1] = ((k - 1) dt, k dt]."""
        return self.slab(int(round(t1 / self.dt)))
