"""The MKZ law with extended Masing rules (:mod:`vstpetsc.materials.masing`)
carried to the plane-strain deviators (issue 46; docs/nonlinear-soil.md,
"Yielding in plane strain: the law"), for n material points at once.
Pure numpy: no PETSc, neither geometry room.

Strains are (exx, eyy, gxy) with gxy = 2 exy and ezz = 0; stresses
(sxx, syy, sxy, szz).  The deviator e = eps - (tr eps / 3) I is written in
the orthonormal basis of the plane-strain deviators

    E1 = (xx - yy) / sqrt2,  E2 = (xx + yy - 2 zz) / sqrt6,  E3 = (xy + yx) / sqrt2,

c_i = e : E_i, so that e : e = |c|^2 and

    c1 = (exx - eyy) / sqrt2,  c2 = (exx + eyy) / sqrt6,  c3 = gxy / sqrt2

(c2 is the out-of-plane part: ezz = 0 makes exx = eyy a deviatoric
strain too).  The stress deviator s has coordinates in the same basis, so
s : de = s . dc and sigma : deps = p tr(deps) + s . dc.  Equivalent shear
strain gamma(e) = sqrt(2 e:e) = sqrt2 |c| (= 2 sqrt(J2(e)); |gxy| in simple
shear), equivalent shear stress tau(s) = sqrt(s:s / 2).

The law.  p = K tr(eps): linear, K the bulk modulus (lam + 2 mu / 3 also
in plane strain).  The deviator follows the 1-D rules on the backbone
F (MKZ, masing.Backbone):

- backbone (depth 0): s = 2 F(gamma(e)) / gamma(e) e;
- branch k from the reversal point (e_k, s_k):
  s = s_k + 4 F(gamma(e - e_k) / 2) / gamma(e - e_k) (e - e_k);

both limits at e = e_k are 2 G (e - e_k).  With a = gamma / 1 (backbone)
or gamma / 2 (branch), s = s_k + 2 G / (1 + X(a)) (e - e_k), X(a) =
beta (a / gamma_ref)^s, and ds/dc = 2 F'(a) n n + 2 G / (1 + X(a)) (I - n n),
n = (e - e_k) / |e - e_k|: the gradient of a potential of |e - e_k| that is
convex where F rises (s <= 1), so a branch alone is elastic (it stores,
it does not dissipate).

- Reversal: the distance r = |e - e_k| (k = 0: |e|) stops growing, i.e.
  the motion's component along n turns negative; the old point (e, s) is
  pushed.  A driver step from e_old to e_new is one straight motion tested
  at its start: n_old . (e_new - e_old) < 0.
- Rejoining: when |e - e_k| >= |e_{k-1} - e_k| (k = 1: >= 2 |e_1|, the
  mirrored point -e_1) the two newest points are dropped (k = 1: the
  one), repeated while it applies (masing.Stack.depth_at).  A stack keeps
  masing.DEPTH points and forgets the same way (the oldest closed pair
  above R_1).

In simple shear (only gxy) every c lies on E3, the distance rules are the
1-D sign rules and the stresses the 1-D ones: sxy is the 1-D law of gxy
(to rounding), sxx = syy = szz = 0; so along any fixed deviator direction.
Off a line two features of the rules show (tests/test_deviatoric_law.py
measures them):

- a branch is left wherever its distance is reached, and the stress jumps
  there unless that point is the target itself: at such a point e branch
  k is s_{k-1} + S(rho) (e - e_{k-1}) and the older one s_{k-1} +
  S(|e - e_{k-1}|) (e - e_{k-1}) (S(r) = 2 G / (1 + X(r / sqrt2)), the
  branches' secant, rho = |e_k - e_{k-1}|; for k = 1 the older one is
  the backbone, its secant at |e| against at |e_1|): they agree only at
  e_{k-1} or where |e - e_{k-1}| = rho (k = 1: |e| = |e_1|);
- a path that keeps |e - e_k| constant (a circle about e_k) sits on the
  reversal test's fence: each chord of a polygon inscribed in it moves
  inward, so it reverses at once and then closes one Masing loop a turn;
  a path circling ever so slightly outward never reverses and stays on
  the backbone, dissipating nothing.

For the slab integration to come: ``PlaneMasing.heading()`` is n at the
slab start (the cut theta* = n.D1 / (n.D1 - n.D2)), ``pushed`` the stack
with a turn's point, ``stress_at`` the stress, tangent and depth at strains
reached from a stack (as masing.MasingState.stress_at).
"""

