"""The slab integrals of the plane-strain MKZ-Masing law (issue 46, step 2:
vstpetsc/materials/deviatoric_slab.py; docs/nonlinear-soil.md section 7):

1. simple shear (D only in gxy): Q, dQ/dD and the slab-end states are the
   1-D masing.slab_integrals of gamma = gxy (area 1, ke_h = G: c = tau -
   G gamma) through random slab sequences with reversals at slab starts
   and inside slabs and rejoins; the other components zero;
2. the tangent against central differences of Q in each of the 6
   components of (D1, D2), from random mixed states (and from rest), for
   slabs that load, reverse at the start and turn inside;
3. a slab that does not turn: Q against a 2000-point Gauss-Legendre rule of
   T_a c(theta) with the stress of PlaneMasing.stress_at, the error's
   order in the slab's size;
4. the elastic limit: tiny strains give Q ~ 0 beside dt C_el eps.

Run with -s to see the measured figures.
"""

import numpy as np

from vstpetsc.materials import deviatoric as dv
from vstpetsc.materials import deviatoric_slab as ds
from vstpetsc.materials import masing

DT = 0.01


def random_laws(rng, n):
    """n points with their own parameters: (G, gamma_ref, beta, s, K)."""
    G = rng.uniform(0.5e6, 2.0e6, n)
    return (G, rng.uniform(2e-4, 1e-3, n), rng.uniform(0.5, 1.5, n), rng.uniform(0.7, 1.0, n),
            G * rng.uniform(1.0, 5.0, n))


def in_gxy(D):
    """Strain increments (n, 3) with only gxy = D."""
    out = np.zeros((D.size, 3))
    out[:, 2] = D
    return out


def wander(rng, law, slabs, scale, idle=None):
    """Commit ``slabs`` random mixed slabs (D1, D2 (n, 3) of ``scale``
    gamma_ref, the rate turning inside about every other slab); points
    with ``idle`` (n,) <= the slab number stay put.  The motion to pass on."""
    n = law.K.size
    gr = law.backbone.gamma_ref
    motion = None
    for j in range(slabs):
        D1 = rng.normal(size=(n, 3)) * scale * gr
        D2 = D1 + rng.normal(size=(n, 3)) * scale * gr
        if idle is not None:
            D1[idle <= j], D2[idle <= j] = 0.0, 0.0
        _, _, path = ds.slab_integrals(law, D1, D2, DT, motion, tangent=False)
        motion = path.commit()
    return motion


# ---- 1. simple shear is the 1-D slab ------------------------------------------

def shear_slabs(rng, n, m, gr):
    """m slabs of (D1, D2) (n,) in gxy: random amplitudes up to 3 gamma_ref,
    every third slab starting against the last one's end rate (a reversal
    at its start), and about half turning inside; some slabs start at rest
    (D1 = 0) and some stand still."""
    D1 = rng.uniform(-1.0, 1.0, (m, n)) * rng.uniform(0.05, 3.0, (m, n)) * gr
    D2 = rng.uniform(-1.0, 1.0, (m, n)) * rng.uniform(0.05, 3.0, (m, n)) * gr
    for j in range(1, m, 3):
        D1[j] = -np.sign(D2[j - 1]) * np.abs(D1[j])
    D1[rng.random((m, n)) < 0.03] = 0.0          # the rate starts at zero: D2 decides
    still = rng.random((m, n)) < 0.03
    D1[still], D2[still] = 0.0, 0.0
    return D1, D2


