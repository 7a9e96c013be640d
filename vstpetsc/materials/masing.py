"""Extended Masing rules on a backbone, for many elements at once, and the
exact-in-space, Gauss-in-time slab integrals of the stress they give
(docs/nonlinear-soil.md).  Pure numpy.

State of an element: its strain and stress at the slab start, the
direction of its last strain motion (+1, -1; 0 before any), and a stack of
reversal points R_1 .. R_k (strain, stress).  With k = 0 the stress is on
the backbone F; otherwise on the branch from R_k,

    tau = tau_k + 2 F((gamma - gamma_k) / 2),

which heads for R_{k-1} (for k = 1: the mirrored point -R_1, on the
backbone).  When the strain passes that target the branch has met the
older one: R_k and R_{k-1} are dropped (k = 1: back on the backbone).
Stress is continuous through every such step, only its slope jumps.

Inside a slab the strain of an element is quadratic in theta,
gamma(theta) = gamma_n + (theta - theta^2/2) D1 + (theta^2/2) D2 with
D_b = dt (v_right^b - v_left^b) / h, so its rate changes sign at most once,
at theta* = D1 / (D1 - D2).  The slab is cut there (clipped to 0 or 1 when
it does not turn: one piece) and each piece gets a Gauss rule; a reversal at the slab start
(the velocity jumps between slabs) or at theta* pushes a point.
"""

import numpy as np

DEPTH = 40                    # reversal points an element keeps
GAUSS_POINTS = 3              # per piece: exact for degree 5

_XG, _WG = np.polynomial.legendre.leggauss(GAUSS_POINTS)
XG, WG = 0.5 * (_XG + 1.0), 0.5 * _WG     # on [0, 1]


class Backbone:
    """tau = F(gamma) per element; ``slope`` its derivative.  Arrays
    broadcast against (ne,) parameters put in columns."""

    def __init__(self, G, gamma_ref, beta, s):
        self.G, self.gamma_ref = G[:, None], gamma_ref[:, None]
        self.beta, self.s = beta[:, None], s[:, None]

    def _x(self, g):
        return self.beta * (np.abs(g) / self.gamma_ref) ** self.s

    def stress(self, g):
        return self.G * g / (1.0 + self._x(g))

    def stress_slope(self, g):
        """(F(g), F'(g))."""
        bx = self._x(g)
        den = 1.0 + bx
        return self.G * g / den, self.G * (1.0 + (1.0 - self.s) * bx) / (den * den)


def push_points(stacks, values, k, rows, mask):
    """Push ``values`` (one array per stack, a row per element) on the
    ``stacks`` (n, DEPTH, ...) at depths ``k`` (n,) of the elements of
    ``mask``, in place (k too).  A full stack forgets its oldest closed pair
    above R_1 (the branch in use is kept, so the stress stays continuous;
    only that old loop's memory is lost).  Shared by the 1-D stack and
    the plane-strain deviators' (vstpetsc.materials.deviatoric)."""
    full = mask & (k >= DEPTH)
    if full.any():
        for arr in stacks:
            arr[full, 1:DEPTH - 2] = arr[full, 3:DEPTH]
        k[full] -= 2
    r = rows[mask]
    for arr, value in zip(stacks, values):
        arr[r, k[mask]] = value[mask]
    k[mask] += 1


class Stack:
    """Reversal points of every element: strains ``g`` and stresses ``t``
    (ne, DEPTH), depth ``k`` (ne,)."""

    def __init__(self, n):
        self.g, self.t = np.zeros((n, DEPTH)), np.zeros((n, DEPTH))
        self.k = np.zeros(n, dtype=np.int64)
        self.rows = np.arange(n)

    def copy(self):
        out = Stack.__new__(Stack)
        out.g, out.t, out.k, out.rows = self.g.copy(), self.t.copy(), self.k.copy(), self.rows
        return out

    def push(self, mask, g, t):
        """Push (g, t) on the elements of ``mask`` (push_points)."""
        push_points((self.g, self.t), (g, t), self.k, self.rows, mask)

    def depth_at(self, gamma, d):
        """The depth in use at strains ``gamma`` (ne, m) reached by a
        monotone motion in direction ``d`` (ne,) from this state: pop while
        the strain has passed the branch's target."""
        k = np.repeat(self.k[:, None], gamma.shape[1], axis=1)
        rows = self.rows[:, None]
        dd = d[:, None]
        while True:
            target = np.where(k >= 2, self.g[rows, np.maximum(k - 2, 0)], -self.g[rows, 0])
            passed = (k > 0) & (dd * (gamma - target) >= 0.0)
            if not passed.any():
                return k
            k = np.where(passed, np.where(k >= 2, k - 2, 0), k)

    def stress(self, backbone, gamma, k):
        """(stress, slope) at strains ``gamma`` (ne, m) on the branches of
        depth ``k`` (ne, m)."""
        rows = self.rows[:, None]
        top = np.maximum(k - 1, 0)
        on_backbone = k == 0
        gr, tr = self.g[rows, top], self.t[rows, top]
        arg = np.where(on_backbone, gamma, 0.5 * (gamma - gr))
        f, slope = backbone.stress_slope(arg)
        return np.where(on_backbone, f, tr + 2.0 * f), slope


