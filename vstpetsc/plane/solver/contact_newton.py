"""Newton on a plane-strain slab's unknowns with interface pairs, its
steps by GMRES (``-vst_contact_steps krylov``; the default, Newton on the
pairs' coordinates, is vstpetsc.plane.solver.pair_newton).

The slab's equations with the pairs' terms, R(X) = A X - r + E f(E^T X)
= 0 (and a yielding zone's, vstpetsc.plane.yielding, in the same Newton),
are solved on the full slab unknowns: with A_c = A + E W_c E^T (every
pair closed and sticking: springs, vstpetsc.plane.pairs) factored once in
place of A, R(X) = A_c X - r + E (f - W_c y) and the Newton matrix is
J = A_c + E (f'(y) - W_c) E^T.  Each step solves J dX = -R by GMRES
preconditioned with A_c's solver (FGMRES when that is itself a Krylov
method); J is applied matrix-free (A_c's product and the pairs' 4 x 4
blocks).  Pairs that stay closed and sticking add nothing to J - A_c: a
slab where every pair does is linear and its step is one solve with A_c
(no Krylov iteration), the welded mesh's cost.  Only pairs that open or
slide make GMRES iterate, each iteration one more solve with A_c: its
work grows with the distinct ways the pairs change (bench/README.md,
"Many pairs": it wins on long uniform interfaces, loses on a dam's).

Full steps for the first FULL_STEPS iterations, then halved while the
residual's norm does not fall.  Converged when |R| <= RTOL (|r| +
|A_c X|) (2-norms).

The pairs' kernels run on rank 0: their unknowns are gathered there by
one PETSc scatter and their terms added back by its reverse (on one rank,
numpy indexing).  A held dof keeps its identity row: a pair's term there
is part of the reaction (``held_work``)."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.errors import SolveFailed

RTOL = 1e-12
MAX_IT = 60
FULL_STEPS = 12
HALVINGS = 20
ROUNDS = 8          # a yielding zone's decision sets tried in one slab
ROUND_IT = 8        # iterations a later set gets before the last converged one is taken
FREEZE_AFTER = 5    # a zone's decisions are kept from this iteration on (before: the rules decide)


class PairDofs:
    """A nonlinear term's slab unknowns z (m, w) of the global slab vector,
    on rank 0: a pair's 8 (the first node's (x: T1, T2; y: T1, T2), then
    the second node's), a yielding zone's 2 a spatial dof (T1, T2)."""

    def __init__(self, comm, global_dofs, held):
        """``global_dofs`` (m, w) global slab indices (every rank: rank 0's
        matter); ``held`` the held ones (m, w), whose identity rows take
        no term (the term's force there is a reaction)."""
        self.comm, self.rank0 = comm, comm.getRank() == 0
        self.index, self.held = global_dofs, held
        self.free = ~held
        self.m, self.width = global_dofs.shape
        if comm.getSize() == 1:
            self.scatter = None
            return
        n = self.width * self.m if self.rank0 else 0
        self.pairs_vec = PETSc.Vec().createMPI((n, self.width * self.m), comm=comm)
        self.source = None
        idx = global_dofs.ravel() if self.rank0 else np.zeros(0, dtype=int)
        self._is = PETSc.IS().createGeneral(idx.astype(PETSc.IntType), comm=comm)
        self.scatter = None

    def bind(self, vec):
        """Scatter set-up against the layout of the slab vector ``vec``."""
        if self.comm.getSize() == 1 or self.scatter is not None:
            return
        self.scatter = PETSc.Scatter().create(vec, self._is, self.pairs_vec, None)

    def gather(self, vec):
        """z (m, 8) on rank 0 (None elsewhere)."""
        if self.scatter is None:
            return vec.getArray(readonly=True)[self.index]
        self.scatter.scatter(vec, self.pairs_vec, addv=PETSc.InsertMode.INSERT,
                             mode=PETSc.ScatterMode.FORWARD)
        return self.pairs_vec.getArray(readonly=True).reshape(-1, self.width).copy() \
            if self.rank0 else None

    def add(self, values, vec):
        """vec += E-entries ``values`` (m, 8) (rank 0's) at the free dofs."""
        if self.scatter is None:          # setValues: PETSc sees the change (cached norms)
            vec.setValues(self.index.ravel().astype(PETSc.IntType),
                          (values * self.free).ravel(), addv=PETSc.InsertMode.ADD)
            vec.assemble()
            return
        if self.rank0:
            self.pairs_vec.setArray((values * self.free).ravel())
        else:
            self.pairs_vec.setArray(np.zeros(0))
        self.scatter.scatter(self.pairs_vec, vec, addv=PETSc.InsertMode.ADD,
                             mode=PETSc.ScatterMode.REVERSE)


class HeldWork:
    """The work at held dofs of a Newton's last terms (each term's
    ``values``, its entries of the residual beyond A_c, at its unknowns
    ``z``)."""

    def held_work(self):
        """Rank 0: the slab's work of the nonlinear terms beyond A_c at held
        dofs (a part of their reactions' work)."""
        return sum(float((t.values * t.dofs.held * t.z).sum()) for t in self.terms
                   if t.values is not None and t.dofs.held.any())


class FrozenDecisions:
    """A yielding zone's discrete decisions (each point's start reversal,
    inside turn, clipped cut, depths at its turn point and Gauss points:
    deviatoric_slab.Decisions) kept fixed while the Newton converges, the
    residual then smooth (the law's stress jumps where a branch is left off
    its target, and the Newton's line search stalls on them); at
    convergence the rules decide afresh at the solution and the Newton
    continues from there with the new decisions when any point's changed
    (an active-set loop).  A point whose decisions changed LOCK times in
    the slab keeps its last (newton_terms.ZoneTerm.settle); after ROUNDS
    sets the last converged state is taken with its decisions, and so when
    a later set does not converge within ROUND_IT iterations (decisions
    taken from one state need not admit a solution near it: a 1e4-cell
    rockfill dam far beyond gamma_ref stalled so, bench/plane_yielding.py).
    ``self.undecided`` counts the points whose rules' decisions disagreed
    with the accepted ones, over the run."""

    def _zones(self):
        return [t for t in self.terms if hasattr(t, "freeze")]

    def _start_decisions(self):
        """The rules' decisions at the last evaluation (at x) are kept from
        now on."""
        self.frozen = True
        for zone in self._zones():
            zone.freeze()

    def _settle(self, b, x, norm):
        """At a converged iterate: (settled, |R| with the decisions now kept)."""
        zones = self._zones()
        if not zones or not self.frozen:
            return True, norm
        kept = [zone.thaw() for zone in zones]
        fresh = self._residual(b, x, self.R)          # the rules decide at x
        counts = np.sum([zone.settle(k) for zone, k in zip(zones, kept)], axis=0)
        moved, held = self.comm.tompi4py().bcast(tuple(int(c) for c in counts), root=0)
        if moved == 0 and held == 0:
            return True, fresh
        self.rounds += moved > 0
        if moved and self.rounds < ROUNDS:
            self.fallback = (x.copy(), kept, moved + held)
        if moved and self.rounds >= ROUNDS:
            for zone, k in zip(zones, kept):         # take the state converged with ``kept``
                zone.restore(k)
            moved, held = 0, held + moved
        norm = self._residual(b, x, self.R)
        if moved == 0:
            self.undecided += held
        return moved == 0, norm

    def _fall_back(self, b, x):
        """Take the last converged state with the decisions it converged
        with (its points the rules disagree with counted as held)."""
        converged, kept, disagree = self.fallback
        converged.copy(x)
        for zone, k in zip(self._zones(), kept):
            zone.restore(k)
        self._residual(b, x, self.R)
        self.undecided += disagree


class ContactNewton(FrozenDecisions, HeldWork):
    """Newton for the slabs of ``A_c`` (its solver ``inner``, set up) with
    nonlinear ``terms`` (vstpetsc.plane.solver.newton_terms: interface
    pairs, yielding zones; kernels and state on rank 0), in one Newton."""

    def __init__(self, A_c, inner, terms, comm):
        self.A_c, self.inner, self.terms, self.comm = A_c, inner, terms, comm
        self.rank0 = comm.getRank() == 0
        self.R, self.dx = A_c.createVecLeft(), A_c.createVecLeft()
        self.trial = A_c.createVecLeft()
        for term in terms:
            term.dofs.bind(self.R)
        from vstpetsc.plane.solver.newton_steps import KrylovSteps
        self.steps = KrylovSteps(self)
        self.linear = True
        self.krylov = 0
        self.undecided = 0

    def _residual(self, b, x, R):
        """R = A_c x - b + the terms' residuals at x (their kernels
        evaluated there); returns |R|."""
        self.A_c.mult(x, R)
        self.ax_norm = R.norm()
        R.axpy(-1.0, b)
        linear = True
        for term in self.terms:
            z = term.dofs.gather(x)
            values = None
            if z is not None:
                values, straight = term.evaluate(z)
                linear = linear and straight
            term.dofs.add(values, R)
        self.linear = self.comm.tompi4py().bcast(linear, root=0)
        return R.norm()

    def solve(self, b, x, k):
        """x solves the slab of right-hand side b, from x's start (slab k
        for messages); returns (Newton iterations, Krylov iterations)."""
        self.krylov = 0
        scale = b.norm()
        for zone in self._zones():
            zone.start()
        norm = self._residual(b, x, self.R)
        it = start = self.rounds = 0
        self.frozen = False
        while True:
            if it == FREEZE_AFTER and not self.frozen and self._zones():
                self._start_decisions()
                start = it
            if norm <= RTOL * (scale + self.ax_norm):
                settled, norm = self._settle(b, x, norm)
                if settled:
                    return it, self.krylov
                start = it
                continue
            if self.rounds and it - start >= ROUND_IT:
                self._fall_back(b, x)
                return it, self.krylov
            if it == MAX_IT:
                break
            self._step()
            norm = self._line(b, x, norm, it - start)
            it += 1
        raise SolveFailed(f"slab {k}: the interfaces' Newton did not converge in {MAX_IT} "
                          f"iterations (|R| = {norm:.3g})")

    def _step(self):
        """dx = -J^{-1} R: one solve with A_c when every pair is linear,
        else GMRES's (vstpetsc.plane.solver.newton_steps.KrylovSteps)."""
        self.R.scale(-1.0)
        if self.linear:
            self.inner.solve(self.R, self.dx)
            self.krylov += max(1, self.inner.getIterationNumber())
        else:
            self.krylov += self.steps.solve(self.R, self.dx)
        self.R.scale(-1.0)

    def _line(self, b, x, norm, it):
        """x + dx: full steps for the first FULL_STEPS iterations (a pair
        that starts or stops sliding or touching moves the residual far
        from its Newton model, and halving there crawls), then halved
        while |R| does not fall; the new |R|."""
        step = 1.0
        for _ in range(1 if it < FULL_STEPS else HALVINGS):
            self.trial.waxpy(step, self.dx, x)
            new = self._residual(b, self.trial, self.R)
            if new < norm:
                break
            step *= 0.5
        self.trial.copy(x)              # the kernels' last evaluation is at x
        return new
