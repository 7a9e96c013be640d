"""What the laws prescribe per slab: nodal force integrals, body forces and
velocities.

Loads and constraints never move, so their nodes are sorted out once; per
slab only the histories are evaluated.  Body forces (a vector times a
history) with a constant history are added to the running right-hand side
once (docs/loads.md section 3); the others give two coefficients a slab.
Pure numpy.
"""

import numpy as np

from vstpetsc.laws.base import FieldLoad


class SlabLoads:
    """``SlabLoads(laws)(t0, t1)`` gives, for the slab (t0, t1]:

    - forces: (nodes, values (n, 2)), ``int T_a f dt`` summed per node
      (nodes sorted, each once);
    - velocities: (nodes, values (n, 2)), (v^1, v^2) of constrained nodes;
    - fields: (m, 2) ``int T_a h dt`` of the m body forces with a history
      (``varying``); those with a constant value are ``constant``.
    """

    def __init__(self, laws):
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
        self.zero = np.zeros((self.fixed_nodes.size, 2))

    def forces(self, t0, t1):
        per = np.zeros((self.force_nodes.size, 2))
        if self.loads:
            vals = np.array([load.weight * load.history.hat_integrals(t0, t1)
                             for load in self.loads])
            np.add.at(per, self.force_slot, vals)
        return self.force_nodes, per

    def velocities(self, t0, t1):
        if self.all_fixed:
            return self.fixed_nodes, self.zero
        ends = np.array([t0, t1])
        vals = np.array([np.zeros(2) if c.history is None else c.history(ends)
                         for c in self.constraints])
        return self.fixed_nodes, vals

    def field_integrals(self, t0, t1):
        return np.array([f.history.hat_integrals(t0, t1) for f in self.varying]).reshape(-1, 2)

    def __call__(self, t0, t1):
        return self.forces(t0, t1), self.velocities(t0, t1), self.field_integrals(t0, t1)
