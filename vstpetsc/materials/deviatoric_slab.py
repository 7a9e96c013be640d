"""The slab integrals of the plane-strain MKZ-Masing law
(:mod:`vstpetsc.materials.deviatoric`) for n material points at once: the
2-D twin of masing.SlabPath / masing.slab_integrals (issue 46, step 2;
docs/nonlinear-soil.md section 7).  Pure numpy.

Inside a slab the strain of a point is quadratic in theta,

    eps(theta) = eps_n + (theta - theta^2/2) D1 + (theta^2/2) D2,

D_b = dt (B v^b) (n, 3) each (exx, eyy, gxy).  The correction integrand
is c(theta) = sigma(eps(theta)) - C_el eps(theta), sigma's in-plane
components (sxx, syy, sxy) beyond the linear elastic stress already in the
slab matrix (C_el of lam = K - 2G/3, mu = G), and

    Q_a = dt int_0^1 T_a(theta) c(theta) dtheta   (n, 2, 3),

T_1 = 1 - theta, T_2 = theta, with dQ_a/dD_b (n, 2, 3, 2, 3): the
derivative of the Gauss sums.  The element forms B^T Q w_area.

The cut.  n0 is the slab start's heading: PlaneMasing.heading(), where the
point sits on its newest reversal point the last motion's direction (the
``motion`` a committed slab returns), and for a point that has never moved
the direction of its first rate (dD1, else dD2: a virgin point cannot
reverse at its start, as in 1-D).  The rate's component along n0 is
linear in theta, r(theta) = (1 - theta) n0.dD1 + theta n0.dD2 (dD_b the
deviator coordinates of D_b):

- the path reverses at the slab start when r's first nonzero value
  (n0.dD1, else n0.dD2) is negative: (e_n, s_n) is pushed;
- it turns inside when (n0.dD1)(n0.dD2) < 0, at theta* = n0.dD1 /
  (n0.dD1 - n0.dD2), and the turn point (e*, s*) on the first piece is
  pushed for the second piece; otherwise theta* is clipped into [0, 1]
  (one piece, the other empty) so the pieces move continuously as a turn
  enters or leaves the slab (masing.SlabPath);
- each piece GAUSS_POINTS Gauss points (masing.XG, WG), the rejoin test
  (DeviatorStack.depth_at) at each from the piece's stack.

n0 is fixed within the slab: a path that bends turns by the distance rule
(|e - e_k| stops growing) at a different theta than r's zero; that is the
discretisation's choice, exact along any straight deviator line (simple
shear gives masing.SlabPath's cut, pieces and pushes).

The tangent: the Gauss sums' derivative with

(a) the turn point's strain e* = e(theta*) moving with D, both through the
    strain's own dependence i_b(theta*) and through theta* (in 2-D the
    rate there is not zero, only its n0 component); the new branch's
    stress s* + S(e - e*) changes by (T_before(e*) - T_branch(e)) de*;
(b) theta* moving the Gauss points of both pieces (masing._cut_terms);
(c) n0 is fixed by the slab start state (for a virgin point n0 =
    dD1/|dD1| moves with D1, and that derivative is included).

Q is only piecewise smooth: where a Gauss point or the turn point crosses a
rejoin (in 2-D the stress may jump there, deviatoric.py), where the turn
enters or leaves the slab (theta* clipped) and where a start reversal
switches on.
"""

import numpy as np

from vstpetsc.materials import deviatoric as dv
from vstpetsc.materials.masing import WG, XG


def strain(eps_n, D1, D2, theta):
    """eps(theta) (n, m, 3) at theta (n, m)."""
    t2 = (0.5 * theta * theta)[..., None]
    return eps_n[:, None] + (theta[..., None] - t2) * D1[:, None] + t2 * D2[:, None]


def rate(D1, D2, theta):
    """d eps / d theta (n, m, 3) at theta (n, m)."""
    th = theta[..., None]
    return (1.0 - th) * D1[:, None] + th * D2[:, None]


def elastic_matrix(G, K):
    """C_el (n, 3, 3) of plane strain: (sxx, syy, sxy) = C_el (exx, eyy, gxy)."""
    lam = K - 2.0 * G / 3.0
    C = np.zeros((G.size, 3, 3))
    C[:, :2, :2] = lam[:, None, None]
    C[:, 0, 0] += 2.0 * G
    C[:, 1, 1] += 2.0 * G
    C[:, 2, 2] = G
    return C


