/* The slab integrals of the plane-strain MKZ-Masing law, point by point:
 * the operations of vstpetsc/materials/deviatoric_slab.py (slab_integrals,
 * SlabPath, cut_terms) and deviatoric.py (DeviatorStack, branch), which
 * stay the checked reference (-vst_native 0; tests/test_deviatoric_native.py).
 * See docs/nonlinear-soil.md section 7.
 *
 * A point's strain in the slab is eps(theta) = eps_n + (theta - theta^2/2)
 * D1 + theta^2/2 D2; the path is cut where the rate's component along the
 * slab start's heading n0 turns (clipped to 0 or 1 when it does not), each
 * piece has a 3-point Gauss rule, a reversal at the slab start or at the
 * cut pushes a point on a copy of the point's stack.  The heading n0 (a
 * virgin point's from D1) is formed by the Python side. */

#include <math.h>
#include <string.h>

#include "deviatoric.h"

#define GP 3
#define MAXDEPTH 64

static double SQ2, SQ6, TO[3][3], FROM[3][3];

static void constants(void)
{
    SQ2 = sqrt(2.0);
    SQ6 = sqrt(6.0);
    double to[3][3] = {{1.0 / SQ2, -1.0 / SQ2, 0.0}, {1.0 / SQ6, 1.0 / SQ6, 0.0},
                       {0.0, 0.0, 1.0 / SQ2}};
    double from[3][3] = {{1.0 / SQ2, 1.0 / SQ6, 0.0}, {-1.0 / SQ2, 1.0 / SQ6, 0.0},
                         {0.0, 0.0, 1.0 / SQ2}};
    memcpy(TO, to, sizeof TO);
    memcpy(FROM, from, sizeof FROM);
}

/* a point's reversal stack: deviators c, stress deviators s (depth x 3) */
typedef struct {
    double *c, *s;
    long k;
} Stack;

typedef struct {
    double G, gref, beta, s, K;
} Law;

static inline void deviator(const double *e, double *c)
{
    c[0] = (e[0] - e[1]) / SQ2;
    c[1] = (e[0] + e[1]) / SQ6;
    c[2] = e[2] / SQ2;
}

static inline double norm3(const double *v) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* (s - s_k, ds/dc) at the distance delta from the branch's origin */
static void branch(const Law *L, const double *delta, double divisor, double *ds, double t[3][3])
{
    double r = norm3(delta);
    double a = SQ2 * r / divisor;
    double bx = L->beta * pow(a / L->gref, L->s);
    double secant = 2.0 * L->G / (1.0 + bx);
    double den = 1.0 + bx;
    double slope = L->G * (1.0 + (1.0 - L->s) * bx) / (den * den);
    double r2 = r * r, inv = r2 > 0.0 ? r2 : 1.0;
    for (int i = 0; i < 3; i++) {
        ds[i] = secant * delta[i];
        for (int j = 0; j < 3; j++)
            t[i][j] = (i == j ? secant : 0.0) + (2.0 * slope - secant) * (delta[i] * delta[j] / inv);
    }
}

static long depth_at(const Stack *st, const double *c)
{
    long k = st->k;
    while (k > 0) {
        const double *ck = st->c + 3 * (k - 1);
        double d1[3], d2[3];
        for (int i = 0; i < 3; i++) {
            d1[i] = c[i] - ck[i];
            d2[i] = (k >= 2 ? st->c[3 * (k - 2) + i] : -ck[i]) - ck[i];
        }
        if (!(norm3(d1) >= norm3(d2)))
            break;
        k = k >= 2 ? k - 2 : 0;
    }
    return k;
}

/* in-plane stresses (3), d sigma/d eps (3 x 3) and the stress deviator at
 * strain e on the branch of depth k of st */
static void evaluate(const Law *L, const Stack *st, const double *e, long k, double *sigma,
                     double tan[3][3], double *sdev)
{
    double c[3], delta[3], ds[3], t[3][3], ft[3][3];
    int on = k == 0;
    deviator(e, c);
    for (int i = 0; i < 3; i++)
        delta[i] = on ? c[i] : c[i] - st->c[3 * (k - 1) + i];
    branch(L, delta, on ? 1.0 : 2.0, ds, t);
    for (int i = 0; i < 3; i++)
        sdev[i] = on ? ds[i] : st->s[3 * (k - 1) + i] + ds[i];
    double p = L->K * (e[0] + e[1]);
    sigma[0] = p + sdev[0] / SQ2 + sdev[1] / SQ6;
    sigma[1] = p - sdev[0] / SQ2 + sdev[1] / SQ6;
    sigma[2] = sdev[2] / SQ2;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            ft[i][j] = FROM[i][0] * t[0][j] + FROM[i][1] * t[1][j] + FROM[i][2] * t[2][j];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            tan[i][j] = ft[i][0] * TO[0][j] + ft[i][1] * TO[1][j] + ft[i][2] * TO[2][j]
                + (i < 2 && j < 2 ? L->K : 0.0);
}