import numpy as np

from vstpetsc.materials.masing import DEPTH, Backbone, push_points

SQ2, SQ6 = np.sqrt(2.0), np.sqrt(6.0)
# (exx, eyy, gxy) -> c and s -> (sxx, syy, sxy, szz): the transpose of
# each other's first three rows (sigma . deps = s . dc + p tr), used for
# the tangent; the stresses themselves are written out term by term so
# that the zeros of simple shear stay exact zeros
TO_DEVIATOR = np.array([[1.0 / SQ2, -1.0 / SQ2, 0.0],
                        [1.0 / SQ6, 1.0 / SQ6, 0.0],
                        [0.0, 0.0, 1.0 / SQ2]])
FROM_DEVIATOR = np.array([[1.0 / SQ2, 1.0 / SQ6, 0.0],
                          [-1.0 / SQ2, 1.0 / SQ6, 0.0],
                          [0.0, 0.0, 1.0 / SQ2],
                          [0.0, -2.0 / SQ6, 0.0]])
VOLUMETRIC = np.outer([1.0, 1.0, 0.0, 1.0], [1.0, 1.0, 0.0])    # d(p I)/d eps per unit K


def deviator(eps):
    """The deviator's coordinates c (..., 3) of strains (..., 3)."""
    exx, eyy, gxy = eps[..., 0], eps[..., 1], eps[..., 2]
    return np.stack(((exx - eyy) / SQ2, (exx + eyy) / SQ6, gxy / SQ2), axis=-1)


def norm(c):
    """|c| over the last axis (exactly |c_i| when one coordinate is nonzero)."""
    return np.sqrt(np.sum(c * c, axis=-1))


def equivalent_strain(eps):
    """gamma(e) = sqrt(2 e:e) = 2 sqrt(J2(e)) of strains (..., 3)."""
    return SQ2 * norm(deviator(eps))


def components(dev, p):
    """(sxx, syy, sxy, szz) (..., 4) from the stress deviator's
    coordinates ``dev`` (..., 3) and the mean stress ``p`` (...)."""
    s1, s2, s3 = dev[..., 0], dev[..., 1], dev[..., 2]
    return np.stack((p + s1 / SQ2 + s2 / SQ6, p - s1 / SQ2 + s2 / SQ6, s3 / SQ2,
                     p - 2.0 * s2 / SQ6), axis=-1)


def equivalent_stress(sigma):
    """tau(s) = sqrt(s:s / 2) of stresses (..., 4)."""
    p = (sigma[..., 0] + sigma[..., 1] + sigma[..., 3]) / 3.0
    ss = (sigma[..., 0] - p) ** 2 + (sigma[..., 1] - p) ** 2 + (sigma[..., 3] - p) ** 2 \
        + 2.0 * sigma[..., 2] ** 2
    return np.sqrt(0.5 * ss)


def tangent_of(dev_tangent, K):
    """d sigma / d eps (..., 4, 3) from ds/dc (..., 3, 3) and the bulk
    moduli K (broadcasting against the leading axes)."""
    # two broadcast matmuls (a three-operand einsum loops naively: it took a
    # third of a yielding dam's slab)
    out = FROM_DEVIATOR @ dev_tangent @ TO_DEVIATOR
    return out + np.asarray(K)[..., None, None] * VOLUMETRIC


