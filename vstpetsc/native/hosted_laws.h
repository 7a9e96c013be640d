/* Contact pairs and Coulomb friction inside the hysteretic soil's compiled
 * Newton (soil_newton.c): the rows and tangent blocks of
 * vstpetsc/petsc/hosted_laws.py, the laws evaluated as
 * vstpetsc.laws.penalty.PenaltyContact.force and
 * vstpetsc.laws.friction.CoulombFriction.force do (pair.h, coulomb.h: the
 * same operations).  The laws' dofs E are nodes of the mesh; y = R0 z_E,
 * their rows on E are U f (U = WE P), their tangent U f'(y) R0, which the
 * 1-D mesh keeps in the block bands (a pair's nodes are neighbours).
 *
 * The caller (vstpetsc/native/hosted_laws.py) owns every array and sets
 * the laws' slab state (gaps, stretches, the walls' velocities) before
 * each slab; after it, it reads the last evaluation's outputs. */
#ifndef VST_HOSTED_LAWS_H
#define VST_HOSTED_LAWS_H

#include <math.h>
#include <string.h>

#include "coulomb.h"
#include "pair.h"

typedef struct {
    int laws;                  /* L, in the LawSet's order */
    int k;                     /* dofs E (2 a node) */
    double dt;
    const long *enode;         /* (k / 2) global node of each E node */
    const double *R0;          /* (2L, k) */
    const double *U;           /* (k, 2L) */
    const int *kind;           /* (L) 0: penalty pair, 1: friction */
    const int *normal_of;      /* (L) friction: its pair's law number */
    const int *power;          /* (L) pairs: 1 "power", 0 "seed" */
    const double *w;           /* (L) pairs: penalty; friction: k_t */
    const double *mu;          /* (L) friction */
    const double *gn;          /* (L) pairs: gap at t^n; friction: stretch at t^n */
    const double *wall;        /* (L, 2) friction: c_wall v_wall at the slab's ends */
    /* out, at the last evaluation */
    double *zE, *y, *f;        /* (k), (2L), (2L) */
    double *out;               /* (L, 6): (f1, f2, t11, t12, t21, t22) */
    int *hit;                  /* (L) */
    double *G;                 /* (L, 6): a pair's integrals */
    double *normal;            /* (L, 3): a pair's normal force coefficients */
    double *pieces;            /* (L, 6): a pair's active pieces */
    int *count;                /* (L): their number */
    double *slab;              /* (L, 10): friction's FrictionSlab */
    double *rows;              /* (k) */
    double *jac;               /* (k, k): d rows / d z_E (with the tangent) */
    double *kept;              /* (k, k): the jac the factors hold */
    int failed;                /* friction's switches did not settle */
} HostedLaws;

/* a pair's terms at its closing rates (d1, d2): PenaltyContact.force and
 * .normal_force */
static inline void hosted_pair(HostedLaws *h, int j, double d1, double d2)
{
    double *G = h->G + 6 * j, *o = h->out + 6 * j, w = h->w[j], *n = h->normal + 3 * j;
    h->hit[j] = pair_integrals(h->gn[j], d1, d2, h->dt, h->power[j], G);
    if (!h->hit[j])
        return;
    o[0] = -w * G[0]; o[1] = -w * G[1];
    o[2] = w * G[2]; o[3] = w * G[3]; o[4] = w * G[4]; o[5] = w * G[5];
    if (h->power[j]) {
        double a[3];
        gap_coefficients(h->gn[j], d1, d2, h->dt, a);
        penalty_normal(a, w, n);
        h->count[j] = active_intervals(a, h->pieces + 6 * j);
    } else {
        n[0] = -w * (G[0] + G[1]) / h->dt; n[1] = 0.0; n[2] = 0.0;
        h->pieces[6 * j] = 0.0; h->pieces[6 * j + 1] = 1.0;
        h->count[j] = 1;
    }
}