/* a copy of src in the buffers c, s with (cp, sp) pushed (masing.push_points) */
static void pushed(const Stack *src, int depth, double *c, double *s, long k,
                   const double *cp, const double *sp, Stack *out)
{
    memcpy(c, src->c, (size_t)(3 * depth) * sizeof(double));
    memcpy(s, src->s, (size_t)(3 * depth) * sizeof(double));
    if (k >= depth) {
        memmove(c + 3, c + 9, (size_t)(3 * (depth - 3)) * sizeof(double));
        memmove(s + 3, s + 9, (size_t)(3 * (depth - 3)) * sizeof(double));
        k -= 2;
    }
    memcpy(c + 3 * k, cp, 3 * sizeof(double));
    memcpy(s + 3 * k, sp, 3 * sizeof(double));
    out->c = c;
    out->s = s;
    out->k = k + 1;
}

static inline void strain(const double *en, const double *D1, const double *D2, double th,
                          double *e)
{
    double t2 = 0.5 * th * th;
    for (int i = 0; i < 3; i++)
        e[i] = en[i] + (th - t2) * D1[i] + t2 * D2[i];
}

/* d theta* / d D_b (2 x 3) where the path turns inside (SlabPath.cut_derivative) */
static void cut_derivative(const DeviatoricSlab *m, long p, double a, double b, double dcut[2][3])
{
    const double *n0 = m->n0 + 3 * p;
    double den = (a - b) * (a - b), grad[3], db1[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < 3; j++)
        grad[j] = n0[0] * TO[0][j] + n0[1] * TO[1][j] + n0[2] * TO[2][j];
    if (m->virgin[p]) {
        double d1[3], d2[3], across[3];
        deviator(m->D1 + 3 * p, d1);
        deviator(m->D2 + 3 * p, d2);
        double r = norm3(d1), along = n0[0] * d2[0] + n0[1] * d2[1] + n0[2] * d2[2];
        for (int i = 0; i < 3; i++)
            across[i] = (d2[i] - along * n0[i]) / r;
        for (int j = 0; j < 3; j++)
            db1[j] = across[0] * TO[0][j] + across[1] * TO[1][j] + across[2] * TO[2][j];
    }
    double by_a = -b / den, by_b = a / den;
    for (int j = 0; j < 3; j++) {
        dcut[0][j] = by_a * grad[j] + by_b * db1[j];
        dcut[1][j] = by_b * grad[j];
    }
}

/* the Gauss sums' derivative in theta* of piece j at fixed e* (cut_terms) */
static void cut_terms(const DeviatoricSlab *m, long p, int j, double cut, const double *theta,
                      double c[GP][3], double dc[GP][3][3], double out[2][3])
{
    const double *D1 = m->D1 + 3 * p, *D2 = m->D2 + 3 * p;
    double scale = j == 0 ? 1.0 : -1.0;
    for (int a = 0; a < 2; a++)
        for (int i = 0; i < 3; i++)
            out[a][i] = 0.0;
    for (int g = 0; g < GP; g++) {
        double th = theta[g], rate[3], dcdt[3];
        for (int i = 0; i < 3; i++)
            rate[i] = (1.0 - th) * D1[i] + th * D2[i];
        for (int i = 0; i < 3; i++)
            dcdt[i] = dc[g][i][0] * rate[0] + dc[g][i][1] * rate[1] + dc[g][i][2] * rate[2];
        double length = (j == 0 ? cut * m->xg[g] : (1.0 - cut) * (1.0 - m->xg[g]));
        for (int a = 0; a < 2; a++) {
            double Ta = a == 0 ? 1.0 - th : th, sign = a == 0 ? -1.0 : 1.0;
            for (int i = 0; i < 3; i++)
                out[a][i] += m->wg[g] * (scale * Ta * c[g][i]
                                         + length * (sign * c[g][i] + Ta * dcdt[i]));
        }
    }
}