def evaluate(law, stack, eps, k=None):
    """At strains ``eps`` (n, m, 3) reached from ``stack`` without a turn
    (the rejoin rule, then the branch in use; or the given depths ``k``
    (n, m), frozen): in-plane stresses (n, m, 3), their tangent
    d sigma / d eps (n, m, 3, 3), the stress deviator (n, m, 3) and the
    depth (n, m)."""
    c = dv.deviator(eps)
    k = stack.depth_at(c) if k is None else k
    s, ds = stack.stress(law.backbone, c, k)
    K = law.K[:, None]
    sigma = dv.components(s, K * (eps[..., 0] + eps[..., 1]))
    return sigma[..., :3], dv.tangent_of(ds, K)[..., :3, :], s, k


def unit(v):
    """v / |v| over the last axis (zero where v is)."""
    r = dv.norm(v)
    return v / np.where(r > 0.0, r, 1.0)[..., None]


def start_heading(law, motion=None):
    """n0 (n, 3) of the slab start: law.heading(), where zero the last
    motion's direction ``motion`` (n, 3) (zero where unknown)."""
    n0 = law.heading()
    if motion is not None:
        still = ~n0.any(axis=1)
        n0[still] = motion[still]
    return n0


class Decisions:
    """A slab path's discrete choices per point: the start reversal
    ``turned``, the inside turn ``reverses``, the clipped cut ``cut`` (0 or
    1 where it does not turn inside), the depths of the turn point ``kc``
    (n, 1) and of each piece's Gauss points ``k`` (two (n, m)).  Given to
    a SlabPath they are kept whatever D (the rejoin tests and the turn
    tests not made): Q is then smooth in D (docs/nonlinear-soil.md
    section 8, "The zone's Newton")."""

    def __init__(self, turned, reverses, cut, kc, k):
        self.turned, self.reverses, self.cut, self.kc, self.k = turned, reverses, cut, kc, k

    def differ(self, other):
        """Per point (n,): where ``other``'s choices are not these."""
        out = (self.turned != other.turned) | (self.reverses != other.reverses)
        out |= ~self.reverses & (self.cut != other.cut)
        out |= (self.kc != other.kc).any(axis=1)
        for mine, theirs in zip(self.k, other.k):
            out |= (mine != theirs).any(axis=1)
        return out

    def merged(self, other, where):
        """These choices with ``other``'s at the points ``where`` (n,)."""
        pick = [lambda a, b: np.where(where, b, a),
                lambda a, b: np.where(where[:, None], b, a)]
        return Decisions(pick[0](self.turned, other.turned),
                         pick[0](self.reverses, other.reverses), pick[0](self.cut, other.cut),
                         pick[1](self.kc, other.kc),
                         [pick[1](a, b) for a, b in zip(self.k, other.k)])


