"""What a result file keeps of the slab solver to continue its run bit for
bit, and taking it back: the running right-hand side, the laws' Newton
state of the last slab, the energy sums and a hysteretic soil's state
(docs/result-file.md: the restart datasets)."""

import numpy as np


class RestartState:
    """The restart datasets of ``solver`` (a SlabSolver)."""

    def __init__(self, solver):
        self.solver = solver

    def saved(self):
        """{layout name: array} on rank 0 (None elsewhere; collective)."""
        from vstpetsc.results.layout import ENERGY_STATE, NEWTON_STATE, RHS_STATE, SOIL_STATE

        s = self.solver
        b = s.space.to_rank0(s.b)           # between slabs: the running sum
        sums = s.sums.gathered(s.nonlinear)
        if b is None:
            return None
        out = {RHS_STATE: b, NEWTON_STATE: s.nonlinear.state(), ENERGY_STATE: sums}
        if s.material is not None:          # the same on every rank
            out[SOIL_STATE] = np.concatenate([s.material.soil.snapshot(),
                                              s.material.state()])
        return out

    def restore(self, state):
        """Continue from :meth:`saved`'s datasets (``state``, from the file,
        each global), after the solver's set_state: the restart is then
        bit for bit."""
        from vstpetsc.results.layout import ENERGY_STATE, NEWTON_STATE, RHS_STATE, SOIL_STATE

        s = self.solver
        n0, n1 = s.space.nodes
        if RHS_STATE in state:
            s.br[:] = state[RHS_STATE][2 * n0:2 * n1]
        if NEWTON_STATE in state:
            s.nonlinear.set_newton_state(state[NEWTON_STATE])
        if ENERGY_STATE in state:
            s.sums.restore(state[ENERGY_STATE], s.nonlinear)
        if SOIL_STATE in state and s.material is not None:
            saved = state[SOIL_STATE]
            size = s.material.soil.snapshot().size
            s.material.soil.restore(saved[:size])
            s.material.restore(saved[size:])
