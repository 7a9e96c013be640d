"""The energy terms of a slab (docs/loads.md section 4): the work of the
dashpots, int v^T C v dt = z^T D z with D = V^T (dt HC) V (x) C in the
solver's unknowns, one product and one dot a slab when C is not zero."""

from vstpetsc.spacetime import slab

from vstpetsc.line import bands
from vstpetsc.line.solver.matrices import block_matrix


class DampingWork:
    def __init__(self, space, ops, dt, V, mat_type):
        self.D = block_matrix(bands.node_blocks(ops, c=V.T @ (dt * slab.HC) @ V), space.nodes,
                              space.comm, mat_type) if ops.damped else None
        self.Dz = space.vector() if self.D is not None else None

    def __call__(self, X):
        """int v^T C v dt over the slab (collective); 0 without dashpots."""
        if self.D is None:
            return 0.0
        self.D.mult(X, self.Dz)
        return X.dot(self.Dz)