/* friction's terms: CoulombFriction.force */
static inline void hosted_friction(HostedLaws *h, int j, double y1, double y2)
{
    int p = h->normal_of[j];
    h->hit[j] = h->hit[p];
    if (!h->hit[j])
        return;
    FrictionSlab fs;
    const double *v = h->wall + 2 * j;
    if (coulomb_friction_integrals(h->gn[j], -(y1 + v[0]), -(y2 + v[1]), h->dt, h->w[j],
                                   h->mu[j], h->normal + 3 * p, h->pieces + 6 * p,
                                   h->count[p], &fs)) {
        h->failed = 1;
        h->hit[j] = 0;
        return;
    }
    double *o = h->out + 6 * j, *s = h->slab + 10 * j;
    o[0] = fs.f1; o[1] = fs.f2; o[2] = -fs.d11; o[3] = -fs.d12; o[4] = -fs.d21; o[5] = -fs.d22;
    s[0] = fs.f1; s[1] = fs.f2; s[2] = fs.d11; s[3] = fs.d12; s[4] = fs.d21; s[5] = fs.d22;
    s[6] = fs.stretch; s[7] = fs.slip; s[8] = fs.dissipation; s[9] = fs.released;
}

/* the laws at the unknowns X (z per node): F += their rows; with_tangent:
 * jac too.  Returns the rows' norm. */
static inline double hosted_residual(HostedLaws *h, const double *X, double *F, int with_tangent)
{
    int k = h->k, n = 2 * h->laws;
    for (int e = 0; e < k / 2; e++) {
        h->zE[2 * e] = X[2 * h->enode[e]];
        h->zE[2 * e + 1] = X[2 * h->enode[e] + 1];
    }
    for (int i = 0; i < n; i++) {
        double s = 0.0;
        for (int c = 0; c < k; c++)
            s += h->R0[i * k + c] * h->zE[c];
        h->y[i] = s;
    }
    for (int j = 0; j < h->laws; j++) {
        if (h->kind[j] == 0)
            hosted_pair(h, j, h->y[2 * j], h->y[2 * j + 1]);
        else
            hosted_friction(h, j, h->y[2 * j], h->y[2 * j + 1]);
        h->f[2 * j] = h->hit[j] ? h->out[6 * j] : 0.0;
        h->f[2 * j + 1] = h->hit[j] ? h->out[6 * j + 1] : 0.0;
    }
    double norm2 = 0.0;
    for (int r = 0; r < k; r++) {
        double s = 0.0;
        for (int i = 0; i < n; i++)
            s += h->U[r * n + i] * h->f[i];
        h->rows[r] = s;
        norm2 += s * s;
    }
    for (int e = 0; e < k / 2; e++) {
        F[2 * h->enode[e]] += h->rows[2 * e];
        F[2 * h->enode[e] + 1] += h->rows[2 * e + 1];
    }
    if (with_tangent) {
        /* jac = U T R0, T block diagonal (each law's 2 x 2 tangent) */
        memset(h->jac, 0, (size_t)(k * k) * sizeof(double));
        for (int j = 0; j < h->laws; j++) {
            if (!h->hit[j])
                continue;
            const double *t = h->out + 6 * j + 2;
            for (int c = 0; c < k; c++) {
                double r1 = t[0] * h->R0[2 * j * k + c] + t[1] * h->R0[(2 * j + 1) * k + c];
                double r2 = t[2] * h->R0[2 * j * k + c] + t[3] * h->R0[(2 * j + 1) * k + c];
                if (r1 == 0.0 && r2 == 0.0)
                    continue;
                for (int r = 0; r < k; r++)
                    h->jac[r * k + c] += h->U[r * n + 2 * j] * r1 + h->U[r * n + 2 * j + 1] * r2;
            }
        }
    }
    return sqrt(norm2);
}

/* J += the laws' blocks (jac, kept as the factors') at their nodes'
 * band entries */
static inline void hosted_tangent(HostedLaws *h, double *J)
{
    int k = h->k;
    memcpy(h->kept, h->jac, (size_t)(k * k) * sizeof(double));
    for (int a = 0; a < k / 2; a++) {
        for (int b = 0; b < k / 2; b++) {
            long d = h->enode[b] - h->enode[a];
            if (d < -1 || d > 1)
                continue;
            double *B = J + 12 * h->enode[a] + 4 * (d + 1);
            B[0] += h->jac[(2 * a) * k + 2 * b];
            B[1] += h->jac[(2 * a) * k + 2 * b + 1];
            B[2] += h->jac[(2 * a + 1) * k + 2 * b];
            B[3] += h->jac[(2 * a + 1) * k + 2 * b + 1];
        }
    }
}

#endif
