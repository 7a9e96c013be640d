/* The slab integrals of a hysteretic soil (MKZ backbone, extended Masing
 * rules) element by element: the same operations, in the same order, as
 * vstpetsc/materials/masing.py (slab_integrals, SlabPath.end), which stays
 * the checked reference (-vst_native 0).  See docs/nonlinear-soil.md.
 *
 * An element's path through the slab: strain gamma(theta) = gn + (theta -
 * theta^2/2) D1 + theta^2/2 D2, cut where its rate turns (clipped to 0 or 1
 * when it does not), a 3-point Gauss rule on each piece, reversal points
 * pushed at a turn at the slab start and at the cut. */

#include <math.h>
#include <string.h>

#define GP 3

#include "masing.h"

static inline double sgn(double x) { return (x > 0.0) - (x < 0.0); }

static inline void backbone(const MasingSlab *m, long e, double g, double *f, double *slope)
{
    double bx = m->beta[e] * pow(fabs(g) / m->gref[e], m->s[e]);
    double den = 1.0 + bx;
    *f = m->G[e] * g / den;
    *slope = m->G[e] * (1.0 + (1.0 - m->s[e]) * bx) / (den * den);
}

/* the depth in use at strain g reached monotonically in direction d */
static long depth_at(const double *lg, long k, double g, double d)
{
    while (k > 0) {
        double target = k >= 2 ? lg[k - 2] : -lg[0];
        if (d * (g - target) >= 0.0)
            k = k >= 2 ? k - 2 : 0;
        else
            break;
    }
    return k;
}

static void stress(const MasingSlab *m, long e, const double *lg, const double *lt, long k,
                   double g, double *tau, double *slope)
{
    double f;
    if (k == 0) {
        backbone(m, e, g, tau, slope);
        return;
    }
    backbone(m, e, 0.5 * (g - lg[k - 1]), &f, slope);
    *tau = lt[k - 1] + 2.0 * f;
}

/* push (g, t) at depth *k; a full stack forgets its oldest pair above R_1 */
static void push(double *lg, double *lt, long *k, int depth, double g, double t)
{
    if (*k >= depth) {
        memmove(lg + 1, lg + 3, (size_t)(depth - 3) * sizeof(double));
        memmove(lt + 1, lt + 3, (size_t)(depth - 3) * sizeof(double));
        *k -= 2;
    }
    lg[*k] = g;
    lt[*k] = t;
    *k += 1;
}

static inline double strain(double gn, double D1, double D2, double th)
{
    double t2 = 0.5 * th * th;
    return gn + (th - t2) * D1 + t2 * D2;
}

/* one element's path through the slab (SlabPath of masing.py) */
typedef struct {
    double gn, D1, D2, A, kh, cut, d1, d2, tc, slope_c;
    int reverses, has[2];
    long k, k2;                               /* depth at the start, after the turn */
    double *lg, *lt;                          /* its stack (a copy) */
    double tau[2][GP], slope[2][GP], th[2][GP], g[2][GP];
    int new_branch[GP];
} Path;

/* the pieces' cut, directions and the start's stack (a turn at the slab
 * start pushes the start point) */
static void path_start(const MasingSlab *m, long e, Path *p)
{
    p->gn = m->gamma[e], p->D1 = m->D[2 * e], p->D2 = m->D[2 * e + 1];
    p->A = m->area[e], p->kh = m->keh[e];
    p->reverses = p->D1 * p->D2 < 0.0;
    const double diff = p->D1 - p->D2;
    double cut = diff != 0.0 ? p->D1 / diff : 1.0;
    p->cut = diff == 0.0 ? 1.0 : (cut < 0.0 ? 0.0 : (cut > 1.0 ? 1.0 : cut));
    const double rate = p->D1 != 0.0 ? p->D1 : p->D2;
    p->d1 = rate != 0.0 ? sgn(rate) : m->dir[e];
    p->d2 = p->reverses ? -p->d1 : p->d1;
    p->k = m->k[e];
    memcpy(p->lg, m->sg + e * m->depth, (size_t)p->k * sizeof(double));
    memcpy(p->lt, m->st + e * m->depth, (size_t)p->k * sizeof(double));
    if (m->dir[e] != 0.0 && p->d1 != m->dir[e])
        push(p->lg, p->lt, &p->k, m->depth, p->gn, m->tau[e]);
    p->has[0] = p->cut > 0.0, p->has[1] = p->cut < 1.0;
}

