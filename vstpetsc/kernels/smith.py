"""The Smith (1960) soil resistance of one node over one slab, exactly
integrated, in plain floats (docs/pile-driving.md).

w is the node's displacement into the ground, v its velocity into the
ground; p the plastic slip, k = R_u / q.  The static resistance is
elastic-perfectly plastic, R_s = k (w - p) within +-R_u (the toe: within
[0, R_u], no pull; a toe whose w falls below p has an open gap), and the
total is R = R_s + J |R_s| v (Smith damping written so that it never adds
energy); at the toe R = max(0, R_s (1 + J v)).

Inside a slab w is the quadratic w^n + y1 I_1 + y2 I_2 and v the line
y1 T_1 + y2 T_2, so the slab splits exactly: at w's vertex (the motion
turns), where the node reaches its yield limit (plastic flow starts), where
R_s changes sign (|R_s| has a kink) and, at the toe, where 1 + J v = 0.
Each piece is integrated with 3-point Gauss against T_a (the integrands are
polynomials of degree 4: exact), the tangent with it; after a plastic
piece that ends at the vertex the slip depends on the slab's velocities
through w(vertex), and the tangent includes that.
"""

from vstpetsc.kernels.gap import GAUSS, roots01


def _w(b, t):
    return b[0] + t * (b[1] + t * b[2])


def _roots(b, level, s, t):
    """Roots of w(theta) = level strictly inside (s, t), sorted."""
    w = t - s
    coef = (_w(b, s) - level, w * (b[1] + 2.0 * s * b[2]), w * w * b[2])
    return [s + w * r for r in roots01(*coef)]


def smith_integrals(wn, p, y1, y2, dt, k, Ru, J, toe):
    """(f1, f2, df1/dy1, df1/dy2, df2/dy1, df2/dy2, slip at the slab's end)
    with f_a = dt int R T_a, or None when the node exerts nothing."""
    b = (wn, dt * y1, 0.5 * dt * (y2 - y1))
    q = Ru / k
    out = [0.0] * 6
    edges = [0.0, 1.0]
    if b[2] != 0.0 and 0.0 < -b[1] / (2.0 * b[2]) < 1.0:
        edges = [0.0, -b[1] / (2.0 * b[2]), 1.0]
    dp = (0.0, 0.0)                     # d p / d y_b (p from earlier slabs: 0)
    node = (y1, y2, dt, k, Ru, J, toe)
    for s, t in zip(edges, edges[1:]):
        mid = 0.5 * (s + t)
        direction = 1.0 if b[1] + 2.0 * mid * b[2] > 0.0 else -1.0
        yields = direction > 0.0 or not toe
        limit = p + direction * q
        ty = t
        if yields:
            if direction * (_w(b, s) - p) >= q * (1.0 - 1e-12):
                ty = s                  # already flowing
            else:
                ups = _roots(b, limit, s, t)
                ty = ups[0] if ups else t
        if ty > s:
            _elastic(out, b, p, dp, s, ty, node)
        if ty < t:
            _pieces(out, b, None, None, direction, ty, t, node)
            p = _w(b, t) - direction * q
            half = 0.5 * t * t
            dp = (dt * (t - half), dt * half)
    if out == [0.0] * 6:
        return None
    return (*out, p)


def _elastic(out, b, p, dp, s, t, node):
    """An elastic stretch [s, t]: split where R_s changes sign."""
    cuts = [s] + _roots(b, p, s, t) + [t]
    for a, c in zip(cuts, cuts[1:]):
        _pieces(out, b, p, dp, None, a, c, node)


def _pieces(out, b, p, dp, plastic, s, t, node):
    """Add [s, t] (elastic about slip p, or plastic in direction
    ``plastic``), split at the toe where 1 + J v = 0."""
    y1, y2, dt, k, Ru, J, toe = node
    cuts = [s, t]
    if toe and J > 0.0 and y2 != y1:
        c = (-1.0 / J - y1) / (y2 - y1)
        if s < c < t:
            cuts = [s, c, t]
    for a, c in zip(cuts, cuts[1:]):
        _gauss(out, b, p, dp, plastic, a, c, node)


def _gauss(out, b, p, dp, plastic, s, t, node):
    """3-point Gauss on [s, t], where the law is smooth."""
    y1, y2, dt, k, Ru, J, toe = node
    length = t - s
    for x, weight in GAUSS:
        th = s + length * x
        w = dt * length * weight
        v = y1 + (y2 - y1) * th
        T = (1.0 - th, th)
        if plastic is None:
            Rs = k * (_w(b, th) - p)
            half = 0.5 * th * th
            dRs = (k * (dt * (th - half) - dp[0]), k * (dt * half - dp[1]))
            if toe and Rs <= 0.0:
                continue                # the toe's gap is open
        else:
            Rs, dRs = plastic * Ru, (0.0, 0.0)
        if toe:
            factor = 1.0 + J * v
            if factor <= 0.0:
                continue
            R = Rs * factor
            dR = (dRs[0] * factor + Rs * J * T[0], dRs[1] * factor + Rs * J * T[1])
        else:
            sign = 1.0 if Rs > 0.0 else -1.0 if Rs < 0.0 else 0.0
            R = Rs + J * abs(Rs) * v
            dR = (dRs[0] * (1.0 + J * sign * v) + J * abs(Rs) * T[0],
                  dRs[1] * (1.0 + J * sign * v) + J * abs(Rs) * T[1])
        for a in (0, 1):
            out[a] += w * R * T[a]
            out[2 + 2 * a] += w * dR[0] * T[a]
            out[3 + 2 * a] += w * dR[1] * T[a]
