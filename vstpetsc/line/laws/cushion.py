"""A compression-only cushion between two ends (hammer cushion, pile
cushion, helmet): ``formulation = "cushion"`` of a [[contact]].

The force is a function of the compression delta = -g and of the largest
compression M of the current contact: loading along k delta (while delta
is at its largest so far), unloading along a line of stiffness
k_u = k / e^2 from (M, k M), never pulling:

    F = k delta                                 loading (delta = M, rising)
    F = max(0, k M - k_u (M - delta))           otherwise

so a blow returns the fraction e^2 of the energy stored at M, and a rigid
mass rebounds at e times its speed (the restitution convention of
GRLWEAP).  M starts from 0 and returns to 0 once the gap is open at a
slab end (the ends separated).

Inside a slab delta is the quadratic -g(theta) (:mod:`vstpetsc.kernels.gap`),
so the slab splits exactly at the points where the law changes: where
delta first exceeds M (loading starts), at delta's vertex (loading stops,
M takes its value there), and where the unloading line reaches zero force.
Each piece is integrated against the power formulation's weights T_a
with 3-point Gauss (cubic integrands: exact).  The tangent includes M's
dependence on the slab's velocities when M is reached inside the slab.
"""

from vstpetsc.input.checker import MAGNITUDE
from vstpetsc.kernels.gap import GAUSS, closed_somewhere, gap_coefficients, merged, roots01
from vstpetsc.line.laws.pair import PairLaw

KEYS = ("stiffness", "restitution")


def read(chk, tbl, where):
    """``stiffness`` (required, > 0) and ``restitution`` e in (0, 1]
    (default 1: elastic)."""
    k = chk.number(tbl, "stiffness", where, positive=True)
    e = chk.number(tbl, "restitution", where, required=False, default=1.0, positive=True)
    if e is not None and e > 1.0:
        chk.add(f"{where}.restitution", f"must lie in (0, 1], got {e:g}")
        e = None
    elif e is not None and k is not None and not k / e / e <= MAGNITUDE[1]:
        # the unloading stiffness k / e^2 must stay a number the solver can use
        chk.add(f"{where}.restitution", f"too small for stiffness {k:g}: the unloading "
                f"stiffness / restitution^2 exceeds {MAGNITUDE[1]:g}, got {e:g}")
        e = None
    return None if k is None or e is None else {"stiffness": k, "restitution": e}


def _pieces(theta1, theta2):
    """[(p, q, kind)] of [0, 1]: "load" on [theta1, theta2], "unload" with
    the slab's earlier or later M elsewhere (theta1 None: no loading)."""
    if theta1 is None:
        return [(0.0, 1.0, "before")]
    out = [(0.0, theta1, "before"), (theta1, theta2, "load"), (theta2, 1.0, "after")]
    return [p for p in out if p[1] > p[0]]


def _loading(c, M):
    """(theta1, theta2) of the slab's loading interval, where delta =
    c0 + c1 t + c2 t^2 rises above M, or (None, None)."""
    c0, c1, c2 = c
    vertex = -c1 / (2.0 * c2) if c2 < 0.0 else None
    top = vertex if vertex is not None and 0.0 < vertex < 1.0 else 1.0
    if c0 + top * (c1 + top * c2) <= M:
        return None, None                   # delta stays at or below M
    if c0 >= M and c1 >= 0.0:
        start = 0.0                         # loading from the slab's start
    else:
        ups = [r for r in roots01(c0 - M, c1, c2) if r < top]
        start = ups[-1] if ups else 0.0
    return start, top


