/* The plain Newton of vstpetsc.line.reduced_newton for penalty contact pairs
 * (vstpetsc.line.laws.penalty, vstpetsc.kernels.gap) and the Coulomb friction of
 * pairs (vstpetsc.line.laws.friction, coulomb.h), in C.
 *
 * Same algorithm and the same floating-point operations in the same order
 * as the Python (built with -ffp-contract=off: no fused multiply-adds), so
 * a slab's answer is the Python one bit for bit whenever at most one law
 * acts at a time (a pair with friction is two acting laws); with several acting pairs the step's dense solve is
 * Gaussian elimination here and LAPACK in numpy, equal to rounding
 * (tests/test_native.py checks both).
 *
 * The caller (vstpetsc/line/native/penalty.py) owns every array; nothing is
 * allocated here beyond the stack.
 */
#include <math.h>
#include <string.h>

#include "gap.h"
#include "law_forces.h"

#define MAX_ROWS 64            /* 2 x the laws the kernel takes (32) */

typedef struct {
    int laws;                  /* L pairs: 2L coordinates y */
    int max_it;
    double rtol, atol, dt;
    const double *S;           /* 2L x 2L, row-major */
    double *y0;                /* the law-free coordinates */
    double *y;                 /* in: the start; out: the solution */
    double *gn;                /* the pairs' gaps at t^n */
    const double *w;           /* the pairs' penalties */
    const int *power;          /* 1: the "power" weight T_a, 0: the seed's I_a */
    double *f;                 /* out: f at the last evaluation (2L) */
    double *out;               /* out: the pairs' (f1, f2, t11, t12, t21, t22) (6L) */
    double *integrals;         /* out: the pairs' (G1, G2, W11, W12, W21, W22) (6L) */
    int *hit;                  /* out: whether each pair acted at the last evaluation */
    int iterations;            /* out */
    double norm;               /* out: the last residual's largest entry */
    /* Coulomb friction beside the pairs (kind NULL: pairs only).  A
     * friction law reads its pair's normal force of the same evaluation:
     * its pair comes before it */
    const int *kind;           /* (L) 0 a penalty pair, 1 the friction of pair partner[j] */
    const int *partner;        /* (L) a friction law's pair */
    const double *friction;    /* (5L) a friction law's FRICTION_INPUTS */
    const double *stretch;     /* (L) a friction law's stretch at t^n */
    double *fslab;             /* out: (10L) a friction law's FrictionSlab at the last evaluation */
    int unsettled;             /* out: a friction law's switches did not settle */
} Newton;

/* the laws' arrays of the Newton, as law_forces() reads them */
static LawForces forces_of(const Newton *c)
{
    LawForces f = {c->laws, c->dt, c->gn, c->w, c->power, c->out, c->integrals, c->hit,
                   c->kind, c->partner, c->friction, c->stretch, c->fslab, 0};
    return f;
}

static int is_friction(const Newton *c, int j)
{
    return c->kind != NULL && c->kind[j] != 0;
}

/* the pairs' outputs at y, r = y - y0 + S f and max |S f| (ReducedNewton._residual) */
static double residual(Newton *c, const double *y, double *r, int *any)
{
    int n = 2 * c->laws;
    double sf[MAX_ROWS];
    LawForces forces = forces_of(c);
    *any = law_forces(&forces, y);
    c->unsettled |= forces.unsettled;
    for (int i = 0; i < n; i++)
        sf[i] = 0.0;
    for (int j = 0; j < c->laws; j++) {
        if (!c->hit[j])
            continue;
        double f1 = c->out[6 * j], f2 = c->out[6 * j + 1];
        for (int i = 0; i < n; i++) {
            const double *row = c->S + i * n;
            sf[i] += row[2 * j] * f1 + row[2 * j + 1] * f2;
        }
    }
    for (int i = 0; i < n; i++)
        r[i] = y[i] - c->y0[i] + sf[i];
    return max_abs(sf, n);
}

/* _solve2: 0 when singular */
static int solve2(double m11, double m12, double m21, double m22, double r0, double r1,
                  double *d)
{
    double det = m11 * m22 - m12 * m21;
    if (det == 0.0 || det != det || fabs(det) == INFINITY)
        return 0;
    d[0] = (m22 * r0 - m12 * r1) / det;
    d[1] = (m11 * r1 - m21 * r0) / det;
    return 1;
}

/* d f_c / d y_b (zero across pairs) */
static double tangent(const Newton *c, int b, int cc)
{
    int j = cc / 2;
    if (b / 2 != j || !c->hit[j])
        return 0.0;
    return c->out[6 * j + 2 + 2 * (cc % 2) + b % 2];
}

