/* The hysteretic soil's Newton on the whole slab, on one rank, in one call:
 * the same steps as vstpetsc/line/solver/material_newton.py PlainSoilNewton (the
 * checked reference, -vst_native 0), with the slab matrix as its 2 x 2
 * block tridiagonal bands and the LU of A + the tangent by the block
 * Thomas algorithm (natural order, as PETSc's LU of A: a block
 * tridiagonal matrix fills nothing in).
 *
 * Unknowns and rows are the solver's (z and W-mixed rows, 2 a node). */

#include <math.h>
#include <string.h>

#include "bands.h"
#include "hosted_laws.h"
#include "masing.h"

typedef struct {
    long N;                    /* nodes */
    const double *A;           /* (N, 3, 2, 2): [i][0] couples i to i-1, [1] itself, [2] i+1 */
    double *J;                 /* (N, 3, 2, 2) workspace: A + the tangent */
    double *Minv, *Cp;         /* (N, 2, 2): the LU of J (block Thomas) */
    double *Ainv, *ACp;        /* (N, 2, 2): the LU of A, once */
    double *F, *y;             /* (2N) workspace */
    const long *node;          /* (n): the soil's nodes' global numbers */
    const double *rfree;       /* (ne, 2): left and right node's free factor */
    const long *gleft;         /* (ne): each element's left global node */
    MasingSlab *m;
    double rtol, atol, slow, lagged;
    int max_it;
    int fresh;                 /* J's factors in use (persist over slabs) */
    double *rows_last;         /* (n, 2): the last slab's rows W r (the predictor) */
    double *kept_blocks;       /* (ne, 2, 2): the element blocks J was factored with */
    /* outputs */
    int iterations, converged;
    double fnorm;
    HostedLaws *laws;          /* contact pairs and friction in the same Newton, or NULL */
    double min_step;           /* with laws: the smallest fraction of a step tried */
} SoilNewton;

static double norm(const double *x, long n)
{
    double s = 0.0;
    for (long i = 0; i < n; i++)
        s += x[i] * x[i];
    return sqrt(s);
}

/* F = A X - b (returns |A X|) */
static double linear_residual(const SoilNewton *s, const double *X, const double *b, double *F)
{
    double ax = 0.0;
    for (long i = 0; i < s->N; i++) {
        double f[2] = {0.0, 0.0}, u[2];
        for (int j = 0; j < 3; j++) {
            long nb = i + j - 1;
            if (nb < 0 || nb >= s->N)
                continue;
            mv2(s->A + 12 * i + 4 * j, X + 2 * nb, u);
            f[0] += u[0], f[1] += u[1];
        }
        ax += f[0] * f[0] + f[1] * f[1];
        F[2 * i] = f[0] - b[2 * i];
        F[2 * i + 1] = f[1] - b[2 * i + 1];
    }
    return sqrt(ax);
}

/* J = A + the tangent of m->blocks */
static void tangent(SoilNewton *s)
{
    memcpy(s->J, s->A, (size_t)(12 * s->N) * sizeof(double));
    for (long e = 0; e < s->m->ne; e++) {
        const double *B = s->m->blocks + 4 * e;
        long l = s->gleft[e];
        double lf = s->rfree[2 * e], rf = s->rfree[2 * e + 1];
        for (int k = 0; k < 4; k++) {
            s->J[12 * l + 4 + k] += lf * B[k];
            s->J[12 * l + 8 + k] -= lf * B[k];
            s->J[12 * (l + 1) + 4 + k] += rf * B[k];
            s->J[12 * (l + 1) + k] -= rf * B[k];
        }
    }
    if (s->laws)
        hosted_tangent(s->laws, s->J);
}

/* the soil's part: gather z, the kernel, F += rows; returns the rows' norm */
static double soil_residual(SoilNewton *s, const double *X, double *F, int with_tangent)
{
    MasingSlab *m = s->m;
    double *values = (double *)m->values;
    for (long i = 0; i < m->n; i++) {
        values[2 * i] = X[2 * s->node[i]];
        values[2 * i + 1] = X[2 * s->node[i] + 1];
    }
    double *dQ = m->dQ;
    if (!with_tangent)
        m->dQ = NULL;
    vst_masing_residual(m);
    m->dQ = dQ;
    for (long i = 0; i < m->n; i++) {
        F[2 * s->node[i]] += m->rows[2 * i];
        F[2 * s->node[i] + 1] += m->rows[2 * i + 1];
    }
    return norm(m->rows, 2 * m->n);
}

