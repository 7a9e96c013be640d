"""Newton on the interface pairs' coordinates: the default for a
plane-strain slab with interfaces (up to newton_steps.DENSE_PAIRS pairs).

The slab's equations R(X) = A_c X - b + E e(E^T X) = 0 (A_c: A with every
pair's closed, sticking springs, factored once; e = f - W_c y the pairs'
terms beyond those springs, vstpetsc.plane.pairs) condense onto the
pairs' 4m coordinates y = E^T X: with S = E^T A_c^-1 E (formed once,
newton_steps.coupling) and y_b = E^T A_c^-1 b,

    r(y) = y - y_b + S e(y) = 0,     X = A_c^-1 (b - E e(y)),

the 1-D reduced Newton's equations (vstpetsc.reduced_newton), solved the
same way: Newton matrix I + S e'(y), whose columns are the identity for
every pair closed and sticking (e' = 0), so a step is a dense solve over
the pairs that open or slide only; converged when max |r| <= RTOL (max
|y_b| + max |S e|).  Its iterations need no solve with A_c: a slab takes
one solve with e predicted at the state's velocity (exact when every pair
stays closed and sticking: the welded mesh's cost) and, if e changed,
the correction A_c^-1 E (e - e_0) from the kept columns A_c^-1 E (or one
more solve).

Full steps for the first FULL_STEPS iterations (a pair that starts or
stops sliding or touching throws r far off its linear model), then the
best of the step halved up to HALVINGS times.  Everything on the pairs
runs on rank 0."""

import numpy as np

from vstpetsc.errors import SolveFailed
from vstpetsc.plane.contact_newton import HeldWork
from vstpetsc.plane.newton_steps import coupling

RTOL = 1e-12
MAX_IT = 100
FULL_STEPS = 12
HALVINGS = 12
ZERO = 1e-12            # a block below this times the springs' is a pair's rounding
UNCHANGED = 1e-14       # a change of e below this times |e| is rounding


class PairNewton(HeldWork):
    """Slabs of ``A_c`` (its solver ``inner``, set up) with ``pairs`` at
    ``dofs`` (vstpetsc.plane.contact_newton.PairDofs)."""

    def __init__(self, A_c, inner, pairs, dofs, comm):
        self.A_c, self.inner, self.pairs, self.dofs, self.comm = A_c, inner, pairs, dofs, comm
        self.rank0 = comm.getRank() == 0
        self.rhs, self.u = A_c.createVecLeft(), A_c.createVecLeft()
        dofs.bind(self.rhs)
        self.S, self.Z = coupling(A_c, inner, pairs, dofs, comm)
        scale = max(float(np.abs(pairs.spring_n).max(initial=0.0)),
                    float(np.abs(pairs.spring_t).max(initial=0.0)))
        self.zero = ZERO * scale * float(np.abs(pairs.hk).max())
        self.values = self.z = None

    def solve(self, b, x, k):
        """x solves the slab of right-hand side b from the start x holds
        (slab k for messages); returns (Newton iterations, solves)."""
        z = self.dofs.gather(x)
        e0 = None
        if self.rank0:
            self.pairs.evaluate(z)
            e0 = self.pairs.excess()
        b.copy(self.rhs)
        self.dofs.add(None if e0 is None else -self.pairs.to_dofs(e0), self.rhs)
        self.inner.solve(self.rhs, x)
        z = self.dofs.gather(x)
        outcome = self._on_rank0(z, e0) if self.rank0 else None
        its, w, error = self.comm.tompi4py().bcast(outcome, root=0)
        if error:
            raise SolveFailed(f"slab {k}: {error}")
        if w is None:
            return its, 1
        return its, 1 + self._correct(x, w)

    def _on_rank0(self, z, e0):
        """(iterations, e - e0 (m, 4) or None when unchanged, error)."""
        pairs = self.pairs
        y1 = pairs.coordinates(z)
        yb = y1 + (self.S @ e0.ravel()).reshape(-1, 4)
        try:
            its, e = self._newton(y1, yb)
        except SolveFailed as exc:
            return 0, None, str(exc)
        self.values, self.z = pairs.to_dofs(e), z
        w = (e - e0).ravel()
        # a pair closed and sticking keeps e: its change is rounding, not a correction
        keep = np.flatnonzero(np.abs(w) > UNCHANGED * np.abs(e).max(initial=0.0))
        return its, ((keep, w[keep]) if keep.size else None), None

    def _correct(self, x, change):
        """x -= A_c^-1 E w for w's entries ``change`` = (indices, values);
        returns the solves it took."""
        keep, w = change
        if self.Z is not None:
            x.setArray(x.getArray(readonly=True) - w @ self.Z[keep])
            return 0
        full = np.zeros(4 * self.pairs.m)
        full[keep] = w
        self.rhs.zeroEntries()
        self.dofs.add(self.pairs.to_dofs(full.reshape(-1, 4)) if self.rank0 else None,
                      self.rhs)
        self.inner.solve(self.rhs, self.u)
        x.axpy(-1.0, self.u)
        return 1

    def _residual(self, y, yb):
        """(r, max |r|, tolerance, e) at y (the kernels evaluated there)."""
        self.pairs.evaluate_at(y)
        e = self.pairs.excess()
        se = (self.S @ e.ravel()).reshape(-1, 4)
        r = y - yb + se
        tol = RTOL * (np.abs(yb).max(initial=0.0) + np.abs(se).max(initial=0.0))
        return r, np.abs(r).max(initial=0.0), tol, e

    def _newton(self, y, yb):
        """(iterations, e at the solution y), the kernels' last evaluation
        there."""
        r, norm, tol, e = self._residual(y, yb)
        for it in range(MAX_IT + 1):
            if norm <= tol:
                return it, e
            if it == MAX_IT:
                break
            step = self._step(r)
            y, r, norm, tol, e = self._line(y, yb, step, norm, it)
        raise SolveFailed(f"the interfaces' Newton did not converge in {MAX_IT} iterations "
                          f"(max |r| = {norm:.3g}, tolerance {tol:.3g})")

    def _step(self, r):
        """-(I + S e'(y))^-1 r, over the pairs whose e' is not zero."""
        D = self.pairs.excess_tangent()
        K = np.flatnonzero(np.abs(D).reshape(D.shape[0], -1).max(axis=1) > self.zero)
        step = -r.copy()
        if not K.size:
            return step
        rows = (4 * K[:, None] + np.arange(4)).ravel()
        SK = self.S[:, rows]                                       # (4m, 4k)
        DK = D[K]                                                  # its 4 x 4 blocks
        SD = np.einsum("rkb,kbc->rkc", SK.reshape(-1, K.size, 4), DK).reshape(-1, rows.size)
        dK = np.linalg.solve(np.eye(rows.size) + SD[rows], -r.ravel()[rows])
        flat = -r.ravel() - SD @ dK
        flat[rows] = dK
        return flat.reshape(-1, 4)

    def _line(self, y, yb, step, norm, it):
        """y + step: full for the first FULL_STEPS iterations, then the
        best of the step and its halvings."""
        best = None
        lam = 1.0
        for _ in range(1 if it < FULL_STEPS else HALVINGS):
            trial = y + lam * step
            r, new, tol, e = self._residual(trial, yb)
            if best is None or new < best[2]:
                best = (trial, r, new, tol, e, lam)
            if new < norm:
                break
            lam *= 0.5
        trial, r, new, tol, e, lam = best
        if lam != 1.0 or new >= norm:
            r, new, tol, e = self._residual(trial, yb)     # the kernels at the chosen y
        return trial, r, new, tol, e
