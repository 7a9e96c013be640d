"""Coulomb friction of a contact pair over one slab: the exact slab integrals
of a tangential elastic-perfectly-plastic spring whose yield limit follows
the normal contact force, in plain floats (the style of kernels/gap.py and
kernels/smith.py).  Not yet wired into a law (issue 27).

Inside a slab theta = (t - t^n)/dt in [0, 1], T_1 = 1 - theta, T_2 = theta,
I_a(theta) = dt int_0^theta T_a.  The pair's relative shear velocity (the
reduced coordinates of its shear dofs) is s(theta) = s1 T_1 + s2 T_2 and
the spring's elastic stretch

    e(theta) = e_n + I_1 s1 + I_2 s2 - p(theta),   p the slip in the slab,

with the friction force T = -k_t e and |k_t e| <= mu N(theta).  The normal
force N >= 0 is given as a quadratic N = n0 + n1 theta + n2 theta^2 on its
active pieces [(p, q)] (N = 0 elsewhere); penalty_normal() gives them for
the power penalty N = k max(0, -g) from gap.py's coefficients.  Polynomial
coefficients rather than a callable: every switching point is then the
root of a polynomial (gap.roots01, cancellation-free, no bracketing or
tolerance on a root finder), and the seed's slab-mean normal force is the
same input (n0 = J/dt, one piece [(0, 1)]).

Sub-intervals, on a piece, from a known state:
- elastic: e = e_a + dt int_a^theta s, T = -k_t e (quadratic).  It yields
  where f_sigma = sigma k_t e - mu N reaches 0 from below and rises
  (sigma = +-1; f_sigma is quadratic: the first root with f_sigma > 0
  after it, tested at the midpoints between roots);
- sliding in direction sigma: e = sigma mu N / k_t, T = -sigma mu N, slip
  rate dp/dtheta = dt s - sigma mu N' / k_t.  It continues while
  h_sigma = sigma k_t dt s - mu N' >= 0 (= d f_sigma / d theta: the elastic
  trial rate outruns the limit) and returns to elastic at the root of h_sigma
  (linear in theta).  With N constant that is where s changes sign
  (unloading by reversal); a limit that grows faster than the stretch also
  unloads, and a shrinking one drags e with it (slip without s).
Tangent: T is continuous in theta at every switch, so a switch point
moving with s1, s2 adds nothing to dF_a/ds_b, and a sliding piece's force
does not depend on s.  Nor does the stretch after sliding ends at x:
e(theta) = sigma mu N(x)/k_t + dt int_x^theta s moves with x at the rate
sigma mu N'(x)/k_t - dt s(x) = -sigma h_sigma(x)/k_t = 0.  So only the
elastic pieces contribute: de/ds_b = dt int_a^theta T_b from the start a
of the elastic run (the slab's start, a piece's start, or an exit point).

Gap open (N = 0 outside the pieces): T = 0 and e = 0.  The limit
|k_t e| <= mu N = 0 leaves no stretch, and the surfaces, no longer
touching, carry no tangential bond: when they touch again they stick where
they meet, from e = 0.  With the power penalty N falls continuously to 0,
so sliding has already dragged e to 0 at the opening: the reset makes no
jump in T and releases no energy outside the dissipation.

Returned (FrictionSlab): F_a = dt int T T_a dtheta (the power weight; every
integrand is a polynomial of degree <= 3 on its sub-interval: 3-point Gauss
is exact), dF_a/ds_b, the stretch at the slab's end, the slip accumulated in
contact (relative motion while the gap is open is not slip), and the
dissipation D = int mu N |dp/dt| dt >= 0.  Since s = s1 T_1 + s2 T_2,
D = -(s1 F_1 + s2 F_2) - k_t (e_end^2 - e_n^2) / 2 (work identity) and
e_end - e_n = dt int_pieces s - slip (kinematics).  A start stretch beyond
the limit at theta = 0 is projected onto it: rounding of the previous
slab's end with the power penalty (N continuous in time); with the seed's
slab-mean N, which jumps between slabs, the projection releases
k_t (e_n^2 - e^2) / 2 outside D (returned as ``released``), which whoever
calls this must book.
"""

