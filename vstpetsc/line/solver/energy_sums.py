"""The running sums of the energy terms that the slab solver keeps
(docs/loads.md section 4): the dashpots' work and this rank's share of
the external work (forces, body forces, reactions), with the laws' and
a soil's own sums their totals over the ranks, and the state a restart
takes back."""

import numpy as np

from vstpetsc.runner.energy import SUMS, SUMS_BEFORE_FRICTION


class EnergySums:
    """The sums over the slabs of ``damping`` (DampingWork), ``fields``
    (FieldTerms), ``forces`` (SlabForces) and ``reactions`` (Reactions or
    None), on this rank of ``space``."""

    def __init__(self, space, damping, fields, forces, reactions):
        self.space, self.damping, self.fields = space, damping, fields
        self.forces, self.reactions = forces, reactions
        self.work = {"damping": 0.0}       # sums, the same on every rank
        self.local = 0.0                   # this rank's share of the external work

    def add_slab(self, X, x):
        """The slab's terms at its solution X (its local array x;
        collective with dashpots); the reactions' Q is the slab's already."""
        if self.damping.D is not None:
            self.work["damping"] += self.damping(X)
        if self.fields.active:
            self.local += self.fields.work(x)
        if self.forces.open is not None:
            self.local += self.forces.work(x)
        if self.reactions is not None:
            self.local += self.reactions.work(x)

    def totals(self, nonlinear, material):
        """The summed energy terms over every rank, the laws' (LawSolver)
        and a soil's (its material Newton, or None) included (collective)."""
        laws = dict(nonlinear.work)
        # a moving wall's work through friction is external, the same on every
        # rank, and so is the work of supports against a soil's stress
        beyond = laws.get("wall", 0.0)
        if material is not None:
            soil = material.soil
            laws["strain_beyond_linear"], laws["hysteretic"] = soil.energies()
            beyond += soil.support_work
        return {**self.work, **laws,
                "external": self.space.sum_over_ranks(self.local) + beyond}

    def gathered(self, nonlinear):
        """The running sums (energy.SUMS order), then every rank's share of
        the external work, on rank 0 (None elsewhere; collective)."""
        shares = self.space.gather_on_rank0(self.local)
        if shares is None:
            return None
        sums = {**self.work, **nonlinear.work}
        return np.array([sums.get(key, 0.0) for key in SUMS] + list(shares))

    def restore(self, saved, nonlinear):
        """Take back the sums of :meth:`gathered`; on another number of
        ranks rank 0 takes the whole external work (equal to rounding)."""
        rank, size = self.space.comm.getRank(), self.space.comm.getSize()
        names = SUMS if saved.size != len(SUMS_BEFORE_FRICTION) + size else SUMS_BEFORE_FRICTION
        sums, shares = saved[:len(names)], saved[len(names):]
        for key, value in zip(names, sums.tolist()):
            for work in (self.work, nonlinear.work):
                if key in work:
                    work[key] = value
        if shares.size == size:
            self.local = float(shares[rank])
        else:
            self.local = float(shares.sum()) if rank == 0 else 0.0