def branch(backbone, delta, divisor):
    """(s - s_k, ds/dc) at distances ``delta`` (n, m, 3) from the branch
    origin: divisor 1 on the backbone, 2 on a branch (arrays (n, m))."""
    r = norm(delta)
    a = SQ2 * r / divisor
    bb = backbone
    secant = 2.0 * bb.G / (1.0 + bb.beta * (a / bb.gamma_ref) ** bb.s)
    _, slope = bb.stress_slope(a)
    r2 = r * r
    # n n^T; at r = 0 the direction is undefined but 2 F'(0) = secant(0) = 2 G
    nn = delta[..., :, None] * delta[..., None, :] / np.where(r2 > 0.0, r2, 1.0)[..., None, None]
    eye = np.eye(3)
    tangent = secant[..., None, None] * eye + (2.0 * slope - secant)[..., None, None] * nn
    return secant[..., None] * delta, tangent


class DeviatorStack:
    """Reversal points of every point: deviators ``c`` and stress
    deviators ``s`` (n, DEPTH, 3), depth ``k`` (n,) (masing.Stack's
    vector twin)."""

    def __init__(self, n):
        self.c, self.s = np.zeros((n, DEPTH, 3)), np.zeros((n, DEPTH, 3))
        self.k = np.zeros(n, dtype=np.int64)
        self.rows = np.arange(n)

    def copy(self):
        out = DeviatorStack.__new__(DeviatorStack)
        out.c, out.s, out.k, out.rows = self.c.copy(), self.s.copy(), self.k.copy(), self.rows
        return out

    def push(self, mask, c, s):
        """Push (c, s) (n, 3) on the points of ``mask`` (masing.push_points)."""
        push_points((self.c, self.s), (c, s), self.k, self.rows, mask)

    def top(self, k):
        """(c_k, s_k) (n, m, 3) of depths ``k`` (n, m) (row 0 where k = 0)."""
        idx = np.maximum(k - 1, 0)
        rows = self.rows[:, None]
        return self.c[rows, idx], self.s[rows, idx]

    def depth_at(self, c):
        """The depth in use at deviators ``c`` (n, m, 3) reached from this
        state: drop while |c - c_k| >= |c_{k-1} - c_k| (k = 1: 2 |c_1|)."""
        k = np.repeat(self.k[:, None], c.shape[1], axis=1)
        rows = self.rows[:, None]
        while True:
            ck = self.c[rows, np.maximum(k - 1, 0)]
            older = np.where((k >= 2)[..., None], self.c[rows, np.maximum(k - 2, 0)], -ck)
            passed = (k > 0) & (norm(c - ck) >= norm(older - ck))
            if not passed.any():
                return k
            k = np.where(passed, np.where(k >= 2, k - 2, 0), k)

    def stress(self, backbone, c, k):
        """(s, ds/dc) at deviators ``c`` (n, m, 3) on the branches of
        depth ``k`` (n, m)."""
        ck, sk = self.top(k)
        on_backbone = k == 0
        delta = np.where(on_backbone[..., None], c, c - ck)
        ds, tangent = branch(backbone, delta, np.where(on_backbone, 1.0, 2.0))
        return np.where(on_backbone[..., None], ds, sk + ds), tangent


