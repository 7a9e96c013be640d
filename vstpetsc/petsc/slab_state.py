"""What results and restarts read of a slab solver's state, and what a
restart gives back to it: the running right-hand side, the energy sums,
a hysteretic soil's state, the envelopes (the part of
:class:`~vstpetsc.petsc.slab_solver.SlabSolver` that the recorder and the
restart use)."""

import numpy as np

from vstpetsc.energy import SUMS, SUMS_BEFORE_FRICTION


class SlabState:
    """The saved and restored state of a :class:`SlabSolver` (its base:
    ``space``, ``br``, ``b``, ``work``, ``local_work``, ``nonlinear``,
    ``material``, ``envelope`` and ``end`` are the solver's)."""

    def set_restart_state(self, state):
        """Continue from the running right-hand side saved by rhs_state()
        (a global array), the Newton state of the last slab and the energy
        sums of energy_sums() ({layout name: array}, from the file), after
        set_state: the restart is then bit for bit."""
        from vstpetsc.results.layout import ENERGY_STATE, NEWTON_STATE, RHS_STATE, SOIL_STATE

        n0, n1 = self.space.nodes
        if RHS_STATE in state:
            self.br[:] = state[RHS_STATE][2 * n0:2 * n1]
        if NEWTON_STATE in state:
            self.nonlinear.set_newton_state(state[NEWTON_STATE])
        if ENERGY_STATE in state:
            self._restore_sums(state[ENERGY_STATE])
        if SOIL_STATE in state and self.material is not None:
            saved = state[SOIL_STATE]
            size = self.material.soil.snapshot().size
            self.material.soil.restore(saved[:size])
            self.material.restore(saved[size:])

    def soil_state(self):
        """A hysteretic soil's state and its Newton's start (None without
        one; the same on every rank)."""
        if self.material is None:
            return None
        return np.concatenate([self.material.soil.snapshot(), self.material.state()])

    def energy_sums(self):
        """The running sums of the energy terms (energy.SUMS order), then
        every rank's share of the external work, on rank 0 (None
        elsewhere; collective)."""
        shares = self.space.gather_on_rank0(self.local_work)
        if shares is None:
            return None
        sums = {**self.work, **self.nonlinear.work}
        return np.array([sums.get(key, 0.0) for key in SUMS] + list(shares))

    def _restore_sums(self, saved):
        """Take back the sums of :meth:`energy_sums`; on another number of
        ranks rank 0 takes the whole external work (equal to rounding)."""
        rank, size = self.space.comm.getRank(), self.space.comm.getSize()
        names = SUMS if saved.size != len(SUMS_BEFORE_FRICTION) + size else SUMS_BEFORE_FRICTION
        sums, shares = saved[:len(names)], saved[len(names):]
        for key, value in zip(names, sums.tolist()):
            for work in (self.work, self.nonlinear.work):
                if key in work:
                    work[key] = value
        if shares.size == size:
            self.local_work = float(shares[rank])
        else:
            self.local_work = float(shares.sum()) if rank == 0 else 0.0

    def state_energies(self):
        """(kinetic, strain) energy after the last slab when the compiled
        close summed them (None: the EnergyBook sums them)."""
        return self.end.energies()

    def elongation(self):
        """u_{i+1} - u_i of every node pair after the last slab, on one rank
        (the envelopes' own; None on several ranks)."""
        return self.envelope.buf if self.serial else None

    def rhs_state(self):
        """The running right-hand side of all dofs on rank 0 (None
        elsewhere), between slabs."""
        return self.space.to_rank0(self.b)

    def envelopes(self, nelements):
        """Elongation envelopes (lo, hi) of every element on rank 0 (None
        elsewhere)."""
        return self.space.assemble_on_rank0(nelements, *self.envelope.local())