/* Gaussian elimination with partial pivoting on M (m x m): 0 when singular */
static int solve_dense(double *M, double *x, int m)
{
    for (int k = 0; k < m; k++) {
        int p = k;
        for (int i = k + 1; i < m; i++)
            if (fabs(M[i * m + k]) > fabs(M[p * m + k]))
                p = i;
        if (M[p * m + k] == 0.0 || M[p * m + k] != M[p * m + k])
            return 0;
        if (p != k) {
            for (int jj = 0; jj < m; jj++) {
                double t = M[k * m + jj]; M[k * m + jj] = M[p * m + jj]; M[p * m + jj] = t;
            }
            double t = x[k]; x[k] = x[p]; x[p] = t;
        }
        for (int i = k + 1; i < m; i++) {
            double l = M[i * m + k] / M[k * m + k];
            for (int jj = k; jj < m; jj++)
                M[i * m + jj] -= l * M[k * m + jj];
            x[i] -= l * x[k];
        }
    }
    for (int k = m - 1; k >= 0; k--) {
        double s = x[k];
        for (int jj = k + 1; jj < m; jj++)
            s -= M[k * m + jj] * x[jj];
        x[k] = s / M[k * m + k];
    }
    for (int k = 0; k < m; k++)
        if (!isfinite(x[k]))
            return 0;
    return 1;
}

/* the step with several acting pairs (ReducedNewton._step's general branch) */
static int step_many(Newton *c, const double *r, double *step, const int *rows, int m)
{
    int n = 2 * c->laws;
    double M[MAX_ROWS * MAX_ROWS], d[MAX_ROWS], jd[MAX_ROWS];
    for (int ia = 0; ia < m; ia++) {
        for (int ib = 0; ib < m; ib++) {
            double s = 0.0;
            for (int ic = 0; ic < m; ic++)
                s += c->S[rows[ia] * n + rows[ic]] * tangent(c, rows[ib], rows[ic]);
            M[ia * m + ib] = (double)(rows[ia] == rows[ib]) + s;
        }
        d[ia] = r[rows[ia]];
    }
    if (!solve_dense(M, d, m))
        return 0;
    memcpy(step, r, n * sizeof(double));
    int in_rows[MAX_ROWS] = {0};
    for (int ic = 0; ic < m; ic++) {
        double s = 0.0;
        for (int ib = 0; ib < m; ib++)
            s += tangent(c, rows[ib], rows[ic]) * d[ib];
        jd[ic] = s;
        step[rows[ic]] = d[ic];
        in_rows[rows[ic]] = 1;
    }
    for (int i = 0; i < n; i++) {
        if (in_rows[i])
            continue;
        double s = 0.0;
        for (int ic = 0; ic < m; ic++)
            s += c->S[i * n + rows[ic]] * jd[ic];
        step[i] = r[i] - s;
    }
    return 1;
}

/* (I + S f'(y))^-1 r (ReducedNewton._step and _step_one): 0 when singular */
static int newton_step(Newton *c, const double *r, double *step)
{
    int n = 2 * c->laws, rows[MAX_ROWS], m = 0, j = -1;
    for (int k = 0; k < c->laws; k++)
        if (c->hit[k]) {
            rows[m++] = 2 * k; rows[m++] = 2 * k + 1; j = k;
        }
    if (m == 0) {
        memcpy(step, r, n * sizeof(double));
        return 1;
    }
    if (m > 2)
        return step_many(c, r, step, rows, m);
    const double *S = c->S, *o = c->out + 6 * j;
    int a = 2 * j, b = 2 * j + 1;
    double t11 = o[2], t12 = o[3], t21 = o[4], t22 = o[5], d[2];
    if (!solve2(1.0 + S[a * n + a] * t11 + S[a * n + b] * t21,
                S[a * n + a] * t12 + S[a * n + b] * t22,
                S[b * n + a] * t11 + S[b * n + b] * t21,
                1.0 + S[b * n + a] * t12 + S[b * n + b] * t22, r[a], r[b], d))
        return 0;
    double jd1 = t11 * d[0] + t12 * d[1], jd2 = t21 * d[0] + t22 * d[1];
    for (int i = 0; i < n; i++)
        step[i] = r[i] - S[i * n + a] * jd1 - S[i * n + b] * jd2;
    step[a] = d[0];
    step[b] = d[1];
    return 1;
}

/* f at the last evaluation (ReducedNewton._keep) */
static void keep(Newton *c)
{
    for (int j = 0; j < c->laws; j++) {
        c->f[2 * j] = c->hit[j] ? c->out[6 * j] : 0.0;
        c->f[2 * j + 1] = c->hit[j] ? c->out[6 * j + 1] : 0.0;
    }
}