class PlaneMasing:
    """The hysteretic state of n plane-strain points: strains ``eps``
    (n, 3), stresses ``sigma`` (n, 4), stress deviators ``dev`` (n, 3)
    (what a reversal pushes), a DeviatorStack.  Parameters (n,) each; an
    initial strain ``eps0`` (n, 3) is taken as reached along the backbone."""

    def __init__(self, G, gamma_ref, beta, s, K, eps0=None):
        G = np.asarray(G, dtype=float)
        n = G.size
        full = [np.broadcast_to(np.asarray(v, dtype=float), (n,)).copy()
                for v in (G, gamma_ref, beta, s, K)]
        self.backbone = Backbone(*full[:4])
        self.K = full[4]
        self.stack = DeviatorStack(n)
        self.eps = np.zeros((n, 3)) if eps0 is None else np.array(eps0, dtype=float)
        dev, _ = self.stack.stress(self.backbone, deviator(self.eps)[:, None],
                                   np.zeros((n, 1), dtype=np.int64))
        self.dev = dev[:, 0]
        self.sigma = components(self.dev, self.K * (self.eps[:, 0] + self.eps[:, 1]))

    def branch_stress(self, eps, k, stack=None):
        """(sigma (n, m, 4), d sigma/d eps (n, m, 4, 3)) at strains ``eps``
        (n, m, 3) on the branches of depth ``k`` (n, m) of ``stack``
        (default: this state's), no rejoin test."""
        stack = self.stack if stack is None else stack
        dev, dev_tangent = stack.stress(self.backbone, deviator(eps), k)
        K = self.K[:, None]
        sigma = components(dev, K * (eps[..., 0] + eps[..., 1]))
        return sigma, tangent_of(dev_tangent, K)

    def stress_at(self, eps, stack=None):
        """(sigma, d sigma/d eps, depth) at strains ``eps`` (n, m, 3)
        reached from ``stack`` (default: this state's) without a turn: the
        rejoin rule, then the branch in use."""
        stack = self.stack if stack is None else stack
        k = stack.depth_at(deviator(eps))
        sigma, tangent = self.branch_stress(eps, k, stack)
        return sigma, tangent, k

    def heading(self):
        """n = (e - e_k) / |e - e_k| (k = 0: e / |e|) (n, 3); zero where
        the point sits on its newest reversal point (or at the origin)."""
        c = deviator(self.eps)
        ck, _ = self.stack.top(self.stack.k[:, None])
        away = np.where((self.stack.k > 0)[:, None], c - ck[:, 0], c)
        r = norm(away)
        return away / np.where(r > 0.0, r, 1.0)[:, None]

    def turns(self, d_eps):
        """Where a motion by ``d_eps`` (n, 3) from this state reverses:
        its deviator's component along ``heading()`` is negative."""
        return np.sum(self.heading() * deviator(d_eps), axis=-1) < 0.0

    def pushed(self, mask):
        """The stack with this state's point pushed where ``mask`` (this
        state's own stack when nothing turns)."""
        if not mask.any():
            return self.stack
        stack = self.stack.copy()
        stack.push(mask, deviator(self.eps), self.dev)
        return stack

    def step(self, eps_new):
        """Move every point straight to ``eps_new`` (n, 3): the reversal
        test at the start, the rejoin rule at the end; its stresses (n, 4)."""
        stack = self.pushed(self.turns(eps_new - self.eps))
        eps = np.asarray(eps_new, dtype=float)[:, None]
        k = stack.depth_at(deviator(eps))
        dev, _ = stack.stress(self.backbone, deviator(eps), k)
        stack = stack.copy() if stack is self.stack else stack
        stack.k = k[:, 0]
        self.stack, self.eps, self.dev = stack, eps[:, 0].copy(), dev[:, 0]
        self.sigma = components(self.dev, self.K * (self.eps[:, 0] + self.eps[:, 1]))
        return self.sigma

    def drive(self, increments):
        """Strain increments (n, m, 3), each one straight step; the
        stresses (n, m, 4) after each.  The strains are the running sums
        from the present ones (added in order)."""
        path = np.cumsum(np.concatenate([self.eps[:, None], increments], axis=1), axis=1)
        out = np.empty(increments.shape[:2] + (4,))
        for j in range(increments.shape[1]):
            out[:, j] = self.step(path[:, j + 1])
        return out

    def tangent(self):
        """d sigma / d eps (n, 4, 3) of the branch in use at the present
        strains (its continuation: a reversal would start at 2 G)."""
        _, tangent = self.branch_stress(self.eps[:, None], self.stack.k[:, None])
        return tangent[:, 0]

    @property
    def strain_measure(self):
        """The equivalent shear strain gamma(e) (n,)."""
        return equivalent_strain(self.eps)
