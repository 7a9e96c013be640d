"""Newton on the laws' reduced coordinates in plain Python floats.

The slab's nonlinear system, condensed onto the laws' 2L coordinates y
(:mod:`vstpetsc.line.solver.newton`), is r(y) = y - y0 + S f(y) = 0 with S a
dense 2L x 2L matrix and f block diagonal: law j acts on (y_2j, y_2j+1)
only.  A law that does nothing at y has f_j = 0 and a zero tangent, so the
Newton matrix I + S f'(y) is the identity in its columns: the step solves a
system over the acting laws only (2 x 2 in floats for one) and gets the
others' components by substitution.  L is small (contact pairs), where
numpy's per-call cost (about 1 us) would exceed the arithmetic.

Full steps, halved while the residual's largest entry does not fall.
Converged when max |r| <= max(atol, rtol (max |y0| + max |S f|)).
"""

import numpy as np

from vstpetsc.errors import SolveFailed


class ReducedNewton:
    """Solves r(y) = 0 for the laws of a LawSet and the matrix S."""

    def __init__(self, lawset, S, rtol=1e-12, atol=1e-50, max_it=30):
        self.laws = lawset.laws
        self.lawset = lawset
        self.S = [[float(x) for x in row] for row in S]
        self.n = len(self.S)
        self.rtol, self.atol, self.max_it = rtol, atol, max_it
        self.iterations = 0

    def solve(self, y0, slab_index, start=None):
        """y (a list) with r(y) = 0 from ``start`` (default y0); the laws'
        last evaluation is at it, and the LawSet's ``f`` holds their terms."""
        y0 = [float(v) for v in y0]
        y = y0 if start is None else [float(v) for v in start]
        outs, r, sf = self._residual(y, y0)
        if start is not None and not any(outs):
            # a start where no law acts: its Newton step would go straight
            # back to the law-free y0, where we know one acts
            y = y0
            outs, r, sf = self._residual(y, y0)
        size = max(map(abs, y0))
        norm = max(map(abs, r))
        for it in range(self.max_it + 1):
            if norm <= max(self.atol, self.rtol * (size + sf)):
                self.iterations = it
                self._keep(outs)
                return y
            if it == self.max_it:
                break
            step = self._step(outs, r)
            if step is None:
                break
            y, outs, r, sf, norm = self._line(y, y0, step, norm)
        self._keep(outs)
        raise not_converged(slab_index, self.max_it, norm)

    def _residual(self, y, y0):
        """(the laws' outputs, r, max |S f|) at y."""
        outs = [law.force(y[2 * j], y[2 * j + 1]) for j, law in enumerate(self.laws)]
        sf = [0.0] * self.n
        for j, out in enumerate(outs):
            if out is not None:
                f1, f2 = out[0], out[1]
                for i, row in enumerate(self.S):
                    sf[i] += row[2 * j] * f1 + row[2 * j + 1] * f2
        r = [a - b + c for a, b, c in zip(y, y0, sf)]
        return outs, r, max(map(abs, sf))

    def _line(self, y, y0, step, norm):
        """Full step, halved (up to 20 times) while the residual grows."""
        lam = 1.0
        for _ in range(20):
            trial = [a - lam * b for a, b in zip(y, step)]
            outs, r, sf = self._residual(trial, y0)
            new = max(map(abs, r))
            if new < norm or lam < 1e-5:
                break
            lam *= 0.5
        return trial, outs, r, sf, new

    def _step(self, outs, r):
        """(I + S f'(y))^-1 r, or None if singular."""
        active = [j for j, out in enumerate(outs) if out is not None]
        if not active:
            return list(r)
        if len(active) == 1:
            return self._step_one(active[0], outs[active[0]], r)
        rows = [i for j in active for i in (2 * j, 2 * j + 1)]
        # the acting laws' block M_AA = I + S_AA J_A, J block diagonal: law
        # j's tangent (t11, t12, t21, t22) = d f_(2j, 2j+1) / d y_(2j, 2j+1)
        blocks = [(2 * j, outs[j][2], outs[j][3], outs[j][4], outs[j][5]) for j in active]
        M = []
        for i, a in enumerate(rows):
            Sa, row = self.S[a], []
            for c, t11, t12, t21, t22 in blocks:
                s1, s2 = Sa[c], Sa[c + 1]
                row += [s1 * t11 + s2 * t21, s1 * t12 + s2 * t22]
            row[i] += 1.0
            M.append(row)
        rhs = [r[a] for a in rows]
        d = _solve2(M, rhs) if len(rows) == 2 else _solve_dense(M, rhs)
        if d is None:
            return None
        step = list(r)
        for a, value in zip(rows, d):
            step[a] = value
        # the others: d_I = r_I - S_IA J_A d_A
        jd = []
        for k, (c, t11, t12, t21, t22) in enumerate(blocks):
            d1, d2 = d[2 * k], d[2 * k + 1]
            jd += [(c, t11 * d1 + t12 * d2), (c + 1, t21 * d1 + t22 * d2)]
        acting = set(rows)
        for i in range(self.n):
            if i not in acting:
                Si = self.S[i]
                step[i] = r[i] - sum(Si[c] * value for c, value in jd)
        return step

    def _step_one(self, j, out, r):
        """_step when law j alone acts, written out in floats."""
        S, a, b = self.S, 2 * j, 2 * j + 1
        t11, t12, t21, t22 = out[2], out[3], out[4], out[5]      # d f_a / d y_b
        d = _solve2(((1.0 + S[a][a] * t11 + S[a][b] * t21, S[a][a] * t12 + S[a][b] * t22),
                     (S[b][a] * t11 + S[b][b] * t21, 1.0 + S[b][a] * t12 + S[b][b] * t22)),
                    (r[a], r[b]))
        if d is None:
            return None
        jd1, jd2 = t11 * d[0] + t12 * d[1], t21 * d[0] + t22 * d[1]
        step = [ri - row[a] * jd1 - row[b] * jd2 for ri, row in zip(r, S)]
        step[a], step[b] = d
        return step

    def _keep(self, outs):
        """The LawSet's terms f at the last evaluation."""
        f = self.lawset.f
        for j, out in enumerate(outs):
            f[2 * j], f[2 * j + 1] = (0.0, 0.0) if out is None else (out[0], out[1])


