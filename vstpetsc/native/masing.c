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

/* one element; lg, lt: scratch of depth doubles each */
static void element(const MasingSlab *m, long e, double *lg, double *lt)
{
    const double gn = m->gamma[e], D1 = m->D[2 * e], D2 = m->D[2 * e + 1];
    const double A = m->area[e], kh = m->keh[e];
    const int reverses = D1 * D2 < 0.0;
    const double diff = D1 - D2;
    double cut = diff != 0.0 ? D1 / diff : 1.0;
    cut = diff == 0.0 ? 1.0 : (cut < 0.0 ? 0.0 : (cut > 1.0 ? 1.0 : cut));
    const double rate = D1 != 0.0 ? D1 : D2;
    const double d1 = rate != 0.0 ? sgn(rate) : m->dir[e];
    const double d2 = reverses ? -d1 : d1;
    long k = m->k[e];
    memcpy(lg, m->sg + e * m->depth, (size_t)k * sizeof(double));
    memcpy(lt, m->st + e * m->depth, (size_t)k * sizeof(double));
    if (m->dir[e] != 0.0 && d1 != m->dir[e])
        push(lg, lt, &k, m->depth, gn, m->tau[e]);

    double Q[2] = {0.0, 0.0}, dQ[2][2] = {{0.0, 0.0}, {0.0, 0.0}}, dQcut[2] = {0.0, 0.0};
    const double ic[2] = {cut - 0.5 * cut * cut, 0.5 * cut * cut};
    /* the turning point (only where the strain turns inside the slab) */
    double tc = 0.0, slope_c = 0.0;
    long kc = k;
    if (reverses) {
        const double gc = strain(gn, D1, D2, cut);
        kc = depth_at(lg, k, gc, d1);
        stress(m, e, lg, lt, kc, gc, &tc, &slope_c);
    }

    /* the first piece from the start's stack; the second from the stack
     * after the turn (pushed only where the strain turns inside); a piece
     * of length 0 (a slab that does not turn) adds exact zeros in the
     * Python reference and is skipped here */
    double tau_p[2][GP], slope_p[2][GP], th_p[2][GP], g_p[2][GP];
    int new_branch[GP] = {0};
    const int has[2] = {cut > 0.0, cut < 1.0};
    if (has[0]) {
        for (int q = 0; q < GP; q++) {
            double th = cut * m->xg[q];
            double g = strain(gn, D1, D2, th);
            long kq = depth_at(lg, k, g, d1);
            stress(m, e, lg, lt, kq, g, &tau_p[0][q], &slope_p[0][q]);
            th_p[0][q] = th;
            g_p[0][q] = g;
        }
    }
    long k2 = k;
    if (reverses) {
        k2 = kc;
        push(lg, lt, &k2, m->depth, strain(gn, D1, D2, cut), tc);
    }
    if (has[1]) {
        for (int q = 0; q < GP; q++) {
            double th = cut + (1.0 - cut) * m->xg[q];
            double g = strain(gn, D1, D2, th);
            long kq = depth_at(lg, k2, g, d2);
            stress(m, e, lg, lt, kq, g, &tau_p[1][q], &slope_p[1][q]);
            th_p[1][q] = th;
            g_p[1][q] = g;
            new_branch[q] = reverses && kq == k2;
        }
    }

    for (int j = 0; j < 2; j++) {
        if (!has[j])
            continue;
        const double len = j == 0 ? cut : 1.0 - cut;
        for (int a = 0; a < 2; a++) {
            double sum = 0.0;
            for (int q = 0; q < GP; q++) {
                double th = th_p[j][q];
                double T = a == 0 ? 1.0 - th : th;
                double c = A * tau_p[j][q] - kh * g_p[j][q];
                sum += len * m->wg[q] * T * c;
            }
            Q[a] += sum;
        }
        if (!m->dQ)
            continue;
        for (int a = 0; a < 2; a++) {
            for (int b = 0; b < 2; b++) {
                double sum = 0.0;
                for (int q = 0; q < GP; q++) {
                    double th = th_p[j][q];
                    double T = a == 0 ? 1.0 - th : th;
                    double ib = b == 0 ? th - 0.5 * th * th : 0.5 * th * th;
                    double integrand = (A * slope_p[j][q] - kh) * ib;
                    if (j == 1 && reverses)
                        integrand += (new_branch[q] ? A * (slope_c - slope_p[j][q]) : 0.0) * ic[b];
                    sum += len * m->wg[q] * T * integrand;
                }
                dQ[a][b] += sum;
            }
        }
        if (reverses) {       /* d/d theta* of this piece's Gauss sums */
            const double moves_sign = j == 0 ? 1.0 : -1.0;
            for (int a = 0; a < 2; a++) {
                double sum = 0.0, sign = a == 0 ? -1.0 : 1.0;
                for (int q = 0; q < GP; q++) {
                    double th = th_p[j][q];
                    double T = a == 0 ? 1.0 - th : th;
                    double c = A * tau_p[j][q] - kh * g_p[j][q];
                    double r = (1.0 - th) * D1 + th * D2;
                    double df = sign * c + T * ((A * slope_p[j][q] - kh) * r);
                    double moves = j == 0 ? m->xg[q] : 1.0 - m->xg[q];
                    sum += m->wg[q] * (moves_sign * T * c + len * moves * df);
                }
                dQcut[a] += sum;
            }
        }
    }
    m->Q[2 * e] = m->dt * Q[0];
    m->Q[2 * e + 1] = m->dt * Q[1];
    if (m->dQ) {
        double dcut[2] = {0.0, 0.0};
        if (reverses) {
            double den = diff * diff;
            dcut[0] = -D2 / den;
            dcut[1] = D1 / den;
        }
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 2; b++)
                m->dQ[4 * e + 2 * a + b] = m->dt * (dQ[a][b] + dQcut[a] * dcut[b]);
    }
    if (m->gamma1) {          /* the state at the slab end */
        double g1 = strain(gn, D1, D2, 1.0), t1, unused;
        long ke = depth_at(lg, k2, g1, d2);
        stress(m, e, lg, lt, ke, g1, &t1, &unused);
        m->gamma1[e] = g1;
        m->tau1[e] = t1;
        m->dir1[e] = d2;
        m->k1[e] = ke;
        memcpy(m->sg1 + e * m->depth, lg, (size_t)ke * sizeof(double));
        memcpy(m->st1 + e * m->depth, lt, (size_t)ke * sizeof(double));
        /* the buffers are reused: nothing stale beyond the depth */
        memset(m->sg1 + e * m->depth + ke, 0, (size_t)(m->depth - ke) * sizeof(double));
        memset(m->st1 + e * m->depth + ke, 0, (size_t)(m->depth - ke) * sizeof(double));
    }
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