class SlabPath:
    """The strain path of every point through one slab for D1, D2 (n, 3):
    its cut, pieces, Gauss points and the stacks they start from (the 2-D
    masing.SlabPath).  ``law`` is the slab start's PlaneMasing (not
    changed), ``motion`` the last motion's direction (what commit returned;
    None: law.heading() alone); ``frozen`` Decisions to keep (None: the
    rules decide)."""

    def __init__(self, law, D1, D2, motion=None, frozen=None):
        self.law, self.D1, self.D2 = law, D1, D2
        dD1, dD2 = dv.deviator(D1), dv.deviator(D2)
        self.n0, self.virgin = slab_heading(law, dD1, dD2, motion)
        n0 = self.n0
        a, b = np.sum(n0 * dD1, axis=1), np.sum(n0 * dD2, axis=1)
        self.a, self.b = a, b
        self.frozen = frozen
        self._cut_and_flags(a, b, frozen)
        self.start = law.pushed(self.turned)
        c = self.cut[:, None]
        self.theta = (c * XG, c + (1.0 - c) * XG)
        self.weight = (c * WG, (1.0 - c) * WG)
        # the turn point theta*: its strain, stress and tangent on the first piece
        self.eps_c = strain(law.eps, D1, D2, c)
        _, self.tangent_c, s_c, kc = evaluate(law, self.start, self.eps_c,
                                              None if frozen is None else frozen.kc)
        self.kc, self.depths = kc, [None, None]
        self.second = second_stack(self.start, self.reverses, kc[:, 0], self.eps_c[:, 0],
                                   s_c[:, 0])
        self.motion = slab_motion(dD1, dD2, n0)

    def _cut_and_flags(self, a, b, frozen):
        """turned, reverses, cut; ``inside``: where the cut moves with D
        (a frozen inside turn whose a, b no longer change sign is clipped
        and fixed)."""
        diff = a - b
        self.cut = np.clip(a / np.where(diff != 0.0, diff, 1.0), 0.0, 1.0)
        self.cut[diff == 0.0] = 1.0
        if frozen is None:
            self.turned = np.where(a != 0.0, a, b) < 0.0
            self.reverses = self.inside = a * b < 0.0
            return
        self.turned, self.reverses = frozen.turned, frozen.reverses
        self.inside = self.reverses & (a * b < 0.0)
        self.cut = np.where(self.reverses, self.cut, frozen.cut)

    def decisions(self):
        """The Decisions this path took (after pieces())."""
        return Decisions(self.turned, self.reverses, self.cut, self.kc, list(self.depths))

    def pieces(self):
        """((theta, weight, eps, sigma, tangent, depth) of each piece):
        in-plane stresses and their tangent (evaluate)."""
        out = []
        for j, stack in enumerate((self.start, self.second)):
            eps = strain(self.law.eps, self.D1, self.D2, self.theta[j])
            sigma, tangent, _, k = evaluate(self.law, stack, eps,
                                            None if self.frozen is None else self.frozen.k[j])
            self.depths[j] = k
            out.append((self.theta[j], self.weight[j], eps, sigma, tangent, k))
        return out

    def cut_derivative(self):
        """d theta* / d D_b (n, 2, 3), zero where the path does not turn
        inside (theta* clipped, or no turn)."""
        a, b, n0 = self.a, self.b, self.n0
        rev = self.inside
        den = np.where(rev, (a - b) ** 2, 1.0)
        grad = n0 @ dv.TO_DEVIATOR                       # d(n0 . dD)/dD, n0 fixed
        db1 = np.zeros_like(grad)
        if self.virgin.any():
            # n0 = dD1 / |dD1|: a = |dD1| (same gradient), b = n0 . dD2 moves too
            dD1, dD2 = dv.deviator(self.D1), dv.deviator(self.D2)
            r = np.where(self.virgin, dv.norm(dD1), 1.0)[:, None]
            across = (dD2 - np.sum(n0 * dD2, axis=1)[:, None] * n0) / r
            db1 = np.where(self.virgin[:, None], across @ dv.TO_DEVIATOR, 0.0)
        by_a, by_b = np.where(rev, -b / den, 0.0)[:, None], np.where(rev, a / den, 0.0)[:, None]
        d1 = by_a * grad + by_b * db1
        d2 = by_b * grad
        return np.stack((d1, d2), axis=1)

    def turn_strain_derivative(self, dcut):
        """d eps* / d D_b (n, 3, 2, 3): eps* = eps(theta*), theta* moving."""
        c = self.cut[:, None]
        ib = np.stack((c - 0.5 * c * c, 0.5 * c * c), axis=-1)[:, 0]     # (n, 2)
        out = ib[:, None, :, None] * np.eye(3)[None, :, None, :]
        return out + rate(self.D1, self.D2, c)[:, 0, :, None, None] * dcut[:, None]

    def commit(self):
        """Make the slab end the law's state; the motion (n, 3) to pass to
        the next slab."""
        return commit_end(self.law, self.second, self.D1, self.D2, self.motion)


def slab_heading(law, dD1, dD2, motion):
    """(n0 (n, 3), virgin (n,)) of a slab with deviator increments dD1,
    dD2: the slab start's heading, where the point never moved its first
    rate's direction (dD1, else dD2; ``virgin`` where that was dD1: n0
    then moves with D1, and a virgin point cannot reverse at its start)."""
    n0 = start_heading(law, motion)
    still = ~n0.any(axis=1)
    virgin = still & dD1.any(axis=1)
    n0[still] = unit(np.where(virgin[:, None], dD1, dD2))[still]
    return n0, virgin


def slab_motion(dD1, dD2, n0):
    """The last motion's direction (n, 3) at the slab end: dD2's, else
    dD1's, else n0."""
    moved = [unit(d) for d in (dD2, dD1)]
    return np.where(dD2.any(axis=1)[:, None], moved[0],
                    np.where(dD1.any(axis=1)[:, None], moved[1], n0))


def second_stack(start, reverses, kc, eps_c, s_c):
    """The stack of the path's second piece: ``start`` at the turn point's
    depth ``kc`` (n,) with the turn point (strain ``eps_c``, stress
    deviator ``s_c``, (n, 3)) pushed where it ``reverses`` (``start``
    itself where nothing does)."""
    if not reverses.any():
        return start
    second = start.copy()
    second.k = np.where(reverses, kc, start.k)
    second.push(reverses, dv.deviator(eps_c), s_c)
    return second