def test_simple_shear_is_the_1d_slab(rng):
    """Q (gxy) equals masing.slab_integrals to 1e-12 of the point's largest
    |Q|, dQ to 1e-12 of dt G (the linear slab tangent's scale; against the
    point's largest entry of dQ the figure is larger where theta* sits
    near a slab end: there d theta*/dD ~ 1/|D| multiplies the rounding
    of the cut's sums in both codes); the other components of Q and the
    couplings of gxy with exx, eyy exact zeros; the slab ends the same
    states (strain bit for bit, stress to rounding, depths, stacks,
    directions)."""
    n, m = 60, 120
    params = random_laws(rng, n)
    G, gr = params[0], params[1]
    law = dv.PlaneMasing(*params)
    state = masing.MasingState(masing.Backbone(*params[:4]), np.zeros(n))
    D1s, D2s = shear_slabs(rng, n, m, gr)
    motion, worst, counts = None, np.zeros(3), np.zeros(3, dtype=int)
    Q_peak = np.zeros(n)
    rows = []
    for D1, D2 in zip(D1s, D2s):
        Q1, dQ1, p1 = masing.slab_integrals(state, D1, D2, np.ones(n), G, DT)
        Q2, dQ2, p2 = ds.slab_integrals(law, in_gxy(D1), in_gxy(D2), DT, motion)
        assert np.array_equal(p2.turned, (state.direction != 0.0) & (p1.d1 != state.direction))
        assert np.array_equal(p2.reverses, p1.reverses)
        assert not Q2[:, :, :2].any() and not dQ2[:, :, 2, :, :2].any() \
            and not dQ2[:, :, :2, :, 2].any()
        Q_peak = np.maximum(Q_peak, np.abs(Q1).max(axis=1))
        rows.append(np.abs(Q2[:, :, 2] - Q1).max(axis=1))
        d = np.abs(dQ2[:, :, 2, :, 2] - dQ1).max(axis=(1, 2))
        worst[1] = max(worst[1], (d / (DT * G)).max())
        big = np.abs(dQ1).max(axis=(1, 2))
        sized = big > 1e-3 * DT * G
        worst[2] = max(worst[2], (d[sized] / big[sized]).max())
        counts += [p2.turned.sum(), p2.reverses.sum(), 0]
        k_before = law.stack.k.copy()
        state.gamma, state.tau, state.stack, state.direction = p1.end()
        motion = p2.commit()
        counts[2] += np.sum(law.stack.k < k_before - 1)       # rejoins
        assert np.array_equal(law.eps[:, 2], state.gamma) and not law.eps[:, :2].any()
        assert np.abs(law.sigma[:, 2] - state.tau).max() <= 1e-14 * np.abs(state.tau).max()
        assert not law.sigma[:, [0, 1, 3]].any()
        assert np.array_equal(law.stack.k, state.stack.k)
        assert np.array_equal(motion[:, 2], state.direction) and not motion[:, :2].any()
        assert np.array_equal(law.heading()[:, 2], state.direction)
    worst[0] = (np.array(rows) / Q_peak).max()
    inside = np.arange(masing.DEPTH)[None, :] < law.stack.k[:, None]
    stack_err = np.abs(np.where(inside, np.sqrt(2.0) * law.stack.c[:, :, 2] - state.stack.g,
                                0.0)).max() / np.abs(state.stack.g).max()
    print(f"simple shear, {n} points x {m} slabs: Q / its peak {worst[0]:.1e}; dQ / (dt G) "
          f"{worst[1]:.1e}, / its largest entry {worst[2]:.1e}; stacks {stack_err:.1e}; "
          f"start reversals {counts[0]}, inside turns {counts[1]}, rejoins {counts[2]}, "
          f"deepest {law.stack.k.max()}")
    assert worst[0] <= 1e-12 and worst[1] <= 1e-12 and worst[2] <= 1e-9
    assert stack_err <= 1e-15
    assert counts[0] > 100 and counts[1] > 100 and counts[2] > 10


# ---- 2. the tangent ------------------------------------------------------------

def signature(path):
    """What makes Q switch: the reversal flags and every depth used."""
    return (path.turned, path.reverses, path.second.k) + tuple(p[5] for p in path.pieces())


