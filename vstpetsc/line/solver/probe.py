"""u and v of a few nodes after each slab, on rank 0 (for gauges)."""

import numpy as np


class NodeValues:
    """Reads u and v^2 of the global nodes ``nodes`` from ``solver`` (a
    SlabSolver) between slabs: on one rank straight from its arrays, on
    several each rank sends its own to rank 0."""

    def __init__(self, solver, nodes):
        n0, n1 = solver.space.nodes
        nodes = np.asarray(nodes, dtype=int)
        owned = (nodes >= n0) & (nodes < n1)
        self.index = np.flatnonzero(owned)          # positions in ``nodes``
        self.local = nodes[owned] - n0
        self.size = nodes.size
        self.solver = solver
        self.z = solver.x.reshape(-1, 2)             # the slab unknowns per node
        # v^2 = z0 V1[0] + z1 V1[1], two products and a sum as the slab's
        # end forms v (no BLAS, whose fused multiply-adds round otherwise):
        # the same bits as the compiled gauge row (native/gauge_row.c)
        self.V1 = solver.V[1].copy()

    def __call__(self):
        """(u, v) at the nodes on rank 0; None elsewhere."""
        u = self.solver.u[self.local]
        z = self.z[self.local]
        v = z[:, 0] * self.V1[0] + z[:, 1] * self.V1[1]
        if self.solver.serial:
            return u, v
        return self.solver.space.assemble_on_rank0(self.size, self.index, u, v)