typedef struct {
    Stack start, second;
    double cut, a, b, tangent_c[3][3];
    int turned, reverses, inside;
    long kc;
} Path;

/* the point's cut, its flags and its stacks (SlabPath.__init__) */
static void path_of(const DeviatoricSlab *m, long p, const Law *L, Path *P, double *buf)
{
    const double *n0 = m->n0 + 3 * p, *e = m->eps + 3 * p;
    const double *D1 = m->D1 + 3 * p, *D2 = m->D2 + 3 * p;
    int depth = m->depth;
    double d1[3], d2[3];
    deviator(D1, d1);
    deviator(D2, d2);
    double a = n0[0] * d1[0] + n0[1] * d1[1] + n0[2] * d1[2];
    double b = n0[0] * d2[0] + n0[1] * d2[1] + n0[2] * d2[2];
    double diff = a - b;
    double cut = diff == 0.0 ? 1.0 : fmin(fmax(a / diff, 0.0), 1.0);
    if (m->fturned == NULL) {
        P->turned = (a != 0.0 ? a : b) < 0.0;
        P->reverses = P->inside = a * b < 0.0;
    } else {
        P->turned = m->fturned[p];
        P->reverses = m->freverses[p];
        P->inside = P->reverses && a * b < 0.0;
        if (!P->reverses)
            cut = m->fcut[p];
    }
    P->a = a, P->b = b, P->cut = cut;
    Stack own = {(double *)m->sc + 3 * depth * p, (double *)m->ss + 3 * depth * p, m->k[p]};
    P->start = own;
    if (P->turned) {
        double c0[3];
        deviator(e, c0);
        pushed(&own, depth, buf, buf + 3 * depth, own.k, c0, m->dev + 3 * p, &P->start);
    }
    double ec[3], sc[3], cc[3], sigma[3];
    strain(e, D1, D2, cut, ec);
    long kc = m->fturned == NULL ? depth_at(&P->start, (deviator(ec, cc), cc)) : m->fkc[p];
    evaluate(L, &P->start, ec, kc, sigma, P->tangent_c, sc);
    P->kc = kc;
    memcpy(m->eps_c + 3 * p, ec, sizeof ec);
    memcpy(m->s_c + 3 * p, sc, sizeof sc);
    P->second = P->start;
    if (P->reverses) {
        deviator(ec, cc);
        pushed(&P->start, depth, buf + 6 * depth, buf + 9 * depth, kc, cc, sc, &P->second);
    }
}

/* d e* / d D_b (3 x 2 x 3): the turn point's strain with theta* moving */
static void turn_strain_derivative(const DeviatoricSlab *m, long p, double cut,
                                   double dcut[2][3], double out[3][2][3])
{
    const double *D1 = m->D1 + 3 * p, *D2 = m->D2 + 3 * p;
    double ib[2] = {cut - 0.5 * cut * cut, 0.5 * cut * cut};
    for (int l = 0; l < 3; l++) {
        double rate = (1.0 - cut) * D1[l] + cut * D2[l];
        for (int b = 0; b < 2; b++)
            for (int j = 0; j < 3; j++)
                out[l][b][j] = (l == j ? ib[b] : 0.0) + rate * dcut[b][j];
    }
}

/* the sums of one Gauss point of piece j: Q, dQ (the branch's tangent),
 * the new branch's jump term; its c and dc kept for the cut terms */
typedef struct {
    double Q[2][3], dQ[2][3][2][3], jump[2][3][3];
    double theta[GP], c[GP][3], dc[GP][3][3];
} Sums;

static void gauss_point(const DeviatoricSlab *m, long p, const Law *L, const Path *P, int j,
                        int g, double C[3][3], int tangent, Sums *S)
{
    const Stack *st = j == 0 ? &P->start : &P->second;
    double e[3], sigma[3], tan[3][3], sdev[3], cd[3];
    double th = j == 0 ? P->cut * m->xg[g] : P->cut + (1.0 - P->cut) * m->xg[g];
    double w = (j == 0 ? P->cut : 1.0 - P->cut) * m->wg[g];
    S->theta[g] = th;
    strain(m->eps + 3 * p, m->D1 + 3 * p, m->D2 + 3 * p, th, e);
    long k = m->fturned != NULL ? m->fk[(2 * p + j) * GP + g] : depth_at(st, (deviator(e, cd), cd));
    m->kk[(2 * p + j) * GP + g] = k;
    evaluate(L, st, e, k, sigma, tan, sdev);
    double T[2] = {1.0 - th, th}, ib[2] = {th - 0.5 * th * th, 0.5 * th * th};
    for (int i = 0; i < 3; i++) {
        S->c[g][i] = sigma[i] - (C[i][0] * e[0] + C[i][1] * e[1] + C[i][2] * e[2]);
        for (int l = 0; l < 3; l++)
            S->dc[g][i][l] = tan[i][l] - C[i][l];
    }
    int on = j == 1 && P->reverses && k == P->second.k;
    for (int a = 0; a < 2; a++) {
        double wT = w * T[a];
        for (int i = 0; i < 3; i++) {
            S->Q[a][i] += wT * S->c[g][i];
            if (!tangent)
                continue;
            for (int l = 0; l < 3; l++) {
                for (int b = 0; b < 2; b++)
                    S->dQ[a][i][b][l] += wT * (S->dc[g][i][l] * ib[b]);
                if (on)
                    S->jump[a][i][l] += wT * (P->tangent_c[i][l] - tan[i][l]);
            }
        }
    }
}

