"""The nonlinear terms of a plane-strain slab's Newton
(vstpetsc.plane.solver.contact_newton), each at its own unknowns z (m, w)
gathered on rank 0 (a PairDofs): ``evaluate(z)`` gives its residual's
entries beyond A_c and whether it is linear there (its step then one solve
with A_c), ``apply(dz)`` its Jacobian's entries beyond A_c times dz;
``values`` and ``z`` the last evaluation's (the held dofs' work)."""

import numpy as np

LOCK = 2            # a zone point's decision changes in one slab before it is held


class PairTerm:
    """Interface pairs (vstpetsc.plane.pairs.PairSet): f - W_c y beyond
    A_c's closed, sticking springs."""

    exact_steps = True          # GMRES steps to 1e-12 (newton_steps.KrylovSteps)

    def __init__(self, pairs, dofs):
        self.pairs, self.dofs = pairs, dofs
        self.values = self.z = self.blocks = None

    def evaluate(self, z):
        self.pairs.evaluate(z)
        self.values, *self.blocks = self.pairs.difference()
        self.z = z
        linear = max(float(np.abs(b).max(initial=0.0)) for b in self.blocks) <= \
            self.pairs.rounding
        return self.values, linear

    def apply(self, dz):
        return self.pairs.apply_difference(dz, *self.blocks)


class ZoneTerm:
    """A yielding zone (vstpetsc.plane.yielding.YieldingZone): its points'
    stress beyond the linear one, never linear."""

    exact_steps = False         # GMRES steps to newton_steps.ZONE_RTOL

    def __init__(self, zone, dofs):
        self.zone, self.dofs = zone, dofs
        self.values = self.z = None

    def evaluate(self, z):
        self.values, self.z = self.zone.evaluate(z), z
        return self.values, False

    def apply(self, dz):
        return self.zone.apply(dz)

    def start(self):
        """At a slab's start: the rules decide (nothing kept, no point
        changed yet)."""
        if self.dofs.rank0:
            self.zone.frozen, self.changes = None, np.zeros(self.zone.law.eps.shape[0], int)

    def freeze(self):
        """Keep the last evaluation's decisions in the evaluations to come."""
        if self.dofs.rank0:
            self.zone.frozen = self.zone.decisions()

    def restore(self, decisions):
        """Keep ``decisions`` (rank 0's)."""
        if self.dofs.rank0:
            self.zone.frozen = decisions

    def thaw(self):
        """Let the rules decide again; the decisions kept so far."""
        if not self.dofs.rank0:
            return None
        kept, self.zone.frozen = self.zone.frozen, None
        return kept

    def settle(self, kept):
        """After an evaluation by the rules at a state converged with the
        ``kept`` decisions: keep the rules' new decisions, except at points
        that changed LOCK times already in this slab (they keep theirs: a
        point flipping at a stress jump has no consistent state);
        (points changed, points held against the rules) (rank 0; zeros
        elsewhere)."""
        if not self.dofs.rank0:
            return 0, 0
        fresh = self.zone.decisions()
        differ = kept.differ(fresh)
        held = differ & (self.changes >= LOCK)
        moved = differ & ~held
        self.changes += moved
        self.zone.frozen = fresh.merged(kept, held)
        return int(moved.sum()), int(held.sum())


def slab_newton(solver, comm):
    """The nonlinear terms' Newton of a PlaneSolver on its A_c: interface
    pairs alone on the pairs' coordinates (vstpetsc.plane.solver.pair_newton)
    when newton_steps.kind says so, else every term (pairs, a yielding
    zone) on the slab's unknowns with GMRES steps (contact_newton)."""
    from vstpetsc.plane.solver.contact_newton import ContactNewton
    from vstpetsc.plane.solver.newton_steps import kind
    from vstpetsc.plane.solver.pair_newton import PairNewton

    terms = []
    if solver.pairs is not None:
        nodes = solver.pairs.global_nodes
        index = (2 * (2 * nodes[:, :, None, None] + np.arange(2)[:, None])
                 + np.arange(2)).reshape(-1, 8)
        dofs = held_dofs(solver, comm, index)
        if solver.zone is None and kind(solver.pairs) == "dense":
            return PairNewton(solver.A, solver.ksp, solver.pairs, dofs, comm)
        terms.append(PairTerm(solver.pairs, dofs))
    if solver.zone is not None:
        terms.append(ZoneTerm(solver.zone, held_dofs(solver, comm, solver.zone.slab_index)))
    return ContactNewton(solver.A, solver.ksp, terms, comm)


def held_dofs(solver, comm, index):
    """The PairDofs of the global slab indices ``index`` (m, w) (rank 0's),
    with those of ``solver``'s held rows marked (collective)."""
    from vstpetsc.plane.solver.contact_newton import PairDofs

    held = comm.tompi4py().gather(4 * solver.model.first + solver.rows, root=0)
    held = np.isin(index, np.concatenate(held)) if comm.getRank() == 0 \
        else np.zeros(index.shape, dtype=bool)
    return PairDofs(comm, index, held)
