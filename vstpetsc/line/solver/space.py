"""The parallel layout: a 1-D DMDA over all nodes of all bodies, two dof
per node (the slab unknowns of the node, interleaved), and the transfers
between ranks that a run needs (the collective sums and gathers of
vstpetsc.petsc.ranks besides)."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.petsc.ranks import Ranks


class Space(Ranks):
    """Nodes ``nodes = (n0, n1)`` of this rank among ``nnodes``."""

    def __init__(self, nnodes, comm, ownership=None):
        self.da = PETSc.DMDA().create(
            dim=1, sizes=(nnodes,), dof=2, stencil_width=1, comm=comm,
            ownership_ranges=None if ownership is None else (tuple(ownership),))
        self.da.setUp()
        (n0, n1), = self.da.getRanges()
        self.nodes = (n0, n1)
        self.comm = comm
        self._to_zero = None

    def vector(self):
        return self.da.createGlobalVec()

    def array_vector(self):
        """(vec, array): a global vector of the DMDA's layout stored in a
        numpy array of ours, so that the per-slab numpy work reads and
        writes it without VecGetArray (0.7 us a call)."""
        n0, n1 = self.nodes
        array = np.zeros(2 * (n1 - n0))
        vec = PETSc.Vec().createWithArray(array, size=(array.size, PETSc.DECIDE), bsize=2,
                                          comm=self.comm)
        return vec, array

    def to_rank0(self, vec):
        """All entries of ``vec`` in node order on rank 0 (None elsewhere)."""
        if self.comm.getSize() == 1:        # one rank: the DMDA's order is the nodes'
            return vec.getArray(readonly=True).copy()
        if self._to_zero is None:
            self._nat = self.da.createNaturalVec()
            self._to_zero, self._zero = PETSc.Scatter.toZero(self._nat)
        self.da.globalToNatural(vec, self._nat)
        self._to_zero.scatter(self._nat, self._zero, addv=PETSc.InsertMode.INSERT,
                              mode=PETSc.ScatterMode.FORWARD)
        if self.comm.getRank() != 0:
            return None
        return self._zero.getArray(readonly=True).copy()


class DofGather:
    """The values of a global vector at the global dofs ``dofs``, on every
    rank (every rank then takes the same decisions from them)."""

    def __init__(self, template, dofs, nodes):
        n0, n1 = nodes
        self.dofs = np.asarray(dofs, dtype=PETSc.IntType)
        self.owned = (self.dofs >= 2 * n0) & (self.dofs < 2 * n1)
        self.local = self.dofs[self.owned] - 2 * n0
        self.all_owned = bool(self.owned.all())
        self.out = PETSc.Vec().createSeq(self.dofs.size, comm=PETSc.COMM_SELF)
        iset = PETSc.IS().createGeneral(self.dofs, comm=PETSc.COMM_SELF)
        self.scatter = PETSc.Scatter().create(template, iset, self.out, None)

    def __call__(self, vec):
        self.scatter.scatter(vec, self.out, addv=PETSc.InsertMode.INSERT,
                             mode=PETSc.ScatterMode.FORWARD)
        return self.out.getArray(readonly=True).copy()

    def add_rows(self, vec, values):
        """Add ``values`` (one per dof) to the owned entries of ``vec``."""
        vec.getArray()[self.local] += values if self.all_owned else values[self.owned]

    def unit(self, vec, j):
        """vec = the unit vector of dof number j."""
        vec.zeroEntries()
        if self.owned[j]:
            vec.setValue(self.dofs[j], 1.0)
        vec.assemble()
        return vec


class Halo:
    """The z (two dofs) of the nodes just beyond this rank's ends, n0 - 1
    and n1, from the global vector ``vec``: what the end of a slab needs
    of its neighbours, in one scatter of up to four numbers (the DMDA's
    ghost update would also copy every owned entry into a local vector).
    After a call (collective) ``z_left`` and ``z_right`` hold them; None
    where the mesh ends."""

    def __init__(self, vec, nodes, nnodes):
        n0, n1 = nodes
        self.vec = vec
        self.values = np.zeros(4)
        left, right = n0 > 0, n1 < nnodes
        self.z_left = self.values[0:2] if left else None
        self.z_right = self.values[2:4] if right else None
        dofs = [2 * n0 - 2, 2 * n0 - 1] * left + [2 * n1, 2 * n1 + 1] * right
        filled = self.values[(0 if left else 2):(4 if right else 2)]
        self.out = PETSc.Vec().createWithArray(filled, comm=PETSc.COMM_SELF)
        iset = PETSc.IS().createGeneral(np.array(dofs, dtype=PETSc.IntType),
                                        comm=PETSc.COMM_SELF)
        self.scatter = PETSc.Scatter().create(vec, iset, self.out, None)

    def __call__(self):
        self.scatter.scatter(self.vec, self.out, addv=PETSc.InsertMode.INSERT,
                             mode=PETSc.ScatterMode.FORWARD)