def test_tangent_is_the_derivative_of_the_gauss_sums(rng):
    """Random mixed states (10 random slabs, a few points never moved:
    virgin n0 = dD1 / |dD1|), random non-proportional slabs of 0.05 to 3
    gamma_ref: dQ against central differences of Q (step 1e-5 gamma_ref
    in each of the 6 components of (D1, D2)), the largest difference over
    all entries over the point's largest |dQ| entry, <= 1e-6.  Points
    where a difference's step switches a reversal flag or a depth (a
    rejoin, where Q is only piecewise smooth: in 2-D the stress can jump
    there) are left out (none did in this draw); every kind of slab is
    asserted present."""
    n = 400
    law = dv.PlaneMasing(*random_laws(rng, n))
    gr = law.backbone.gamma_ref[:, 0]
    motion = wander(rng, law, 10, 2.0, idle=rng.integers(0, 12, n))
    D1 = rng.normal(size=(n, 3)) * gr[:, None] * rng.uniform(0.05, 3.0, (n, 1))
    D2 = rng.normal(size=(n, 3)) * gr[:, None] * rng.uniform(0.05, 3.0, (n, 1))
    _, dQ, path = ds.slab_integrals(law, D1, D2, DT, motion)
    base = signature(path)
    smooth = np.ones(n, dtype=bool)
    fd = np.zeros_like(dQ)
    h = 1e-5 * gr
    for b in range(2):
        for j in range(3):
            Q_pm = []
            for sign in (1.0, -1.0):
                D = [D1.copy(), D2.copy()]
                D[b][:, j] += sign * h
                Q, _, p = ds.slab_integrals(law, D[0], D[1], DT, motion, tangent=False)
                Q_pm.append(Q)
                for x, y in zip(signature(p), base):
                    smooth &= (x == y).reshape(n, -1).all(axis=1)
            fd[..., b, j] = (Q_pm[0] - Q_pm[1]) / (2.0 * h[:, None, None])
    err = np.abs(fd - dQ).max(axis=(1, 2, 3, 4)) / np.abs(dQ).max(axis=(1, 2, 3, 4))
    kinds = {"inside turns": path.reverses, "start reversals": path.turned,
             "virgin": path.virgin, "straight on": ~path.turned & ~path.reverses}
    print(f"tangent: central differences / largest entry {err[smooth].max():.1e} "
          f"(median {np.median(err[smooth]):.1e}), {smooth.sum()} of {n} points smooth; "
          + ", ".join(f"{k} {np.sum(v & smooth)}" for k, v in kinds.items()))
    assert err[smooth].max() <= 1e-6
    assert smooth.sum() >= 0.9 * n
    assert all(np.sum(v & smooth) >= 10 for v in kinds.values())
    assert (law.stack.k >= 2).any()


# ---- 3. consistency with the integral -------------------------------------------