/* ReducedNewton.solve: 0 converged, 1 not (c->norm, c->iterations set),
 * 3 a friction law's switches did not settle (the Python's ArithmeticError) */
int vst_penalty_newton(Newton *c, int from_start)
{
    int n = 2 * c->laws, any;
    double r[MAX_ROWS], step[MAX_ROWS], trial[MAX_ROWS];
    if (c->laws < 1 || n > MAX_ROWS)
        return 2;
    c->unsettled = 0;
    if (!from_start)
        memcpy(c->y, c->y0, n * sizeof(double));
    double sf = residual(c, c->y, r, &any);
    if (from_start && !any) {
        /* a start where no pair acts: its step would go straight back to y0 */
        memcpy(c->y, c->y0, n * sizeof(double));
        sf = residual(c, c->y, r, &any);
    }
    if (c->unsettled)
        return 3;
    double size = max_abs(c->y0, n), norm = max_abs(r, n);
    for (int it = 0; it <= c->max_it; it++) {
        if (norm <= fmax(c->atol, c->rtol * (size + sf))) {
            c->iterations = it;
            c->norm = norm;
            keep(c);
            return 0;
        }
        if (it == c->max_it || !newton_step(c, r, step))
            break;
        /* ReducedNewton._line: full step, halved while the residual grows */
        double lam = 1.0, fresh = norm;
        for (int h = 0; h < 20; h++) {
            for (int i = 0; i < n; i++)
                trial[i] = c->y[i] - lam * step[i];
            sf = residual(c, trial, r, &any);
            if (c->unsettled)
                return 3;
            fresh = max_abs(r, n);
            if (fresh < norm || lam < 1e-5)
                break;
            lam *= 0.5;
        }
        memcpy(c->y, trial, n * sizeof(double));
        norm = fresh;
    }
    c->iterations = c->max_it;
    c->norm = norm;
    keep(c);
    return 1;
}

/* A whole slab of the pairs (LawSolver.solve with LawSet.start_slab,
 * Coupling.coordinates and the work sums): the gaps at t^n from the nodes'
 * displacements, the law-free coordinates y0 = R0 x_E, whether any pair
 * closes, the start guess y0 - S f_prev and the Newton; on one rank also
 * x_E read from x and, once converged, x -= sum f_j Zred_j. */
typedef struct {
    int nodes;                 /* k: the pairs' nodes */
    int acted;                 /* whether a pair acted in the previous slab */
    double *u;                 /* (k) the nodes' displacements at t^n */
    const int *node;           /* (2L) pair j's nodes (-1: none) */
    const double *sign;        /* (2L) their signs */
    const double *g0;          /* (L) initial gaps */
    const double *R0;          /* (2L x 2k) y = R0 x_E */
    double *xE;                /* (2k) the slab's unknowns at the pairs' dofs */
    double *f_prev;            /* (2L) the pairs' terms of the previous slab; out: this one's */
    double *work;              /* out: (L) f . y of each pair */
    int ran;                   /* out: whether a pair acts (Newton ran) */
    /* on one rank (serial): the solver's arrays, read and written here
     * (Coupling.unknowns, LawInfluence.subtract, LawSolver.advance) */
    int serial;
    double *x;                 /* the slab's unknowns (the solver's array) */
    double *b;                 /* the running right-hand side */
    const int *local;          /* (2k) the pairs' dofs in x and b */
    const double *carry;       /* (2k x 2L) b[local] += carry f after a slab that acted */
    int groups;                /* LawInfluence's groups: */
    const int *span;           /* (2 groups) each one's [lo, hi) in x */
    const int *first;          /* (groups + 1) its columns: cols[first[g] .. first[g + 1]) */
    const int *cols;
    const double *const *Z;    /* (2L) the columns Zred over x */
    int *pieces;               /* out: (L) how many pieces of the slab each pair acted on */
    double *ends;              /* out: (6L) their (p, q) in [0, 1] (PenaltyContact.finish_slab) */
} Slab;

/* Each acting pair's pieces of the slab at its converged rates y */
static void pair_pieces(const Newton *c, Slab *s)
{
    for (int j = 0; j < c->laws; j++) {
        double a[3];
        if (!c->hit[j] || is_friction(c, j)) {
            s->pieces[j] = 0;
            continue;
        }
        gap_coefficients(c->gn[j], c->y[2 * j], c->y[2 * j + 1], c->dt, a);
        s->pieces[j] = active_intervals(a, s->ends + 6 * j);
    }
}

/* x[lo, hi) += a_0 Z_0 + ... + a_{m-1} Z_{m-1}, the sums grouped as
 * PETSc's VecMAXPY_Seq groups them (the remainder of m / 4 first, then
 * fours), so that the result is LawInfluence.subtract's */