def not_converged(slab_index, max_it, norm):
    """The error of a plain Newton that stopped short (Python or compiled)."""
    return SolveFailed(f"slab {slab_index}: Newton did not converge (DIVERGED_MAX_IT "
                       f"after {max_it} Newton iterations, residual {norm:.3g})")


def _solve2(M, r):
    (m11, m12), (m21, m22) = M
    det = m11 * m22 - m12 * m21
    if det == 0.0 or det != det or abs(det) == float("inf"):
        return None
    return [(m22 * r[0] - m12 * r[1]) / det, (m11 * r[1] - m21 * r[0]) / det]


def _solve_dense(M, r):
    try:
        return list(np.linalg.solve(np.array(M), np.array(r)))
    except np.linalg.LinAlgError:
        return None


class ManyLawNewton(ReducedNewton):
    """:class:`ReducedNewton` for many laws (Smith soil on every shaft
    node): the products with S and the step's system over the acting laws
    in numpy, the laws still evaluated one by one."""

    def __init__(self, lawset, S, **kw):
        super().__init__(lawset, S, **kw)
        self.S_np = np.array(S, dtype=float)
        # laws that evaluate many at once (force_batch), grouped by kind
        kinds = {}
        for j, law in enumerate(self.laws):
            if hasattr(type(law), "force_batch"):
                kinds.setdefault(type(law), []).append(j)
        self.batches = [(cls.force_batch, np.array(js), [self.laws[j] for j in js])
                        for cls, js in kinds.items()]
        batched = {j for _, js, _ in self.batches for j in js}
        self.single = [j for j in range(len(self.laws)) if j not in batched]

    def _outputs(self, y):
        """Every law's force() at y, the batched kinds at once."""
        outs = [None] * len(self.laws)
        for j in self.single:
            outs[j] = self.laws[j].force(y[2 * j], y[2 * j + 1])
        ya = np.asarray(y, dtype=float)
        for force, js, laws in self.batches:
            for j, out in zip(js, force(laws, ya[2 * js], ya[2 * js + 1])):
                outs[j] = out
        return outs

    def _residual(self, y, y0):
        outs = self._outputs(y)
        f = np.zeros(self.n)
        for j, out in enumerate(outs):
            if out is not None:
                f[2 * j], f[2 * j + 1] = out[0], out[1]
        sf = self.S_np @ f
        r = np.asarray(y, dtype=float) - np.asarray(y0, dtype=float) + sf
        return outs, r.tolist(), float(np.abs(sf).max())

    def _step(self, outs, r):
        """(I + S J) d = r: over the acting laws' rows A first
        (d_A + S_AA J_A d_A = r_A), then d_I = r_I - S_IA J_A d_A."""
        active = [j for j, out in enumerate(outs) if out is not None]
        if not active:
            return list(r)
        rows = np.array([i for j in active for i in (2 * j, 2 * j + 1)])
        J = np.zeros((rows.size, rows.size))
        for k, j in enumerate(active):
            out = outs[j]
            J[2 * k:2 * k + 2, 2 * k:2 * k + 2] = ((out[2], out[3]), (out[4], out[5]))
        r = np.asarray(r, dtype=float)
        M = np.eye(rows.size) + self.S_np[np.ix_(rows, rows)] @ J
        try:
            dA = np.linalg.solve(M, r[rows])
        except np.linalg.LinAlgError:
            return None
        step = r - self.S_np[:, rows] @ (J @ dA)
        step[rows] = dA
        return step.tolist() if np.isfinite(step).all() else None