from typing import NamedTuple

from vstpetsc.kernels.gap import GAUSS, active_intervals, roots01

_MAX_SWITCHES = 64      # a piece has a handful; more would be a float loop


class FrictionSlab(NamedTuple):
    f1: float
    f2: float
    d11: float          # dF_1/ds_1
    d12: float
    d21: float
    d22: float
    stretch: float      # e at the slab's end
    slip: float         # slip accumulated in contact over the slab
    dissipation: float  # int mu N |slip rate| dt >= 0
    released: float     # k_t (e_n^2 - e^2) / 2 of the projection of e_n onto the start limit


def penalty_normal(a0, a1, a2, k):
    """(n0, n1, n2), pieces of the power penalty N = k max(0, -g) for the
    gap g = a0 + a1 theta + a2 theta^2 (gap.gap_coefficients)."""
    return (-k * a0, -k * a1, -k * a2), active_intervals(a0, a1, a2)


def _J(t):
    """(int_0^t T_1, int_0^t T_2)."""
    half = 0.5 * t * t
    return t - half, half


class _Slab:
    """What the pieces of one slab share: the motion, the normal force, the
    friction constants and the running sums."""

    def __init__(self, s1, s2, dt, k, mu, normal):
        self.s1, self.s2, self.dt, self.k, self.mu = s1, s2, dt, k, mu
        self.n0, self.n1, self.n2 = normal
        self.out = [0.0] * 6
        self.slip = self.dissipation = 0.0
        # |h| below this is rounding (h_sigma sums terms of these sizes)
        self.tol = 1e-12 * (k * dt * (abs(s1) + abs(s2))
                            + mu * (abs(self.n1) + 2.0 * abs(self.n2)))

    def normal(self, t):
        """N(t) on a piece (never below 0: a root at a piece's edge may
        round to a slightly negative value just inside it)."""
        return max(0.0, self.n0 + t * (self.n1 + t * self.n2))

    def dnormal(self, t):
        return self.n1 + 2.0 * t * self.n2

    def moved(self, a, b):
        """Relative displacement dt int_a^b s."""
        (pa, qa), (pb, qb) = _J(a), _J(b)
        return self.dt * (self.s1 * (pb - pa) + self.s2 * (qb - qa))

    def h(self, sigma, t):
        """sigma k dt s - mu N': the trial rate of f_sigma."""
        s = self.s1 + (self.s2 - self.s1) * t
        return sigma * self.k * self.dt * s - self.mu * self.dnormal(t)

    def h_slope(self, sigma):
        return sigma * self.k * self.dt * (self.s2 - self.s1) - 2.0 * self.mu * self.n2

    def slides_from(self, sigma, t):
        """Whether the limit in direction sigma is pushed outward just after t."""
        h = self.h(sigma, t)
        return h > self.tol or (h >= -self.tol and self.h_slope(sigma) > 0.0)


def friction_integrals(e_n, s1, s2, dt, k_t, mu, normal, pieces):
    """FrictionSlab of one slab: stretch e_n at its start, relative shear
    velocities s1, s2, tangential stiffness k_t, coefficient mu, the normal
    force's coefficients ``normal`` on its ordered active ``pieces``."""
    slab = _Slab(s1, s2, dt, k_t, mu, normal)
    start_limit = mu * slab.n0 / k_t if pieces and pieces[0][0] == 0.0 else 0.0
    e = max(-start_limit, min(start_limit, e_n))
    released = 0.5 * k_t * (e_n * e_n - e * e)
    for p, q in pieces:
        if p > 0.0:
            e = 0.0                 # the gap was open just before p
        e = _piece(slab, e, p, q)
    if not pieces or pieces[-1][1] < 1.0:
        e = 0.0                     # open at the slab's end
    return FrictionSlab(*slab.out, e, slab.slip, slab.dissipation, released)