/* stress and slope at piece j's Gauss points (a piece of length 0, in a
 * slab that does not turn, adds exact zeros in the Python reference and
 * is skipped); the turn pushes its point between the two pieces */
static void path_points(const MasingSlab *m, long e, Path *p)
{
    long kc = p->k;
    p->tc = p->slope_c = 0.0;
    if (p->reverses) {
        const double gc = strain(p->gn, p->D1, p->D2, p->cut);
        kc = depth_at(p->lg, p->k, gc, p->d1);
        stress(m, e, p->lg, p->lt, kc, gc, &p->tc, &p->slope_c);
    }
    for (int j = 0; j < 2; j++) {
        if (j == 1) {
            p->k2 = p->k;
            if (p->reverses) {
                p->k2 = kc;
                push(p->lg, p->lt, &p->k2, m->depth, strain(p->gn, p->D1, p->D2, p->cut), p->tc);
            }
        }
        if (!p->has[j])
            continue;
        const long k0 = j == 0 ? p->k : p->k2;
        const double d = j == 0 ? p->d1 : p->d2;
        for (int q = 0; q < GP; q++) {
            double th = j == 0 ? p->cut * m->xg[q] : p->cut + (1.0 - p->cut) * m->xg[q];
            double g = strain(p->gn, p->D1, p->D2, th);
            long kq = depth_at(p->lg, k0, g, d);
            stress(m, e, p->lg, p->lt, kq, g, &p->tau[j][q], &p->slope[j][q]);
            p->th[j][q] = th, p->g[j][q] = g;
            if (j == 1)
                p->new_branch[q] = p->reverses && kq == p->k2;
        }
    }
}

/* piece j's Gauss sums: Q_a, dQ_a/dD_b at a fixed cut (the turning
 * point's strain enters the new branch) and d/d theta* of the sums */
static void piece_sums(const MasingSlab *m, const Path *p, int j, double Q[2], double dQ[2][2],
                       double dQcut[2])
{
    const double len = j == 0 ? p->cut : 1.0 - p->cut, A = p->A, kh = p->kh;
    const double ic[2] = {p->cut - 0.5 * p->cut * p->cut, 0.5 * p->cut * p->cut};
    for (int a = 0; a < 2; a++) {
        double sum = 0.0, sb[2] = {0.0, 0.0}, scut = 0.0, sign = a == 0 ? -1.0 : 1.0;
        for (int q = 0; q < GP; q++) {
            double th = p->th[j][q], T = a == 0 ? 1.0 - th : th;
            double c = A * p->tau[j][q] - kh * p->g[j][q], dc = A * p->slope[j][q] - kh;
            sum += len * m->wg[q] * T * c;
            for (int b = 0; b < 2; b++) {
                double ib = b == 0 ? th - 0.5 * th * th : 0.5 * th * th;
                double integrand = dc * ib;
                if (j == 1 && p->reverses)
                    integrand += (p->new_branch[q] ? A * (p->slope_c - p->slope[j][q]) : 0.0) * ic[b];
                sb[b] += len * m->wg[q] * T * integrand;
            }
            double r = (1.0 - th) * p->D1 + th * p->D2;
            double df = sign * c + T * (dc * r);
            double moves = j == 0 ? m->xg[q] : 1.0 - m->xg[q];
            scut += m->wg[q] * ((j == 0 ? 1.0 : -1.0) * T * c + len * moves * df);
        }
        Q[a] += sum;
        dQ[a][0] += sb[0], dQ[a][1] += sb[1];
        if (p->reverses)
            dQcut[a] += scut;
    }
}

/* the state at the slab end into the end buffers (reused: nothing stale
 * beyond the depth) */
static void path_end(const MasingSlab *m, long e, const Path *p)
{
    double g1 = strain(p->gn, p->D1, p->D2, 1.0), t1, unused;
    long ke = depth_at(p->lg, p->k2, g1, p->d2);
    stress(m, e, p->lg, p->lt, ke, g1, &t1, &unused);
    m->gamma1[e] = g1, m->tau1[e] = t1, m->dir1[e] = p->d2, m->k1[e] = ke;
    memcpy(m->sg1 + e * m->depth, p->lg, (size_t)ke * sizeof(double));
    memcpy(m->st1 + e * m->depth, p->lt, (size_t)ke * sizeof(double));
    memset(m->sg1 + e * m->depth + ke, 0, (size_t)(m->depth - ke) * sizeof(double));
    memset(m->st1 + e * m->depth + ke, 0, (size_t)(m->depth - ke) * sizeof(double));
}