def cushion_integrals(gn, d1, d2, dt, k, ku, M):
    """(f1, f2, df1/dd1, df1/dd2, df2/dd1, df2/dd2, M at the slab's end,
    the pieces [(p, q)] of [0, 1] where it pushes) of a cushion with
    largest earlier compression ``M``, or None when it exerts nothing in
    the slab."""
    a = gap_coefficients(gn, d1, d2, dt)
    c = (-a[0], -a[1], -a[2])                        # delta(theta)
    M = max(M, c[0])                                 # M is the largest compression so far
    zero = M * (1.0 - k / ku)                        # delta where unloading reaches F = 0
    if not closed_somewhere(a[0] + zero, a[1], a[2]):
        return None
    theta1, theta2 = _loading(c, M)
    M2, dM2 = M, None
    if theta1 is not None:                           # M2 = delta(theta2), the vertex or the end
        M2 = c[0] + theta2 * (c[1] + theta2 * c[2])
        half = 0.5 * theta2 * theta2
        dM2 = (dt * (theta2 - half), dt * half)      # dM2/dd_b (delta' = 0 at a vertex)
    out, spans = [0.0] * 6, []
    for p, q, kind in _pieces(theta1, theta2):
        if kind == "load":
            _add(out, c, p, q, dt, k, 0.0, None)
            spans.append((p, q))
            continue
        m, dm = (M, None) if kind == "before" else (M2, dM2)
        shift = m * (1.0 - k / ku)                   # F = ku (delta - shift)
        edges = [p] + [p + (q - p) * r for r in roots01(*_on(c, shift, p, q))] + [q]
        for s, t in zip(edges, edges[1:]):
            mid = 0.5 * (s + t)
            if c[0] + mid * (c[1] + mid * c[2]) > shift:
                _add(out, c, s, t, dt, ku, shift, None if dm is None else (1.0 - k / ku, dm))
                spans.append((s, t))
    if out == [0.0] * 6:
        return None
    return (*out, max(M, M2), spans)


def _on(c, shift, p, q):
    """Coefficients in s in [0, 1] of delta(p + (q - p) s) - shift."""
    w = q - p
    return (c[0] - shift + p * (c[1] + p * c[2]), w * (c[1] + 2.0 * p * c[2]), w * w * c[2])


def _add(out, c, p, q, dt, stiffness, shift, moving):
    """Add the piece [p, q] with F = stiffness (delta - shift): forces
    dt int F T_a and tangents dt int dF/dd_b T_a; ``moving`` = (factor,
    dM/dd) when shift = factor M with M reached inside the slab."""
    length = q - p
    for x, weight in GAUSS:
        t = p + length * x
        w = dt * length * weight
        F = stiffness * (c[0] + t * (c[1] + t * c[2]) - shift)
        half = 0.5 * t * t
        g1, g2 = stiffness * dt * (t - half), stiffness * dt * half    # dF/dd_b
        if moving:
            g1 -= stiffness * moving[0] * moving[1][0]
            g2 -= stiffness * moving[0] * moving[1][1]
        for a, T in ((0, 1.0 - t), (1, t)):
            out[a] += w * F * T
            out[2 + 2 * a] += w * g1 * T
            out[3 + 2 * a] += w * g2 * T


class Cushion(PairLaw):
    """A cushion pair: k, e and the largest compression M of the contact."""

    series = PairLaw.series + ("compression_max",)

    def __init__(self, spec, index, case, mesh):
        super().__init__(spec, index, case, mesh)
        self.k = spec.params["stiffness"]
        self.e = spec.params["restitution"]
        self.ku = self.k / (self.e * self.e)
        self.M = 0.0
        self.last = None

    def acts(self, d1, d2):
        zero = self.M * (1.0 - self.k / self.ku)
        return closed_somewhere(self.gn + zero, -self.dt * d1, 0.5 * self.dt * (d1 - d2))

    def force(self, d1, d2):
        out = self.last = cushion_integrals(self.gn, d1, d2, self.dt, self.k, self.ku, self.M)
        return None if out is None else out[:6]

    def finish_slab(self, t0, dt):
        """Record the slab's impulse; M moves on (or resets once apart)."""
        last = self.last
        self.add_impulse(last[0] + last[1] if last else 0.0, t0, dt)
        if last:
            self.M = last[6]
        if last or self.closed:
            self.track(t0, dt, merged(last[7]) if last else ())

    def start_slab(self, u, dt):
        super().start_slab(u, dt)
        if self.gn > 0.0:       # the ends are apart: the next contact starts fresh
            self.M = 0.0

    @property
    def static_stiffness(self):
        """The loading branch's stiffness (the static state, PairLaw.static)."""
        return self.k

    def values(self, u):
        return {**super().values(u), "compression_max": self.M}

    def restore(self, values):
        super().restore(values)
        self.M = float(values["compression_max"])

    def attrs(self):
        return {**super().attrs(), "stiffness": self.k, "restitution": self.e,
                "penalty": self.k}

    def describe(self):
        return (f"{super().describe()}, cushion k = {self.k:.6g}, restitution "
                f"{self.e:g} (unloading k / e^2 = {self.ku:.6g})")


def build(spec, index, case, mesh):
    return Cushion(spec, index, case, mesh)