class MasingState:
    """The hysteretic state of ``n`` elements on ``backbone``."""

    def __init__(self, backbone, gamma0):
        n = gamma0.size
        self.backbone = backbone
        self.stack = Stack(n)
        self.gamma = gamma0.astype(float).copy()
        # an initial strain was reached by loading from zero
        self.direction = np.sign(self.gamma)
        self.tau = backbone.stress(self.gamma[:, None])[:, 0]

    def stress_at(self, gamma, d, stack=None):
        """(stress, slope, depth) at strains (ne, m) reached monotonically
        in direction ``d`` from ``stack`` (default: the slab start's)."""
        stack = self.stack if stack is None else stack
        k = stack.depth_at(gamma, d)
        tau, slope = stack.stress(self.backbone, gamma, k)
        return tau, slope, k


def strain(gn, D1, D2, theta):
    """gamma(theta) of the slab (theta (ne, m))."""
    t2 = 0.5 * theta * theta
    return gn[:, None] + (theta - t2) * D1[:, None] + t2 * D2[:, None]


class SlabPath:
    """The strain path of every element through one slab for given D1, D2:
    its pieces, their Gauss points and the stacks they start from."""

    def __init__(self, state, D1, D2):
        self.state, self.D1, self.D2 = state, D1, D2
        gn = state.gamma
        self.reverses = D1 * D2 < 0.0
        # theta* where the rate would vanish, clipped: a slab that does not
        # turn is one piece (the other empty), and the pieces move
        # continuously as a turn enters or leaves the slab (a fixed cut
        # there made the Gauss sums jump by their quadrature error, and
        # Newton cycled between the two sides)
        diff = D1 - D2
        self.cut = np.clip(D1 / np.where(diff != 0.0, diff, 1.0), 0.0, 1.0)
        self.cut[diff == 0.0] = 1.0
        rate = np.where(D1 != 0.0, D1, D2)
        self.d1 = np.where(rate != 0.0, np.sign(rate), state.direction)
        self.d2 = np.where(self.reverses, -self.d1, self.d1)
        # a reversal at the slab start (the velocity jumps between slabs)
        turned = (state.direction != 0.0) & (self.d1 != state.direction)
        self.start = state.stack
        if turned.any():
            self.start = state.stack.copy()
            self.start.push(turned, gn, state.tau)
        c = self.cut[:, None]
        self.theta = (c * XG, c + (1.0 - c) * XG)
        self.weight = (c * WG, (1.0 - c) * WG)
        # the turning point theta*: its stress and slope on the first piece
        gc = strain(gn, D1, D2, c)
        tc, self.slope_c, kc = state.stress_at(gc, self.d1, self.start)
        self.second = self.start
        if self.reverses.any():
            self.second = self.start.copy()
            self.second.k = np.where(self.reverses, kc[:, 0], self.start.k)
            self.second.push(self.reverses, gc[:, 0], tc[:, 0])

    def pieces(self):
        """((theta, weight, gamma, stress, slope, depth) of each piece)."""
        out = []
        for j, (stack, d) in enumerate(((self.start, self.d1), (self.second, self.d2))):
            gamma = strain(self.state.gamma, self.D1, self.D2, self.theta[j])
            tau, slope, k = self.state.stress_at(gamma, d, stack)
            out.append((self.theta[j], self.weight[j], gamma, tau, slope, k))
        return out

    def end(self):
        """(strain, stress, stack, direction) at the slab end."""
        g1 = strain(self.state.gamma, self.D1, self.D2, np.ones((self.D1.size, 1)))
        k = self.second.depth_at(g1, self.d2)
        tau, _ = self.second.stress(self.state.backbone, g1, k)
        stack = self.second.copy() if self.second is self.state.stack else self.second
        stack.k = k[:, 0]
        return g1[:, 0], tau[:, 0], stack, self.d2


