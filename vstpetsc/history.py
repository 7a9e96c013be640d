"""Piecewise-linear histories ``f(t)`` (or profiles ``f(x)``) given as a number
or a ``[[t, value], ...]`` table, and their exact integrals against the linear
time shape functions of a slab."""

import numpy as np

# 3-point Gauss-Legendre rule on [0, 1]: exact for polynomials of degree <= 5.
GAUSS_X = 0.5 + 0.5 * np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
GAUSS_W = np.array([5.0, 8.0, 5.0]) / 18.0


class History:
    """A constant or a piecewise-linear function of one variable.

    Outside the table the end values are held (like :func:`numpy.interp`).

    Parameters
    ----------
    points : array_like, shape (n, 2), optional
        Increasing abscissae and values.  ``None`` for a constant.
    value : float
        The constant value when ``points`` is ``None``.
    """

    def __init__(self, points=None, value=0.0):
        if points is None:
            self.t = np.array([0.0])
            self.f = np.array([float(value)])
        else:
            pts = np.asarray(points, dtype=float)
            self.t, self.f = pts[:, 0].copy(), pts[:, 1].copy()

    @property
    def is_zero(self):
        return not np.any(self.f)

    def __eq__(self, other):
        return (isinstance(other, History) and np.array_equal(self.t, other.t)
                and np.array_equal(self.f, other.f))

    def __repr__(self):
        if self.t.size == 1:
            return f"History({self.f[0]!r})"
        return f"History({self.t.size} points, {self.t[0]:g} .. {self.t[-1]:g})"

    def __call__(self, t):
        return np.interp(t, self.t, self.f)

    def hat_integrals(self, t0, t1):
        """Exact ``(int T1 f dt, int T2 f dt)`` over ``[t0, t1]``.

        ``T1 = 1 - theta`` and ``T2 = theta`` with ``theta = (t - t0)/(t1 - t0)``;
        the interval is split at the table's break points, so a Gauss rule on
        each piece integrates the product of two linear functions exactly.
        """
        inner = self.t[(self.t > t0) & (self.t < t1)]
        edges = np.concatenate(([t0], inner, [t1]))
        lo, length = edges[:-1], np.diff(edges)
        t = lo[:, None] + length[:, None] * GAUSS_X[None, :]
        w = length[:, None] * GAUSS_W[None, :]
        f = self(t) * w
        theta = (t - t0) / (t1 - t0)
        return np.array([np.sum(f * (1.0 - theta)), np.sum(f * theta)])
