"""The principal stress envelopes of a plane-strain run as its solver
keeps them every slab (the stresses, the envelopes and their file:
vstpetsc.plane.principal).  Each rank takes its own linear cells through
one sparse matrix D B from its owned u to their centre stresses, formed
once: a PETSc product per slab, which brings the ghost values; rank 0
takes the yielding cells, whose law it holds."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.plane.principal import DATASETS, Envelope, stress_rows


class PrincipalStresses:
    """The envelopes of a plane-strain run on ``comm``: this rank's own
    linear cells from its owned u (the solver's numbering), and on rank 0
    the yielding zone's cells (``model.zone``)."""

    def __init__(self, model, dt, comm):
        self.dt, self.comm, self.slab = dt, comm, 0
        self.ncells = model.ncells
        local = model.local
        yielding = np.array([r.shear_law is not None for r in model.regions], dtype=bool)
        own = np.flatnonzero(local.owned_cells & ~yielding[local.mesh.region])
        self.B = _stress_matrix(model, own, comm)
        self.u_vec, self.stress_vec = self.B.createVecs()
        self.linear = Envelope(local.original_cells[own])
        zone = model.zone
        self.zone = zone if hasattr(zone, "cell_stress") else None     # rank 0's
        self.yielding = Envelope(self.zone.cells if self.zone is not None else [])

    def _stresses(self, u):
        """(this rank's linear cells' stress, the zone cells' or None) of
        the owned u."""
        self.u_vec.setArray(u)
        self.B.mult(self.u_vec, self.stress_vec)
        linear = self.stress_vec.getArray(readonly=True).reshape(-1, 3)
        zone = None if self.zone is None else self.zone.cell_stress()[self.zone.cells]
        return linear, zone

    def start(self, u, saved=None):
        """From the state u (owned, the solver's numbering) at t = 0, or
        ``saved`` (read_envelopes: a restart's envelopes at its slab)."""
        if saved is not None:
            self.slab = int(saved["slab"])
            for part in (self.linear, self.yielding):
                part.restore(saved)
            return
        self.slab = 0
        linear, zone = self._stresses(u)
        self.linear.start(linear, 0.0)
        if zone is not None:
            self.yielding.start(zone, 0.0)

    def after_slab(self, u):
        """The slab just closed (its end state u)."""
        self.slab += 1
        t = self.slab * self.dt
        linear, zone = self._stresses(u)
        self.linear.take(linear, t)
        if zone is not None:
            self.yielding.take(zone, t)

    def gathered(self):
        """{DATASETS name: (ne,)} of every cell on rank 0 in the mesh's
        numbering as read (None elsewhere; collective)."""
        parts = [self.linear.arrays(), self.yielding.arrays()]
        parts = self.comm.tompi4py().gather(parts, root=0)
        if parts is None:
            return None
        out = np.zeros((len(DATASETS), self.ncells))
        for cells, values in (p for rank in parts for p in rank):
            out[:, cells] = values
        return dict(zip(DATASETS, out))


def _stress_matrix(model, cells, comm):
    """PETSc's AIJ of the centre stresses of this rank's ``cells`` (its
    local numbers) from its owned u: stress_operator's rows, set a chunk
    of cells at a time into the preallocated matrix (no whole copy beside
    PETSc's)."""
    local = model.local
    nodes = local.mesh.cells[cells]
    number = local.global_vertex[nodes]
    real = nodes >= 0                                    # (a triangle's fourth is -1)
    mine = real & (number >= local.start) & (number < local.stop)
    inside, outside = (np.repeat(2 * k.sum(axis=1), 3).astype(PETSc.IntType)
                       for k in (mine, real & ~mine))     # each row's columns by owner
    owned = 2 * (local.stop - local.start)
    B = PETSc.Mat().createAIJ(((inside.size, PETSc.DECIDE), (owned, 2 * local.size)),
                              comm=comm)
    # (a rank without linear cells gives numbers: empty arrays hang PETSc's assembly)
    B.setPreallocationNNZ((inside, outside) if inside.size else (0, 0))
    first = B.getOwnershipRange()[0]
    for rows, columns, values in stress_rows(local.mesh, model.materials["lam"],
                                             model.materials["mu"], cells, local.global_vertex):
        order = np.argsort(columns, axis=1, kind="stable")      # (rows' columns sorted)
        B.setValuesRCV((first + rows).astype(PETSc.IntType)[:, None],
                       np.take_along_axis(columns, order, 1).astype(PETSc.IntType),
                       np.take_along_axis(values, order, 1))
    B.assemble()
    return B