def slab_integrals(state, D1, D2, area, ke_h, dt, tangent=True):
    """The slab's correction integrals of every element,

        Q_a = dt int_0^1 T_a(theta) c(theta) dtheta,  c = A tau - (E A / h) h gamma,

    (the nonlinear stress beyond the linear K already in the slab matrix),
    with T_1 = 1 - theta, T_2 = theta, and their derivatives dQ_a/dD_b
    (ne, 2, 2): the derivative of these Gauss sums, so that Newton
    converges quadratically and a finite-difference Jacobian agrees.

    Where the strain turns inside the slab two more terms enter.  The
    turning point's strain gamma* = gamma(theta*) moves with D (the rate
    vanishes there, so only through gamma's own dependence), and the branch
    after it, tau = tau* + 2 F((gamma - gamma*)/2), feels d tau / d gamma*
    = F'_before(gamma*) - F'(branch).  And the cut theta* = D1 / (D1 - D2)
    moves the Gauss points of both pieces: the exact integral would not
    notice (the integrand is continuous there), the Gauss sums do, by the
    quadrature error's derivative."""
    path = SlabPath(state, D1, D2)
    n = D1.size
    Q = np.zeros((n, 2))
    dQ = np.zeros((n, 2, 2)) if tangent else None
    dQ_cut = np.zeros((n, 2))
    A, kh = area[:, None], ke_h[:, None]
    ic = (path.cut - 0.5 * path.cut ** 2, 0.5 * path.cut ** 2)
    turning = path.reverses.any()
    for j, (theta, w, gamma, tau, slope, k) in enumerate(path.pieces()):
        c = A * tau - kh * gamma
        T = (1.0 - theta, theta)
        for a in range(2):
            Q[:, a] += np.sum(w * T[a] * c, axis=1)
        if not tangent:
            continue
        dc = A * slope - kh
        ib = (theta - 0.5 * theta * theta, 0.5 * theta * theta)
        new_branch = None
        if j == 1 and turning:
            new_branch = (path.reverses[:, None] & (k == path.second.k[:, None])) * \
                (A * (path.slope_c - slope))
        for a in range(2):
            for b in range(2):
                integrand = dc * ib[b]
                if new_branch is not None:
                    integrand = integrand + new_branch * ic[b][:, None]
                dQ[:, a, b] += np.sum(w * T[a] * integrand, axis=1)
        if turning:
            _cut_terms(dQ_cut, j, path, theta, c, dc, T)
    Q *= dt
    if tangent:
        if turning:
            den = np.where(path.reverses, (D1 - D2) ** 2, 1.0)
            dcut = (np.where(path.reverses, -D2 / den, 0.0), np.where(path.reverses, D1 / den, 0.0))
            for b in range(2):
                dQ[:, :, b] += dQ_cut * dcut[b][:, None]
        dQ *= dt
    return Q, dQ, path


def _cut_terms(out, piece, path, theta, c, dc, T):
    """Add d/d theta* of piece ``piece``'s Gauss sums (per unit dt) to
    ``out`` (ne, 2): piece 1 has points theta* x_g and weights theta* w_g,
    piece 2 theta* + (1 - theta*) x_g and (1 - theta*) w_g."""
    rate = (1.0 - theta) * path.D1[:, None] + theta * path.D2[:, None]
    dc_dtheta = dc * rate
    cut = path.cut[:, None]
    moves, scale = (XG, 1.0) if piece == 0 else (1.0 - XG, -1.0)
    length = cut if piece == 0 else 1.0 - cut
    for a, sign in ((0, -1.0), (1, 1.0)):
        df = sign * c + T[a] * dc_dtheta
        out[:, a] += np.sum(WG * (scale * T[a] * c + length * moves * df), axis=1)
