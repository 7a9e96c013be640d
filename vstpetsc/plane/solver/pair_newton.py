"""Newton on the interface pairs' coordinates: the default for a
plane-strain slab with interfaces (up to newton_steps.DENSE_PAIRS pairs).

The slab's equations R(X) = A_c X - b + E e(E^T X) = 0 (A_c: A with every
pair's closed, sticking springs, factored once; e = f - W_c y the pairs'
terms beyond those springs, vstpetsc.plane.pairs) condense onto the
pairs' 4m coordinates y = E^T X: with S = E^T A_c^-1 E
(newton_steps.Coupling) and y_b = E^T A_c^-1 b,

    r(y) = y - y_b + S e(y) = 0,     X = A_c^-1 (b - E e(y)),

or, from y_1 = E^T A_c^-1 (b - E e_0) (the slab's one solve),
r(y) = y - y_1 + S (e(y) - e_0),

the 1-D reduced Newton's equations (vstpetsc.line.reduced_newton), solved the
same way: Newton matrix I + S e'(y), whose columns are the identity for
every pair closed and sticking (e' = 0), so a step is a dense solve over
the pairs that open or slide only; converged when max |r| <= RTOL (max
|y_1| + max |y| + max |S (e - e_0)| + max |e_0| / (k dt^2 / 8)).  Its iterations need no solve with
A_c: a slab takes one solve with e predicted at the state's velocity
(e_0; exact when every pair stays closed and sticking: the welded mesh's
cost) and, if e changed, the correction A_c^-1 E (e - e_0) from the kept
columns A_c^-1 E (or one more solve).  Since only pairs whose e changes
enter r, S's columns are formed a pair at a time, the first time a pair
needs them (newton_steps.Coupling).

Full steps for the first FULL_STEPS iterations (a pair that starts or
stops sliding or touching throws r far off its linear model), then the
best of the step halved up to HALVINGS times.  Everything on the pairs
runs on rank 0."""

import numpy as np
from petsc4py import PETSc

from vstpetsc.errors import SolveFailed
from vstpetsc.native import library
from vstpetsc.plane.solver.contact_newton import HeldWork
from vstpetsc.plane.solver.newton_steps import Coupling

DONE, FAILED = "done", "failed"      # rank 0's last word of a slab's Newton
RTOL = 1e-12
MAX_IT = 100
FULL_STEPS = 12
HALVINGS = 12
UNCHANGED = 1e-14       # a change of e below this times |e| is rounding


def subtract_rows(x, w, Z, rows, lib):
    """x - w @ Z[rows], in place in x: by the compiled library ``lib``
    (each row read once, in the order given) or, None, numpy's (the rows
    first copied)."""
    if lib is None:
        x -= w @ Z[rows]
        return x
    rows = np.ascontiguousarray(rows, dtype=np.int64)
    w = np.ascontiguousarray(w, dtype=float)
    lib.vst_rows_axpy(rows.size, rows.ctypes.data, w.ctypes.data, Z.ctypes.data, Z.shape[1],
                      x.ctypes.data)
    return x