static void maxpy(double *x, int lo, int hi, int m, const double *a, const double *const *z)
{
    int rem = m & 3, j = 0;
    if (rem == 3) {
        for (int i = lo; i < hi; i++)
            x[i] += a[0] * z[0][i] + a[1] * z[1][i] + a[2] * z[2][i];
    } else if (rem == 2) {
        for (int i = lo; i < hi; i++)
            x[i] += a[0] * z[0][i] + a[1] * z[1][i];
    } else if (rem == 1) {
        for (int i = lo; i < hi; i++)
            x[i] += a[0] * z[0][i];
    }
    for (j = rem; j < m; j += 4)
        for (int i = lo; i < hi; i++)
            x[i] += a[j] * z[j][i] + a[j + 1] * z[j + 1][i] + a[j + 2] * z[j + 2][i]
                + a[j + 3] * z[j + 3][i];
}

/* x -= sum_j f_j Zred_j over each group's span (LawInfluence.subtract) */
static void subtract_influence(const Slab *s, const double *f)
{
    double a[MAX_ROWS];
    const double *z[MAX_ROWS];
    for (int g = 0; g < s->groups; g++) {
        int m = 0;
        for (int c = s->first[g]; c < s->first[g + 1]; c++, m++) {
            a[m] = -f[s->cols[c]];
            z[m] = s->Z[s->cols[c]];
        }
        maxpy(s->x, s->span[2 * g], s->span[2 * g + 1], m, a, z);
    }
}

/* The end of a slab for the pairs (LawSolver.advance): u += z_2 at their
 * nodes, and after a slab where a pair acted b[local] += carry f_prev */
void vst_penalty_advance(const Newton *c, Slab *s, int acted)
{
    int k = s->nodes, n = 2 * c->laws;
    for (int i = 0; i < k; i++)
        s->u[i] += s->x[s->local[2 * i + 1]];
    if (!acted)
        return;
    for (int m = 0; m < 2 * k; m++) {
        double v = 0.0;
        for (int i = 0; i < n; i++)
            v += s->carry[m * n + i] * s->f_prev[i];
        s->b[s->local[m]] += v;
    }
}

int vst_penalty_slab(Newton *c, Slab *s)
{
    int L = c->laws, n = 2 * L, k2 = 2 * s->nodes, any = 0;
    if (L < 1 || n > MAX_ROWS)
        return 2;
    if (s->serial)             /* Coupling.unknowns */
        for (int m = 0; m < k2; m++)
            s->xE[m] = s->x[s->local[m]];
    for (int j = 0; j < L; j++) {
        if (is_friction(c, j))   /* CoulombFriction.start_slab: nothing */
            continue;
        /* PairLaw.start_slab: g0 - signs . u (every pair has a first node) */
        double moved = s->sign[2 * j] * s->u[s->node[2 * j]];
        if (s->node[2 * j + 1] >= 0)
            moved += s->sign[2 * j + 1] * s->u[s->node[2 * j + 1]];
        c->gn[j] = s->g0[j] - moved;
    }
    for (int i = 0; i < n; i++) {
        double y = 0.0;
        for (int m = 0; m < k2; m++)
            y += s->R0[i * k2 + m] * s->xE[m];
        c->y0[i] = y;
    }
    for (int j = 0; j < L && !any; j++) {          /* LawSet.acts */
        double a[3];
        if (is_friction(c, j))   /* friction acts only where its pair does */
            continue;
        gap_coefficients(c->gn[j], c->y0[2 * j], c->y0[2 * j + 1], c->dt, a);
        any = closed_somewhere(a[0], a[1], a[2]);
    }
    s->ran = any;
    if (!any) {                /* the pairs give nothing (LawSet.evaluate at y0) */
        for (int j = 0; j < L; j++)
            c->hit[j] = 0;
        keep(c);
        return 0;
    }
    if (s->acted)
        for (int i = 0; i < n; i++) {
            double sf = 0.0;
            for (int m = 0; m < n; m++)
                sf += c->S[i * n + m] * s->f_prev[m];
            c->y[i] = c->y0[i] - sf;
        }
    int code = vst_penalty_newton(c, s->acted);
    for (int j = 0; j < L; j++)
        s->work[j] = c->f[2 * j] * c->y[2 * j] + c->f[2 * j + 1] * c->y[2 * j + 1];
    if (code != 0)
        return code;
    pair_pieces(c, s);
    memcpy(s->f_prev, c->f, n * sizeof(double));
    if (s->serial)
        subtract_influence(s, c->f);
    return 0;
}