static double element_norm(const SoilNewton *s)
{
    const MasingSlab *m = s->m;
    double sum = 0.0;
    for (long e = 0; e < m->ne; e++) {
        double f = m->keh[e] * (fabs(m->gamma[e]) + fabs(m->D[2 * e]) + fabs(m->D[2 * e + 1]));
        sum += f * f;
    }
    return m->dt * sqrt(sum);
}

/* factor A + the tangent of m->blocks (kept for a restart) */
void vst_soil_refresh(SoilNewton *s)
{
    memcpy(s->kept_blocks, s->m->blocks, (size_t)(4 * s->m->ne) * sizeof(double));
    tangent(s);
    bands_factor(s->N, s->J, s->Minv, s->Cp);
    s->fresh = 1;
}

void vst_soil_factor_a(SoilNewton *s)
{
    bands_factor(s->N, s->A, s->Ainv, s->ACp);
}

/* Newton from X (A^{-1} b on entry), X becomes the slab's solution; the
 * last kernel call is at the solution (its D, Q, rows close the slab). */
void vst_soil_newton(SoilNewton *s, const double *b, double *X)
{
    const long n2 = 2 * s->N;
    MasingSlab *m = s->m;
    /* the predictor: X -= A^{-1} W r_last */
    memset(s->F, 0, (size_t)n2 * sizeof(double));
    int any = 0;
    for (long i = 0; i < m->n; i++) {
        s->F[2 * s->node[i]] = s->rows_last[2 * i];
        s->F[2 * s->node[i] + 1] = s->rows_last[2 * i + 1];
        any |= s->rows_last[2 * i] != 0.0 || s->rows_last[2 * i + 1] != 0.0;
    }
    if (any) {
        bands_solve(s->N, s->A, s->Ainv, s->ACp, s->F, s->y);
        for (long k = 0; k < n2; k++)
            X[k] -= s->y[k];
    }
    double bnorm = norm(b, n2), axnorm = 0.0, elnorm = 0.0, last = 0.0, lam = 1.0;
    int with_tangent = 1;
    s->converged = 0;
    for (int it = 0; it <= s->max_it; it++) {
        double ax = linear_residual(s, X, b, s->F);
        double rnorm = soil_residual(s, X, s->F, with_tangent);
        double lnorm = s->laws ? hosted_residual(s->laws, X, s->F, with_tangent) : 0.0;
        if (it == 0)
            axnorm = ax, elnorm = element_norm(s);
        double fnorm = norm(s->F, n2);
        s->iterations = it, s->fnorm = fnorm;
        if (!isfinite(fnorm) || (s->laws && s->laws->f.unsettled))
            return;
        double target = fmax(s->atol, s->rtol * (bnorm + axnorm + elnorm + rnorm + lnorm));
        if (fnorm <= target) {
            s->converged = 1;
            return;
        }
        if (it == s->max_it)
            return;
        if (s->laws && it > 0 && fnorm >= last && lam > s->min_step) {
            /* a law switched within the step: half the step back */
            lam *= 0.5;
            for (long k = 0; k < n2; k++)
                X[k] += lam * s->y[k];
            with_tangent = 1;
            continue;
        }
        lam = 1.0;
        int refresh = !s->fresh;
        if (!refresh && it > 0) {
            double rate = fnorm / last;
            refresh = rate >= s->slow || log(target / fnorm) / log(rate) > s->lagged;
        }
        if (refresh && with_tangent)
            vst_soil_refresh(s);
        with_tangent = !(it > 0 && fnorm * (fnorm / last) < 0.01 * target);
        last = fnorm;
        if (s->fresh)
            bands_solve(s->N, s->J, s->Minv, s->Cp, s->F, s->y);
        else
            bands_solve(s->N, s->A, s->Ainv, s->ACp, s->F, s->y);
        for (long k = 0; k < n2; k++)
            X[k] -= s->y[k];
    }
}