class PairNewton(HeldWork):
    """Slabs of ``A_c`` (its solver ``inner``, set up) with ``pairs`` at
    ``dofs`` (vstpetsc.plane.solver.contact_newton.PairDofs).  Collective: the
    pairs' arithmetic is rank 0's, every rank takes part in the solves
    (a slab's, and the coupling's columns as pairs first need them)."""

    def __init__(self, A_c, inner, pairs, dofs, comm):
        self.A_c, self.inner, self.pairs, self.dofs, self.comm = A_c, inner, pairs, dofs, comm
        self.rank0 = comm.getRank() == 0
        self.rhs, self.u = A_c.createVecLeft(), A_c.createVecLeft()
        dofs.bind(self.rhs)
        self.coupling = Coupling(A_c, inner, pairs, dofs, comm)
        # each pair coordinate's own spring (k dt^2 / 8), for the offsets' scale
        own = np.repeat(np.column_stack([pairs.spring_n, pairs.kt]), 2, axis=1)
        self.own = own * pairs.hk[0, 0]
        self.values = self.z = None
        self.terms = (self,)            # its own values and z: HeldWork's one term
        self.lib = library() if PETSc.Options().getBool("vst_native", True) else None

    def solve(self, b, x, k):
        """x solves the slab of right-hand side b from the start x holds
        (slab k for messages); returns (Newton iterations, solves)."""
        z = self.dofs.gather(x)
        self.e0 = None
        if self.rank0:
            self.pairs.evaluate(z)
            self.e0 = self.pairs.excess()
        b.copy(self.rhs)
        self.dofs.add(None if self.e0 is None else -self.pairs.to_dofs(self.e0), self.rhs)
        self.inner.solve(self.rhs, x)
        z = self.dofs.gather(x)
        outcome = self._lead(k, z) if self.rank0 else self.coupling.serve()
        if outcome[0] == FAILED:
            raise SolveFailed(outcome[1])
        _, its, change = outcome
        # (the coupling's columns, formed once per pair, are not the slab's
        # solves: a restart forms them again, and its rows are the same)
        return its, 1 + (self._correct(x, change) if change is not None else 0)

    def _lead(self, k, z):
        """Rank 0: the Newton from the pairs' unknowns z after the slab's
        solve, the other ranks called in only to form columns
        (Coupling.serve); (DONE, iterations, e's change) or (FAILED, why),
        sent to them too."""
        try:
            self.y1 = self.pairs.coordinates(z)
            self.offset_scale = self._offset_scale()
            its, e = self._newton(k)
            self.values, self.z = self.pairs.to_dofs(e), z
            outcome = (DONE, its, self._change(e))
        except Exception as exc:        # (the other ranks must hear of any)
            self.coupling.tell((FAILED, str(exc)))
            raise
        self.coupling.tell(outcome)
        return outcome

    def _changed(self, e):
        """(indices of e - e0 beyond rounding, e - e0): a pair closed and
        sticking keeps e, up to the rounding of f - W_c y."""
        w = (e - self.e0).ravel()
        scale = np.abs(e).max(initial=0.0) + np.abs(self.pairs.forces()).max(initial=0.0)
        return np.flatnonzero(np.abs(w) > UNCHANGED * scale), w

    def _change(self, e):
        """(indices, values) of e - e0 beyond rounding, or None."""
        keep, w = self._changed(e)
        return (keep, w[keep]) if keep.size else None

    def _correct(self, x, change):
        """x -= A_c^-1 E w for w's entries ``change`` = (indices, values);
        returns the solves it took."""
        keep, w = change
        Z = self.coupling.Z
        if not self.coupling.known[keep // 4].all():    # (Z's other rows are unwritten)
            raise RuntimeError("a correction asked for a column not formed")
        if Z is not None:
            x.setArray(subtract_rows(x.getArray(readonly=True).copy(), w, Z, keep, self.lib))
            return 0
        full = np.zeros(4 * self.pairs.m)
        full[keep] = w
        self.rhs.zeroEntries()
        self.dofs.add(self.pairs.to_dofs(full.reshape(-1, 4)) if self.rank0 else None,
                      self.rhs)
        self.inner.solve(self.rhs, self.u)
        x.axpy(-1.0, self.u)
        return 1

    def _residual(self, y):
        """(r, max |r|, tolerance, e) at y, the kernels evaluated there:
        r = y - y1 + S (e - e0) (the columns of the pairs whose e changed
        formed first; rank 0's)."""
        self.pairs.evaluate_at(y)
        e = self.pairs.excess()
        cols, w = self._changed(e)
        self.coupling.ensure(np.unique(cols // 4))
        se = (w[cols] @ self.coupling.ST[cols]).reshape(-1, 4)
        r = y - self.y1 + se
        tol = RTOL * (np.abs(self.y1).max(initial=0.0) + np.abs(y).max(initial=0.0)
                      + np.abs(se).max(initial=0.0) + self.offset_scale)
        return r, np.abs(r).max(initial=0.0), tol, e

    def _offset_scale(self):
        """max |e0| over each pair's own spring (k dt^2 / 8): the rates the
        slab's offsets stand for, the scale of y where y itself is about
        0 (a body at rest under its weight)."""
        k = self.own
        return float(np.abs(np.divide(self.e0, k, out=np.zeros_like(self.e0), where=k > 0))
                     .max(initial=0.0))

    def _newton(self, k):
        """(iterations, e at the solution y), the kernels' last evaluation
        there (rank 0's)."""
        y = self.y1
        state = self._residual(y)
        for it in range(MAX_IT + 1):
            if state[1] <= state[2]:
                return it, state[3]
            if it == MAX_IT:
                break
            y, state = self._line(y, self._step(state[0]), state, it)
        raise SolveFailed(f"slab {k}: the interfaces' Newton did not converge in {MAX_IT} "
                          f"iterations (max |r| = {state[1]:.3g}, tolerance {state[2]:.3g})")

    def _step(self, r):
        """-(I + S e'(y))^-1 r over the pairs whose e' is not zero (their
        columns formed first; rank 0's)."""
        D = self.pairs.excess_tangent()
        K = np.flatnonzero(np.abs(D).reshape(D.shape[0], -1).max(axis=1) > self.pairs.rounding)
        self.coupling.ensure(K)
        step = -r.copy()
        if not K.size:
            return step
        rows = (4 * K[:, None] + np.arange(4)).ravel()
        SK_T = self.coupling.ST[rows]                    # S_K transposed (4k, 4m)
        # (S D)[rows] with D's 4 x 4 blocks: a batched product on the k rows
        # of blocks; the rest of S D dK as S_K (D dK), a product with a vector
        own = np.matmul(SK_T[:, rows].T.reshape(-1, K.size, 4).transpose(1, 0, 2), D[K])
        own = own.transpose(1, 0, 2).reshape(rows.size, rows.size)
        dK = np.linalg.solve(np.eye(rows.size) + own, -r.ravel()[rows])
        flat = -r.ravel() - np.matmul(D[K], dK.reshape(-1, 4, 1)).ravel() @ SK_T
        flat[rows] = dK
        return flat.reshape(-1, 4)

    def _line(self, y, step, state, it):
        """(y + lam step, its residual): lam = 1 for the first FULL_STEPS
        iterations, then the best of 1 and its halvings (rank 0's)."""
        best, lam = None, 1.0
        for _ in range(1 if it < FULL_STEPS else HALVINGS):
            trial = y + lam * step
            new = self._residual(trial)
            if best is None or new[1] < best[1][1]:
                best = (trial, new, lam)
            if new[1] < state[1]:
                break
            lam *= 0.5
        if best[2] != lam:                      # the kernels at the chosen y
            best = (best[0], self._residual(best[0]), best[2])
        return best[0], best[1]
