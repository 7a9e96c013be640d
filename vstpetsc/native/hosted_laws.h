/* Contact pairs and Coulomb friction inside the hysteretic soil's compiled
 * Newton (soil_newton.c): the rows and tangent blocks of
 * vstpetsc/line/solver/hosted_laws.py, the laws evaluated as
 * vstpetsc.line.laws.penalty.PenaltyContact.force and
 * vstpetsc.line.laws.friction.CoulombFriction.force do (pair.h, coulomb.h: the
 * same operations).  The laws' dofs E are nodes of the mesh; y = R0 z_E,
 * their rows on E are U f (U = WE P), their tangent U f'(y) R0, which the
 * 1-D mesh keeps in the block bands (a pair's nodes are neighbours).
 *
 * The laws' terms are law_forces()'s (law_forces.h), as in the laws' own
 * compiled Newton.  The caller (vstpetsc/line/native/hosted_laws.py) owns every
 * array and sets the laws' slab state (gaps, stretches, the walls'
 * velocities) before each slab; after it, it reads the last evaluation's
 * outputs. */
#ifndef VST_HOSTED_LAWS_H
#define VST_HOSTED_LAWS_H

#include <math.h>
#include <string.h>

#include "law_forces.h"

typedef struct {
    LawForces f;               /* the laws' arrays: law_forces() evaluates them */
    int k;                     /* dofs E (2 a node) */
    const long *enode;         /* (k / 2) global node of each E node */
    const double *R0;          /* (2L, k) */
    const double *U;           /* (k, 2L) */
    /* out, at the last evaluation */
    double *zE, *y, *fy;       /* (k), (2L), (2L): the laws' terms f */
    double *rows;              /* (k) */
    double *jac;               /* (k, k): d rows / d z_E (with the tangent) */
    double *kept;              /* (k, k): the jac the factors hold */
} HostedLaws;

/* the laws at the unknowns X (z per node): F += their rows; with_tangent:
 * jac too.  Returns the rows' norm. */
static inline double hosted_residual(HostedLaws *h, const double *X, double *F, int with_tangent)
{
    int k = h->k, n = 2 * h->f.laws;
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
    law_forces(&h->f, h->y);
    for (int j = 0; j < h->f.laws; j++) {
        h->fy[2 * j] = h->f.hit[j] ? h->f.out[6 * j] : 0.0;
        h->fy[2 * j + 1] = h->f.hit[j] ? h->f.out[6 * j + 1] : 0.0;
    }
    double norm2 = 0.0;
    for (int r = 0; r < k; r++) {
        double s = 0.0;
        for (int i = 0; i < n; i++)
            s += h->U[r * n + i] * h->fy[i];
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
        for (int j = 0; j < h->f.laws; j++) {
            if (!h->f.hit[j])
                continue;
            const double *t = h->f.out + 6 * j + 2;
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