/* one element; lg, lt: scratch of depth doubles each */
static void element(const MasingSlab *m, long e, double *lg, double *lt)
{
    Path p;
    p.lg = lg, p.lt = lt;
    path_start(m, e, &p);
    path_points(m, e, &p);
    double Q[2] = {0.0, 0.0}, dQ[2][2] = {{0.0, 0.0}, {0.0, 0.0}}, dQcut[2] = {0.0, 0.0};
    for (int j = 0; j < 2; j++)
        if (p.has[j])
            piece_sums(m, &p, j, Q, dQ, dQcut);
    m->Q[2 * e] = m->dt * Q[0];
    m->Q[2 * e + 1] = m->dt * Q[1];
    if (m->dQ) {
        double dcut[2] = {0.0, 0.0};
        if (p.reverses) {
            double den = (p.D1 - p.D2) * (p.D1 - p.D2);
            dcut[0] = -p.D2 / den, dcut[1] = p.D1 / den;
        }
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 2; b++)
                m->dQ[4 * e + 2 * a + b] = m->dt * (dQ[a][b] + dQcut[a] * dcut[b]);
    }
    if (m->gamma1)
        path_end(m, e, &p);
}

static void tangent_blocks(MasingSlab *m);
static void tangent_data(MasingSlab *m);

/* W r and the tangent's element blocks from the unknowns z of the soil's
 * nodes: v = V z per node, D_b = (dt/h)(v_right - v_left), the slab
 * integrals, forces -Q on the left and +Q on the right node. */
void vst_masing_residual(MasingSlab *m)
{
    const double *V = m->V, *W = m->W;
    double *D = (double *)m->D;
    for (long e = 0; e < m->ne; e++) {
        const double *zl = m->values + 2 * m->left[e], *zr = zl + 2;
        for (int a = 0; a < 2; a++) {
            double vl = zl[0] * V[2 * a] + zl[1] * V[2 * a + 1];
            double vr = zr[0] * V[2 * a] + zr[1] * V[2 * a + 1];
            D[2 * e + a] = (vr - vl) * m->scale[e];
        }
    }
    double lg[256], lt[256];
    for (long e = 0; e < m->ne; e++)
        element(m, e, lg, lt);
    memset(m->rows, 0, (size_t)(2 * m->n) * sizeof(double));
    for (long e = 0; e < m->ne; e++) {
        long l = m->left[e];
        for (int a = 0; a < 2; a++) {
            m->rows[2 * l + a] -= m->Q[2 * e + a];
            m->rows[2 * (l + 1) + a] += m->Q[2 * e + a];
        }
    }
    for (long i = 0; i < m->n; i++) {
        double f0 = m->rows[2 * i] * m->free[i], f1 = m->rows[2 * i + 1] * m->free[i];
        m->rows[2 * i] = W[0] * f0 + W[1] * f1;
        m->rows[2 * i + 1] = W[2] * f0 + W[3] * f1;
    }
    if (!m->blocks || !m->dQ)
        return;
    tangent_blocks(m);
    if (m->pdata)
        tangent_data(m);
}

static void tangent_blocks(MasingSlab *m)
{
    const double *V = m->V, *W = m->W;
    for (long e = 0; e < m->ne; e++) {
        const double *T = m->dQ + 4 * e;
        double S[4], WS[4];
        for (int i = 0; i < 4; i++)
            S[i] = m->scale[e] * T[i];
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 2; b++)
                WS[2 * a + b] = W[2 * a] * S[b] + W[2 * a + 1] * S[2 + b];
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 2; b++)
                m->blocks[4 * e + 2 * a + b] = WS[2 * a] * V[b] + WS[2 * a + 1] * V[2 + b];
    }
}

static void tangent_data(MasingSlab *m)
{
    memcpy(m->pdata, m->pbase, (size_t)(4 * m->nb) * sizeof(double));
    for (int key = 0; key < 4; key++) {
        for (long e = 0; e < m->ne; e++) {
            long slot = m->slots[key * m->ne + e];
            if (slot < 0)
                continue;
            double c = m->pcoef[key * m->ne + e];
            for (int i = 0; i < 4; i++)
                m->pdata[4 * slot + i] += c * m->blocks[4 * e + i];
        }
    }
}

void vst_masing_slab(const MasingSlab *m)
{
    double lg[256], lt[256];
    for (long e = 0; e < m->ne; e++)
        element(m, e, lg, lt);
}
