"""The gap of a contact pair inside a slab and the exact penalty integrals
over its active part (formulation.md sections 3-6), in plain Python floats
(a slab needs them for one pair at a time, where numpy's per-call cost
would dominate).

Inside a slab the gap of a pair is the quadratic

    g(theta) = g^n - I_1(theta) d^1 - I_2(theta) d^2,   d^a = sum_k c_k v_{n_k}^a

where the pair's nodes ``n_k`` carry signs ``c_k`` (+1 for the body on the
left, -1 for the body on the right).  The penalty terms are integrated
exactly over the active part {g < 0}: split the slab at the real roots of g,
then a 3-point Gauss rule on each active piece (the integrands are
polynomials of degree <= 4; evaluating g at the points, not summing
moments, keeps a barely active piece accurate).  The residual of node
``n_k`` gets ``-c_k w G_a`` with ``G_a = int min(0, g) phi_a dt``; the weight
``phi_a`` is I_a for the seed's penalty and T_a for the consistent ("power")
one.
"""

import math

_SQ = math.sqrt(0.6)
GAUSS = ((0.5 - 0.5 * _SQ, 5.0 / 18.0), (0.5, 8.0 / 18.0), (0.5 + 0.5 * _SQ, 5.0 / 18.0))


def gap_coefficients(gn, d1, d2, dt):
    """Coefficients (a0, a1, a2) of g(theta) = a0 + a1 theta + a2 theta^2."""
    return gn, -dt * d1, 0.5 * dt * (d1 - d2)


def roots01(a0, a1, a2):
    """Real roots of a0 + a1 t + a2 t^2 strictly inside (0, 1), sorted; the
    cancellation-free pair q / a2, a0 / q (a linear g has one root)."""
    if a2 != 0.0:
        disc = a1 * a1 - 4.0 * a2 * a0
        if disc < 0.0:
            return ()
        q = -0.5 * (a1 + math.copysign(math.sqrt(disc), a1))
        if q == 0.0:
            return ()
        r1, r2 = sorted((q / a2, a0 / q))
        return tuple(r for r in (r1, r2) if 0.0 < r < 1.0)
    if a1 != 0.0:
        r = -a0 / a1
        return (r,) if 0.0 < r < 1.0 else ()
    return ()


def closed_on_slab(gn, d1, d2, dt):
    """Whether g < 0 somewhere in the slab."""
    return closed_somewhere(*gap_coefficients(gn, d1, d2, dt))


def closed_somewhere(a0, a1, a2):
    """Whether g < 0 somewhere in [0, 1] (the end points and the vertex of
    the parabola are its only candidates for a minimum)."""
    if a0 < 0.0 or a0 + a1 + a2 < 0.0:
        return True
    if a2 > 0.0:
        t = -a1 / (2.0 * a2)
        return 0.0 < t < 1.0 and a0 + t * (a1 + t * a2) < 0.0
    return False


def closed_throughout(a0, a1, a2):
    """Whether g < 0 on the whole slab [0, 1]."""
    if a0 >= 0.0 or a0 + a1 + a2 >= 0.0:
        return False
    if a2 < 0.0:                 # concave: its vertex may rise above zero inside
        t = -a1 / (2.0 * a2)
        return not (0.0 < t < 1.0 and a0 + t * (a1 + t * a2) >= 0.0)
    return True


def pair_integrals(gn, d1, d2, dt, power):
    """Exact penalty integrals of one pair over one slab.

    Returns (G1, G2, W11, W12, W21, W22) with G_a = int min(0, g) phi_a dt
    and W_ab = int_active phi_a I_b dt (= -dG_a / dd^b), or None when g >= 0
    on the whole slab.  ``power`` picks phi = T (else I, the seed's).
    A gap closed over the whole slab (steady contact) has closed forms: the
    moments of T_a and I_a and the products T_a I_b, I_a I_b on [0, 1].
    """
    a0, a1, a2 = gap_coefficients(gn, d1, d2, dt)
    if closed_throughout(a0, a1, a2):
        if power:
            w = dt * dt
            return (dt * (a0 / 2.0 + a1 / 6.0 + a2 / 12.0),
                    dt * (a0 / 2.0 + a1 / 3.0 + a2 / 4.0),
                    w / 8.0, w / 24.0, 5.0 * w / 24.0, w / 8.0)
        w = dt * dt * dt
        return (dt * dt * (a0 / 3.0 + 5.0 * a1 / 24.0 + 3.0 * a2 / 20.0),
                dt * dt * (a0 / 6.0 + a1 / 8.0 + a2 / 10.0),
                2.0 * w / 15.0, 3.0 * w / 40.0, 3.0 * w / 40.0, w / 20.0)
    if not closed_somewhere(a0, a1, a2):
        return None
    edges = (0.0,) + roots01(a0, a1, a2) + (1.0,)
    G1 = G2 = W11 = W12 = W21 = W22 = 0.0
    hit = False
    for k in range(len(edges) - 1):
        p, q = edges[k], edges[k + 1]
        length = q - p
        mid = p + 0.5 * length
        if length <= 0.0 or a0 + mid * (a1 + mid * a2) >= 0.0:
            continue
        hit = True
        for x, weight in GAUSS:
            t = p + length * x
            w = dt * length * weight
            g = a0 + t * (a1 + t * a2)
            half = 0.5 * t * t
            i1, i2 = dt * (t - half), dt * half
            f1, f2 = ((1.0 - t), t) if power else (i1, i2)
            G1 += w * g * f1
            G2 += w * g * f2
            w1, w2 = w * f1, w * f2
            W11 += w1 * i1
            W12 += w1 * i2
            W21 += w2 * i1
            W22 += w2 * i2
    return (G1, G2, W11, W12, W21, W22) if hit else None


def active_intervals(a0, a1, a2):
    """[(p, q)] of [0, 1] where g = a0 + a1 t + a2 t^2 < 0, in order: the
    pieces between the roots that pair_integrals integrates (a piece is
    active where its midpoint is), touching pieces joined (a double root
    inside a closed stretch is no event)."""
    if closed_throughout(a0, a1, a2):
        return [(0.0, 1.0)]
    edges = (0.0,) + roots01(a0, a1, a2) + (1.0,)
    pieces = []
    for p, q in zip(edges, edges[1:]):
        mid = p + 0.5 * (q - p)
        if q > p and a0 + mid * (a1 + mid * a2) < 0.0:
            pieces.append((p, q))
    return merged(pieces)


def merged(pieces):
    """Ordered pieces [(p, q)] with the touching ones joined."""
    out = []
    for p, q in pieces:
        if out and out[-1][1] == p:
            out[-1] = (out[-1][0], q)
        else:
            out.append((p, q))
    return out
