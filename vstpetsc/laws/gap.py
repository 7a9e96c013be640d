"""The gap of a contact pair inside a slab and the exact penalty integrals
over its active part (formulation.md sections 3-6).  Pure numpy.

Inside a slab the gap of a pair is the quadratic

    g(theta) = g^n - I_1(theta) d^1 - I_2(theta) d^2,   d^a = sum_k c_k v_{n_k}^a

where the pair's nodes ``n_k`` carry signs ``c_k`` (+1 for the body on the
left, -1 for the body on the right).  The penalty terms are integrated
exactly over the active part {g < 0}: split the slab at the real roots of g,
then a 3-point Gauss rule on each active piece (the integrands are
polynomials of degree <= 4).  The residual of node ``n_k`` gets
``-c_k w G_a`` with ``G_a = int min(0, g) phi_a dt``; the weight ``phi_a`` is
I_a for the seed's penalty and T_a for the consistent ("power") one.
"""

import numpy as np

from vstpetsc.history import GAUSS_W, GAUSS_X


def gap_coefficients(gn, d1, d2, dt):
    """Coefficients (a0, a1, a2) of g(theta) = a0 + a1 theta + a2 theta^2."""
    return gn, -dt * d1, 0.5 * dt * (d1 - d2)


def gap_roots(a0, a1, a2):
    """Real roots of a0 + a1 t + a2 t^2 inside (0, 1), as an (P, 2) array
    sorted per row, with 1.0 standing for "no root" (it adds an empty piece).

    Uses the cancellation-free pair q / a2, a0 / q; a linear or constant g
    falls out of the same formulas (infinite or nan roots are discarded).
    """
    a0, a1, a2 = (np.atleast_1d(np.asarray(c, dtype=float)) for c in (a0, a1, a2))
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = a1 * a1 - 4.0 * a2 * a0
        sq = np.sqrt(np.where(disc >= 0.0, disc, np.nan))
        q = -0.5 * (a1 + np.copysign(sq, a1))
        r1, r2 = q / a2, a0 / q
    r1 = np.where((r1 > 0.0) & (r1 < 1.0), r1, 1.0)     # nan and inf compare False
    r2 = np.where((r2 > 0.0) & (r2 < 1.0), r2, 1.0)
    return np.stack([np.minimum(r1, r2), np.maximum(r1, r2)], axis=-1)


def contact_integrals(gn, d1, d2, dt, formulation):
    """Exact penalty integrals of P pairs over one slab.

    Parameters
    ----------
    gn, d1, d2 : (P,) arrays
        Gap at t^n and the gap closing rates ``d^a`` at the two time nodes.
    dt : float
    formulation : (P,) sequence of "seed"/"power", or a boolean array that
        is True for "power"

    Returns
    -------
    G : (P, 2)  int_{I_n} min(0, g) phi_a dt
    W : (P, 2, 2)  int_{active} phi_a I_b dt  (= -dG_a / dd^b)
    active : (P,) bool, some part of the slab has g < 0
    """
    power = np.asarray(formulation)
    if power.dtype != bool:
        power = power == "power"
    a0, a1, a2 = gap_coefficients(np.asarray(gn, float), np.asarray(d1, float),
                                  np.asarray(d2, float), dt)
    r = gap_roots(a0, a1, a2)
    lo = np.concatenate([np.zeros_like(r[:, :1]), r], axis=1)          # (P, 3) pieces
    length = np.concatenate([r, np.ones_like(r[:, :1])], axis=1) - lo
    mid = lo + 0.5 * length
    on = (a0[:, None] + mid * (a1[:, None] + mid * a2[:, None]) < 0.0) & (length > 0.0)
    active = on.any(axis=1)
    P = a0.size
    G, W = np.zeros((P, 2)), np.zeros((P, 2, 2))
    if not active.any():
        return G, W, active
    # Gauss points of all pieces, flattened per pair: (P, 9); weights are dt dtheta
    theta = (lo[..., None] + length[..., None] * GAUSS_X).reshape(P, -1)
    w = (dt * (length * on)[..., None] * GAUSS_W).reshape(P, -1)
    g = a0[:, None] + theta * (a1[:, None] + theta * a2[:, None])
    half = 0.5 * theta * theta
    i1, i2 = dt * (theta - half), dt * half
    pw = power[:, None]
    phi1 = np.where(pw, 1.0 - theta, i1)
    phi2 = np.where(pw, theta, i2)
    wg = w * g
    G[:, 0], G[:, 1] = (wg * phi1).sum(axis=1), (wg * phi2).sum(axis=1)
    w1, w2 = w * phi1, w * phi2
    W[:, 0, 0], W[:, 0, 1] = (w1 * i1).sum(axis=1), (w1 * i2).sum(axis=1)
    W[:, 1, 0], W[:, 1, 1] = (w2 * i1).sum(axis=1), (w2 * i2).sum(axis=1)
    return G, W, active