/* after piece j: the new branch's jump term through d e* / d D, the cut terms */
static void piece_terms(const DeviatoricSlab *m, long p, const Path *P, int j,
                        double dec[3][2][3], Sums *S, double dsum[2][3])
{
    if (j == 1 && P->reverses)
        for (int a = 0; a < 2; a++)
            for (int i = 0; i < 3; i++)
                for (int b = 0; b < 2; b++)
                    for (int l = 0; l < 3; l++)
                        S->dQ[a][i][b][l] += S->jump[a][i][0] * dec[0][b][l]
                            + S->jump[a][i][1] * dec[1][b][l] + S->jump[a][i][2] * dec[2][b][l];
    if (P->inside) {
        double part[2][3];
        cut_terms(m, p, j, P->cut, S->theta, S->c, S->dc, part);
        for (int a = 0; a < 2; a++)
            for (int i = 0; i < 3; i++)
                dsum[a][i] += part[a][i];
    }
}

static void point(const DeviatoricSlab *m, long p, double *buf)
{
    Law L = {m->G[p], m->gref[p], m->beta[p], m->s[p], m->K[p]};
    Path P;
    path_of(m, p, &L, &P, buf);
    double lam = L.K - 2.0 * L.G / 3.0;
    double C[3][3] = {{lam + 2.0 * L.G, lam, 0.0}, {lam, lam + 2.0 * L.G, 0.0}, {0.0, 0.0, L.G}};
    double dsum[2][3] = {{0.0}}, dcut[2][3] = {{0.0}}, dec[3][2][3] = {{{0.0}}};
    double *dQout = m->dQ == NULL ? NULL : m->dQ + 36 * p;
    int tangent = dQout != NULL;
    Sums S;
    memset(S.Q, 0, sizeof S.Q);
    memset(S.dQ, 0, sizeof S.dQ);
    if (tangent && P.inside)
        cut_derivative(m, p, P.a, P.b, dcut);
    if (tangent && P.reverses)
        turn_strain_derivative(m, p, P.cut, dcut, dec);
    for (int j = 0; j < 2; j++) {
        memset(S.jump, 0, sizeof S.jump);
        for (int g = 0; g < GP; g++)
            gauss_point(m, p, &L, &P, j, g, C, tangent, &S);
        if (tangent)
            piece_terms(m, p, &P, j, dec, &S, dsum);
    }
    for (int a = 0; a < 2; a++)
        for (int i = 0; i < 3; i++)
            m->Q[6 * p + 3 * a + i] = S.Q[a][i] * m->dt;
    m->turned[p] = (unsigned char)P.turned;
    m->reverses[p] = (unsigned char)P.reverses;
    m->cut[p] = P.cut;
    m->kc[p] = P.kc;
    if (!tangent)
        return;
    for (int a = 0; a < 2; a++)
        for (int i = 0; i < 3; i++)
            for (int b = 0; b < 2; b++)
                for (int l = 0; l < 3; l++) {
                    double v = S.dQ[a][i][b][l];
                    if (P.inside)
                        v += dsum[a][i] * dcut[b][l];
                    dQout[18 * a + 6 * i + 3 * b + l] = v * m->dt;
                }
}

int vst_deviatoric_slab(DeviatoricSlab *m)
{
    double buf[12 * MAXDEPTH];
    if (m->depth > MAXDEPTH)
        return 1;
    if (SQ2 == 0.0)
        constants();
    for (long p = 0; p < m->n; p++)
        point(m, p, buf);
    return 0;
}