def path_end(law, second, D1, D2):
    """(strains (n, 3), stresses (n, 4), stress deviators (n, 3), stack)
    at the slab end of the path whose second piece starts from ``second``:
    the next slab's start."""
    eps1 = strain(law.eps, D1, D2, np.ones((D1.shape[0], 1)))
    c1 = dv.deviator(eps1)
    k = second.depth_at(c1)
    dev, _ = second.stress(law.backbone, c1, k)
    stack = second.copy() if second is law.stack else second
    stack.k = k[:, 0]
    sigma = dv.components(dev[:, 0], law.K * (eps1[:, 0, 0] + eps1[:, 0, 1]))
    return eps1[:, 0], sigma, dev[:, 0], stack


def commit_end(law, second, D1, D2, motion):
    """Make the slab end (path_end) ``law``'s state; the ``motion`` (n, 3)
    to pass to the next slab (a copy)."""
    law.eps, law.sigma, law.dev, law.stack = path_end(law, second, D1, D2)
    return motion.copy()


def slab_integrals(law, D1, D2, dt, motion=None, tangent=True, frozen=None):
    """(Q (n, 2, 3), dQ/dD (n, 2, 3, 2, 3) or None, the SlabPath) of the
    slab from ``law``'s state for strain increments D1, D2 (n, 3): the
    correction integrals Q_a = dt int T_a (sigma - C_el eps) dtheta by the
    Gauss rule of each piece and the derivative of those sums (the module's
    docstring: terms (a), (b), (c)); ``frozen`` Decisions to keep."""
    path = SlabPath(law, D1, D2, motion, frozen)
    n = D1.shape[0]
    C = elastic_matrix(law.backbone.G[:, 0], law.K)
    Q = np.zeros((n, 2, 3))
    dQ = np.zeros((n, 2, 3, 2, 3)) if tangent else None
    turning = path.reverses.any()
    if tangent and turning:
        dcut = path.cut_derivative()
        de_c = path.turn_strain_derivative(dcut)
        d_cut_sums = np.zeros((n, 2, 3))
    for j, (theta, w, eps, sigma, tan, k) in enumerate(path.pieces()):
        c = sigma - np.einsum("nij,nmj->nmi", C, eps)
        T = np.stack((1.0 - theta, theta), axis=-1)
        # (w T) first: the multi-operand einsums contract pairwise in this
        # order instead of one naive loop over every index (they took most
        # of a yielding dam's slab)
        wT = w[:, :, None] * T
        Q += np.einsum("nma,nmi->nai", wT, c)
        if not tangent:
            continue
        dc = tan - C[:, None]
        ib = np.stack((theta - 0.5 * theta * theta, 0.5 * theta * theta), axis=-1)
        dQ += np.einsum("nma,nmijb->naibj", wT, dc[..., None] * ib[:, :, None, None, :])
        if not turning:
            continue
        if j == 1:
            # the new branch s* + S(e - e*): d/d e* = T_before(e*) - T_branch(e)
            on = path.reverses[:, None] & (k == path.second.k[:, None])
            jump = (path.tangent_c - tan) * on[..., None, None]
            dQ += np.einsum("nail,nlbj->naibj", np.einsum("nma,nmil->nail", wT, jump), de_c)
        d_cut_sums += cut_terms(j, path, theta, c, dc, T)
    Q *= dt
    if tangent:
        if turning:
            dQ += np.einsum("nai,nbj->naibj", d_cut_sums, dcut)
        dQ *= dt
    return Q, dQ, path


def cut_terms(piece, path, theta, c, dc, T):
    """d/d theta* (n, 2, 3) of piece ``piece``'s Gauss sums (per unit dt)
    at fixed e*: piece 1 has points theta* x_g and weights theta* w_g,
    piece 2 theta* + (1 - theta*) x_g and (1 - theta*) w_g
    (masing._cut_terms)."""
    dc_dtheta = np.einsum("nmij,nmj->nmi", dc, rate(path.D1, path.D2, theta))
    cut = path.cut[:, None]
    moves, scale = (XG, 1.0) if piece == 0 else (1.0 - XG, -1.0)
    length = (cut if piece == 0 else 1.0 - cut) * moves
    out = np.empty((theta.shape[0], 2, 3))
    for a, sign in ((0, -1.0), (1, 1.0)):
        Ta = T[..., a, None]
        df = sign * c + Ta * dc_dtheta
        out[:, a] = np.sum(WG[:, None] * (scale * Ta * c + length[..., None] * df), axis=1)
    return out