def test_slab_that_does_not_turn_is_the_integral(rng):
    """Slabs of size x gamma_ref (random mixed D1, D2) from random states
    that neither reverse at the start nor turn, nor rejoin: Q against a
    2000-point Gauss-Legendre rule of T_a (sigma - C_el eps) with the
    stress of PlaneMasing.stress_at from the slab's stack (that rule's own
    error is far below these figures).  The 3-point rule's error falls as
    size^3 (theta's sixth derivative of sigma(eps(theta)) holds sigma'''
    (eps'')^3, eps'' = D2 - D1) while Q stays of the state's size.
    Measured (the error over the point's largest |Q|) at 1, 1/2, 1/4, 1/8,
    1/16 gamma_ref: largest 8.7e-5, 2.6e-5, 4.8e-6, 6.4e-7, 6.9e-8 (not
    yet asymptotic at the big slabs: points whose path passes near their
    branch origin, where |e - e_k|^s is least smooth), medians 2.5e-7 ..
    1.1e-10, falling by 6.5, 6.1, 7.3, 7.7.  Asserted: largest <= 2e-4 at
    1 and 1/2, <= 5e-4 size^3 from 1/4 down; median ratios >= 6, the
    last >= 7."""
    n = 300
    law = dv.PlaneMasing(*random_laws(rng, n))
    G, K, gr = law.backbone.G[:, 0], law.K, law.backbone.gamma_ref[:, 0]
    motion = wander(rng, law, 10, 2.0)
    dirs = rng.normal(size=(2, n, 3))
    xg, wg = np.polynomial.legendre.leggauss(2000)
    theta = np.broadcast_to(0.5 * (xg + 1.0), (n, xg.size))
    T = np.stack((1.0 - theta, theta), axis=-1)
    C = ds.elastic_matrix(G, K)
    worst, median = [], []
    for size in (1.0, 0.5, 0.25, 0.125, 0.0625):
        D1, D2 = size * gr[:, None] * dirs[0], size * gr[:, None] * dirs[1]
        Q, _, path = ds.slab_integrals(law, D1, D2, DT, motion, tangent=False)
        eps = ds.strain(law.eps, D1, D2, theta)
        sigma, _, k = law.stress_at(eps, path.start)
        c = sigma[..., :3] - np.einsum("nij,nmj->nmi", C, eps)
        fine = DT * np.einsum("m,nma,nmi->nai", 0.5 * wg, T, c)
        keep = ~path.turned & ~path.reverses & (k == k[:, :1]).all(axis=1)
        assert keep.sum() >= 40
        err = (np.abs(Q - fine).max(axis=(1, 2)) / np.abs(fine).max(axis=(1, 2)))[keep]
        worst.append(err.max())
        median.append(np.median(err))
        assert worst[-1] <= (2e-4 if size > 0.3 else 5e-4 * size ** 3)
    ratios = np.array(median[:-1]) / np.array(median[1:])
    print("no turn: Gauss / fine rule at 1, 1/2, 1/4, 1/8, 1/16 gamma_ref, largest "
          + ", ".join(f"{w:.1e}" for w in worst) + "; medians "
          + ", ".join(f"{w:.1e}" for w in median) + ", falling by "
          + ", ".join(f"{r:.1f}" for r in ratios))
    assert (ratios >= 6.0).all() and ratios[-1] >= 7.0


# ---- 4. the elastic limit --------------------------------------------------------

def test_tiny_strains_give_no_correction(rng):
    """From rest, three slabs of 1e-12 gamma_ref (turning inside and at the
    start): |Q| against dt |C_el eps| (the linear stress's integral scale)
    stays below the backbone's relative softening beta (gamma/gamma_ref)^s
    there, and dQ beside dt G likewise."""
    n = 100
    params = random_laws(rng, n)
    law = dv.PlaneMasing(*params)
    G, gr, beta, s = params[:4]
    C = ds.elastic_matrix(G, law.K)
    motion, worst = None, 0.0
    for j in range(3):
        D1 = rng.normal(size=(n, 3)) * 1e-12 * gr[:, None]
        D2 = -D1 * rng.uniform(0.2, 2.0, (n, 1))
        Q, dQ, path = ds.slab_integrals(law, D1, D2, DT, motion)
        eps_end = law.eps + 0.5 * (D1 + D2)
        scale = DT * np.abs(np.einsum("nij,nj->ni", C, np.abs(law.eps) + np.abs(D1) + np.abs(D2)))
        soft = beta * (3e-12 * np.sqrt(2.0)) ** s
        ratio = np.abs(Q).max(axis=(1, 2)) / scale.max(axis=1)
        assert (ratio <= soft).all()
        assert (np.abs(dQ).max(axis=(1, 2, 3, 4)) <= soft * DT * G).all()
        worst = max(worst, ratio.max())
        assert path.reverses.any() and (j == 0 or path.turned.any())
        motion = path.commit()
        assert np.allclose(law.eps, eps_end, rtol=0.0, atol=1e-28)
    print(f"elastic limit: |Q| / dt |C_el eps| up to {worst:.1e}")