def _piece(slab, e, p, q):
    """One active piece [p, q] from stretch e at p; the stretch at q."""
    t, de, sigma = p, (0.0, 0.0), None
    for _ in range(_MAX_SWITCHES):
        if t >= q:
            return e
        if sigma is None:
            ts, sigma = _yield_point(slab, e, t, q)
            if ts > t:
                e, de = _elastic(slab, e, de, t, ts)
            t = ts
        else:
            x = _exit_point(slab, sigma, t, q)
            _sliding(slab, sigma, t, x)
            e, de = sigma * slab.mu * slab.normal(x) / slab.k, (0.0, 0.0)
            t, sigma = x, None
    raise ArithmeticError("coulomb: friction switches did not settle in a slab")


def _yield_point(slab, e, t0, q):
    """(theta, sigma) where the elastic stretch from e at t0 first reaches
    the limit and presses on it, or (q, None)."""
    L, best = q - t0, (q, None)
    k, mu = slab.k, slab.mu
    for sigma in (1.0, -1.0):
        c0 = sigma * k * e - mu * slab.normal(t0)
        if c0 >= -1e-12 * mu * slab.normal(t0) and slab.slides_from(sigma, t0):
            return t0, sigma        # on the limit (to rounding) and pressed on
        c1 = L * slab.h(sigma, t0)
        c2 = L * L * (0.5 * sigma * k * slab.dt * (slab.s2 - slab.s1) - mu * slab.n2)
        cuts = (0.0,) + roots01(c0, c1, c2) + (1.0,)
        for u, v in zip(cuts, cuts[1:]):
            ts = t0 + L * u
            if ts >= best[0]:
                break
            m = 0.5 * (u + v)
            if c0 + m * (c1 + m * c2) > 0.0 and slab.slides_from(sigma, ts):
                best = (ts, sigma)
                break
    return best


def _exit_point(slab, sigma, t, q):
    """Where sliding from t ends: the root of h_sigma ahead, or q."""
    slope = slab.h_slope(sigma)
    if slope < 0.0:
        x = t - slab.h(sigma, t) / slope
        if t < x < q:
            return x
    return q


def _elastic(slab, e, de, a, b):
    """Add the elastic stretch [a, b] from e (de: its derivatives by s1, s2)
    at a; return the stretch at b and its derivatives."""
    k, dt, out = slab.k, slab.dt, slab.out
    ja = _J(a)
    length = b - a
    for x, weight in GAUSS:
        t = a + length * x
        w = dt * length * weight
        jt = _J(t)
        force = -k * (e + slab.moved(a, t))
        dforce = (-k * (de[0] + dt * (jt[0] - ja[0])), -k * (de[1] + dt * (jt[1] - ja[1])))
        for i, phi in enumerate((1.0 - t, t)):
            out[i] += w * force * phi
            out[2 + 2 * i] += w * dforce[0] * phi
            out[3 + 2 * i] += w * dforce[1] * phi
    jb = _J(b)
    return (e + slab.moved(a, b),
            (de[0] + dt * (jb[0] - ja[0]), de[1] + dt * (jb[1] - ja[1])))


def _sliding(slab, sigma, a, b):
    """Add sliding in direction sigma over [a, b]: force, slip, dissipation
    (mu N sigma dp/dtheta = mu N h_sigma / k_t)."""
    mu, out = slab.mu, slab.out
    length = b - a
    for x, weight in GAUSS:
        t = a + length * x
        n = slab.normal(t)
        w = slab.dt * length * weight
        out[0] -= w * sigma * mu * n * (1.0 - t)
        out[1] -= w * sigma * mu * n * t
        slab.dissipation += length * weight * mu * n * slab.h(sigma, t) / slab.k
    slab.slip += slab.moved(a, b) - sigma * mu * (slab.normal(b) - slab.normal(a)) / slab.k
