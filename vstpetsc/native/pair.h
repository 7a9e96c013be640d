/* One penalty contact pair over one slab (vstpetsc.kernels.gap): its gap's
 * coefficients, its exact penalty integrals and its active pieces, with
 * the same floating-point operations in the same order as the Python.
 * Pure functions on plain arrays, shared by penalty_newton.c (and the
 * compiled Newtons that will take pairs beside other laws). */
#ifndef VST_PAIR_H
#define VST_PAIR_H

#include "gap.h"

/* vstpetsc.kernels.gap.closed_throughout: g < 0 on the whole slab */
static inline int closed_throughout(double a0, double a1, double a2)
{
    if (a0 >= 0.0 || a0 + a1 + a2 >= 0.0)
        return 0;
    if (a2 < 0.0) {
        double t = -a1 / (2.0 * a2);
        return !(0.0 < t && t < 1.0 && a0 + t * (a1 + t * a2) >= 0.0);
    }
    return 1;
}

/* vstpetsc.kernels.gap.gap_coefficients: g(theta) = a[0] + a[1] theta + a[2] theta^2 */
static inline void gap_coefficients(double gn, double d1, double d2, double dt, double *a)
{
    a[0] = gn;
    a[1] = -dt * d1;
    a[2] = 0.5 * dt * (d1 - d2);
}

/* vstpetsc.kernels.gap.pair_integrals: 1 and G[6] when the pair acts, else 0 */
static inline int pair_integrals(double gn, double d1, double d2, double dt, int power, double *G)
{
    /* sqrt(0.6): Python's repr of math.sqrt(0.6), which parses to the same double */
    static const double SQ = 0.7745966692414834;
    double a[3];
    gap_coefficients(gn, d1, d2, dt, a);
    double a0 = a[0], a1 = a[1], a2 = a[2];
    if (closed_throughout(a0, a1, a2)) {
        if (power) {
            double w = dt * dt;
            G[0] = dt * (a0 / 2.0 + a1 / 6.0 + a2 / 12.0);
            G[1] = dt * (a0 / 2.0 + a1 / 3.0 + a2 / 4.0);
            G[2] = w / 8.0; G[3] = w / 24.0; G[4] = 5.0 * w / 24.0; G[5] = w / 8.0;
        } else {
            double w = dt * dt * dt;
            G[0] = dt * dt * (a0 / 3.0 + 5.0 * a1 / 24.0 + 3.0 * a2 / 20.0);
            G[1] = dt * dt * (a0 / 6.0 + a1 / 8.0 + a2 / 10.0);
            G[2] = 2.0 * w / 15.0; G[3] = 3.0 * w / 40.0; G[4] = 3.0 * w / 40.0;
            G[5] = w / 20.0;
        }
        return 1;
    }
    if (!closed_somewhere(a0, a1, a2))
        return 0;
    const double gx[3] = {0.5 - 0.5 * SQ, 0.5, 0.5 + 0.5 * SQ};
    const double gw[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
    double edges[4];
    int ne = 0;
    edges[ne++] = 0.0;
    ne += roots01(a0, a1, a2, edges + 1);
    edges[ne++] = 1.0;
    double G1 = 0.0, G2 = 0.0, W11 = 0.0, W12 = 0.0, W21 = 0.0, W22 = 0.0;
    int hit = 0;
    for (int k = 0; k < ne - 1; k++) {
        double p = edges[k], q = edges[k + 1];
        double length = q - p;
        double mid = p + 0.5 * length;
        if (length <= 0.0 || a0 + mid * (a1 + mid * a2) >= 0.0)
            continue;
        hit = 1;
        for (int i = 0; i < 3; i++) {
            double t = p + length * gx[i];
            double w = dt * length * gw[i];
            double g = a0 + t * (a1 + t * a2);
            double half = 0.5 * t * t;
            double i1 = dt * (t - half), i2 = dt * half;
            double f1 = power ? 1.0 - t : i1, f2 = power ? t : i2;
            G1 += w * g * f1;
            G2 += w * g * f2;
            double w1 = w * f1, w2 = w * f2;
            W11 += w1 * i1;
            W12 += w1 * i2;
            W21 += w2 * i1;
            W22 += w2 * i2;
        }
    }
    if (!hit)
        return 0;
    G[0] = G1; G[1] = G2; G[2] = W11; G[3] = W12; G[4] = W21; G[5] = W22;
    return 1;
}

/* vstpetsc.kernels.gap.active_intervals: the pieces (p, q) of [0, 1] where
 * g < 0 into pq (at most three), touching ones joined; returns their count */
static inline int active_intervals(const double *a, double *pq)
{
    double e[4], r[2];
    int m, n = 0;
    if (closed_throughout(a[0], a[1], a[2])) {
        pq[0] = 0.0;
        pq[1] = 1.0;
        return 1;
    }
    m = roots01(a[0], a[1], a[2], r);
    e[0] = 0.0;
    for (int i = 0; i < m; i++)
        e[i + 1] = r[i];
    e[m + 1] = 1.0;
    for (int i = 0; i <= m; i++) {
        double p = e[i], q = e[i + 1], mid = p + 0.5 * (q - p);
        if (!(q > p && a[0] + mid * (a[1] + mid * a[2]) < 0.0))
            continue;
        if (n > 0 && pq[2 * n - 1] == p) {
            pq[2 * n - 1] = q;
        } else {
            pq[2 * n] = p;
            pq[2 * n + 1] = q;
            n++;
        }
    }
    return n;
}

/* vstpetsc.kernels.coulomb.penalty_normal's coefficients: the power penalty's
 * normal force N = k max(0, -g) is -k g on the active pieces */
static inline void penalty_normal(const double *a, double k, double *n)
{
    n[0] = -k * a[0];
    n[1] = -k * a[1];
    n[2] = -k * a[2];
}

#endif
