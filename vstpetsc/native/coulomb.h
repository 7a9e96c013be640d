/* Coulomb friction of a contact pair over one slab: the exact slab
 * integrals of vstpetsc.kernels.coulomb.friction_integrals (whose docstring
 * has the mathematics), with the same floating-point operations in the
 * same order, so that built with -ffp-contract=off (no fused
 * multiply-adds) its answer is the Python one bit for bit.
 *
 * A pure function on plain numbers and arrays (no state, nothing
 * allocated): any compiled Newton can call it beside the penalty pair's
 * integrals (pair.h); penalty_newton.c does.  "sigma None" of the Python is
 * sigma = 0 here. */
#ifndef VST_COULOMB_H
#define VST_COULOMB_H

#include <math.h>

#include "gap.h"

#define COULOMB_MAX_SWITCHES 64     /* a piece has a handful; more would be a float loop */

/* kernels/coulomb.py FrictionSlab, field for field */
typedef struct {
    double f1, f2;                  /* F_a = dt int T T_a */
    double d11, d12, d21, d22;      /* dF_a / ds_b */
    double stretch;                 /* e at the slab's end */
    double slip;                    /* slip accumulated in contact over the slab */
    double dissipation;             /* int mu N |slip rate| dt >= 0 */
    double released;                /* k_t (e_n^2 - e^2) / 2 of the start's projection */
} FrictionSlab;

/* kernels/coulomb.py _Slab: what the pieces of one slab share */
typedef struct {
    double s1, s2, dt, k, mu, n0, n1, n2, tol;
    double out[6];
    double slip, dissipation;
} CoulombRun;

/* the 3-point Gauss rule of kernels/gap.py GAUSS (sqrt(0.6) as Python's repr) */
static inline double coulomb_gauss_x(int i)
{
    static const double SQ = 0.7745966692414834;
    return i == 0 ? 0.5 - 0.5 * SQ : i == 1 ? 0.5 : 0.5 + 0.5 * SQ;
}

static inline double coulomb_gauss_w(int i)
{
    return i == 1 ? 8.0 / 18.0 : 5.0 / 18.0;
}

/* _J: (int_0^t T_1, int_0^t T_2) */
static inline void coulomb_J(double t, double *j)
{
    double half = 0.5 * t * t;
    j[0] = t - half;
    j[1] = half;
}

/* N(t) on a piece, never below 0 (Python's max(0.0, N)) */
static inline double coulomb_normal(const CoulombRun *r, double t)
{
    double n = r->n0 + t * (r->n1 + t * r->n2);
    return n > 0.0 ? n : 0.0;
}

static inline double coulomb_dnormal(const CoulombRun *r, double t)
{
    return r->n1 + 2.0 * t * r->n2;
}

/* dt int_a^b s: the relative displacement */
static inline double coulomb_moved(const CoulombRun *r, double a, double b)
{
    double ja[2], jb[2];
    coulomb_J(a, ja);
    coulomb_J(b, jb);
    return r->dt * (r->s1 * (jb[0] - ja[0]) + r->s2 * (jb[1] - ja[1]));
}

/* sigma k dt s - mu N': the trial rate of f_sigma */
static inline double coulomb_h(const CoulombRun *r, double sigma, double t)
{
    double s = r->s1 + (r->s2 - r->s1) * t;
    return sigma * r->k * r->dt * s - r->mu * coulomb_dnormal(r, t);
}

static inline double coulomb_h_slope(const CoulombRun *r, double sigma)
{
    return sigma * r->k * r->dt * (r->s2 - r->s1) - 2.0 * r->mu * r->n2;
}

/* whether the limit in direction sigma is pushed outward just after t */
static inline int coulomb_slides_from(const CoulombRun *r, double sigma, double t)
{
    double h = coulomb_h(r, sigma, t);
    return h > r->tol || (h >= -r->tol && coulomb_h_slope(r, sigma) > 0.0);
}

/* _yield_point: where the elastic stretch from e at t0 first reaches the
 * limit and presses on it (*ts, *sigma), or (q, 0) */
static inline void coulomb_yield_point(const CoulombRun *r, double e, double t0, double q,
                                       double *ts_out, double *sigma_out)
{
    double L = q - t0, best_t = q, best_s = 0.0, k = r->k, mu = r->mu;
    for (int side = 0; side < 2; side++) {
        double sigma = side == 0 ? 1.0 : -1.0, n_t0 = coulomb_normal(r, t0);
        double c0 = sigma * k * e - mu * n_t0;
        if (c0 >= -1e-12 * mu * n_t0 && coulomb_slides_from(r, sigma, t0)) {
            *ts_out = t0;       /* on the limit (to rounding) and pressed on */
            *sigma_out = sigma;
            return;
        }
        double c1 = L * coulomb_h(r, sigma, t0);
        double c2 = L * L * (0.5 * sigma * k * r->dt * (r->s2 - r->s1) - mu * r->n2);
        double cuts[4];
        int n = 1 + roots01(c0, c1, c2, cuts + 1);
        cuts[0] = 0.0;
        cuts[n++] = 1.0;
        for (int i = 0; i + 1 < n; i++) {
            double u = cuts[i], v = cuts[i + 1], ts = t0 + L * u;
            if (ts >= best_t)
                break;
            double m = 0.5 * (u + v);
            if (c0 + m * (c1 + m * c2) > 0.0 && coulomb_slides_from(r, sigma, ts)) {
                best_t = ts;
                best_s = sigma;
                break;
            }
        }
    }
    *ts_out = best_t;
    *sigma_out = best_s;
}

/* _exit_point: where sliding from t ends, the root of h_sigma ahead, or q */
static inline double coulomb_exit_point(const CoulombRun *r, double sigma, double t, double q)
{
    double slope = coulomb_h_slope(r, sigma);
    if (slope < 0.0) {
        double x = t - coulomb_h(r, sigma, t) / slope;
        if (t < x && x < q)
            return x;
    }
    return q;
}

/* _elastic: add the elastic stretch over [a, b] from e (de: its
 * derivatives by s1, s2) at a; e and de become the stretch at b and its */
static inline void coulomb_elastic(CoulombRun *r, double *e, double *de, double a, double b)
{
    double k = r->k, dt = r->dt, *out = r->out, ja[2], jt[2], jb[2];
    double length = b - a;
    coulomb_J(a, ja);
    for (int i = 0; i < 3; i++) {
        double t = a + length * coulomb_gauss_x(i);
        double w = dt * length * coulomb_gauss_w(i);
        coulomb_J(t, jt);
        double force = -k * (*e + coulomb_moved(r, a, t));
        double df0 = -k * (de[0] + dt * (jt[0] - ja[0]));
        double df1 = -k * (de[1] + dt * (jt[1] - ja[1]));
        double phi0 = 1.0 - t, phi1 = t;
        out[0] += w * force * phi0;
        out[2] += w * df0 * phi0;
        out[3] += w * df1 * phi0;
        out[1] += w * force * phi1;
        out[4] += w * df0 * phi1;
        out[5] += w * df1 * phi1;
    }
    coulomb_J(b, jb);
    *e = *e + coulomb_moved(r, a, b);
    de[0] = de[0] + dt * (jb[0] - ja[0]);
    de[1] = de[1] + dt * (jb[1] - ja[1]);
}

/* _sliding: add sliding in direction sigma over [a, b]: force, slip,
 * dissipation (mu N sigma dp/dtheta = mu N h_sigma / k_t) */
static inline void coulomb_sliding(CoulombRun *r, double sigma, double a, double b)
{
    double mu = r->mu, *out = r->out, length = b - a;
    for (int i = 0; i < 3; i++) {
        double t = a + length * coulomb_gauss_x(i);
        double n = coulomb_normal(r, t);
        double w = r->dt * length * coulomb_gauss_w(i);
        out[0] -= w * sigma * mu * n * (1.0 - t);
        out[1] -= w * sigma * mu * n * t;
        r->dissipation += length * coulomb_gauss_w(i) * mu * n * coulomb_h(r, sigma, t) / r->k;
    }
    r->slip += coulomb_moved(r, a, b)
        - sigma * mu * (coulomb_normal(r, b) - coulomb_normal(r, a)) / r->k;
}

/* _piece: one active piece [p, q] from stretch *e at p; *e becomes the
 * stretch at q.  0, or 1 when the switches did not settle */
static inline int coulomb_piece(CoulombRun *r, double *e, double p, double q)
{
    double t = p, de[2] = {0.0, 0.0}, sigma = 0.0;
    for (int it = 0; it < COULOMB_MAX_SWITCHES; it++) {
        if (t >= q)
            return 0;
        if (sigma == 0.0) {
            double ts;
            coulomb_yield_point(r, *e, t, q, &ts, &sigma);
            if (ts > t)
                coulomb_elastic(r, e, de, t, ts);
            t = ts;
        } else {
            double x = coulomb_exit_point(r, sigma, t, q);
            coulomb_sliding(r, sigma, t, x);
            *e = sigma * r->mu * coulomb_normal(r, x) / r->k;
            de[0] = de[1] = 0.0;
            t = x;
            sigma = 0.0;
        }
    }
    return 1;
}

/* friction_integrals: the FrictionSlab of one slab from the stretch e_n at
 * its start, the relative shear velocities s1, s2, the tangential
 * stiffness k_t, the coefficient mu and the normal force's coefficients
 * normal[3] on its ordered active pieces (p, q) = pieces[2 i], pieces[2 i + 1],
 * i < count.  0, or 1 when the switches did not settle (the Python raises) */
static inline int coulomb_friction_integrals(double e_n, double s1, double s2, double dt,
                                             double k_t, double mu, const double *normal,
                                             const double *pieces, int count, FrictionSlab *o)
{
    CoulombRun r = {s1, s2, dt, k_t, mu, normal[0], normal[1], normal[2], 0.0,
                    {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, 0.0, 0.0};
    /* |h| below this is rounding (h_sigma sums terms of these sizes) */
    r.tol = 1e-12 * (k_t * dt * (fabs(s1) + fabs(s2)) + mu * (fabs(r.n1) + 2.0 * fabs(r.n2)));
    double start_limit = count > 0 && pieces[0] == 0.0 ? mu * r.n0 / k_t : 0.0;
    double e = e_n < start_limit ? e_n : start_limit;      /* Python's min, then max */
    e = e > -start_limit ? e : -start_limit;
    o->released = 0.5 * k_t * (e_n * e_n - e * e);
    for (int i = 0; i < count; i++) {
        if (pieces[2 * i] > 0.0)
            e = 0.0;                /* the gap was open just before p */
        if (coulomb_piece(&r, &e, pieces[2 * i], pieces[2 * i + 1]))
            return 1;
    }
    if (count == 0 || pieces[2 * count - 1] < 1.0)
        e = 0.0;                    /* open at the slab's end */
    o->f1 = r.out[0]; o->f2 = r.out[1];
    o->d11 = r.out[2]; o->d12 = r.out[3]; o->d21 = r.out[4]; o->d22 = r.out[5];
    o->stretch = e;
    o->slip = r.slip;
    o->dissipation = r.dissipation;
    return 0;
}

#endif
