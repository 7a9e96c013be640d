/* A slab of laws with Smith soil nodes among them, on one rank, in one
 * call (vstpetsc/line/native/smith_slab.py): the steps of
 * vstpetsc.line.reduced_newton.ReducedNewton (the checked reference,
 * -vst_native 0) on the laws' coordinates y,
 *
 *     r(y) = y - y0 + S f(y) = 0,    S = R A^{-1} C,
 *
 * with R (y from the unknowns: sign V at each law's nodes) and C (the laws'
 * rows: sign W) local, and the slab matrix A block tridiagonal.  Nothing
 * dense: S f is one solve with A's factors, and the Newton step
 * (I + S F) d = r is, by the push-through identity,
 *
 *     d = r - R (A + C F R)^{-1} C F r,
 *
 * where C F R adds each law's 2 x 2 tangent F_j to the blocks of its
 * nodes (a pair: of two neighbouring nodes), so A + C F R keeps A's bands
 * and its LU is the block Thomas algorithm: O(nodes) a step where the
 * dense Newton costs O(laws^3).  Few laws on many nodes (a pile's toe
 * soil on a long mesh) take the dense S instead: O(laws^2) a residual,
 * O(laws^3) a step, nothing over the nodes.
 *
 * The Smith nodes' integrals are vstpetsc.kernels.smith.smith_integrals and
 * the cushions' vstpetsc.line.laws.cushion.cushion_integrals, the same pieces
 * and Gauss points; other laws (a penalty pair) are evaluated by a
 * callback into Python. */

#include <math.h>
#include <string.h>

#include "bands.h"
#include "gap.h"

typedef struct {
    int count;                 /* Smith nodes */
    const int *law;            /* each one's law number j (coordinates 2j, 2j + 1) */
    const long *uidx;          /* its node among the LawSet's nodes (u) */
    const double *sign, *Ru, *k, *J;
    const int *toe;
    double *wn, *p;            /* at the slab start */
    double *out;               /* (count, 7): f1 f2 t11 t12 t21 t22 slip at the end */
    int *hit;                  /* whether it acted at the last evaluation */
    const int *table;          /* its soil table */
    double *impulse;           /* out: f1 + f2 of the slab */
    int tables;
    double *tally;             /* per table, the work its nodes took: running sums */
} SmithNodes;

#define SPANS 8                /* a cushion's pieces in a slab (at most 7) */

typedef struct {
    int count;                 /* cushion pairs */
    const int *law;            /* each one's law number j */
    const long *uidx;          /* (count, 2): its nodes among the LawSet's nodes, -1: none */
    const double *g0, *k, *ku;
    double *gn, *M;            /* at the slab start (M: in from the law, reset when apart) */
    double *out;               /* (count, 7): f1 f2 t11 t12 t21 t22 M at the end */
    double *spans;             /* (count, SPANS, 2): where it pushes */
    int *nspans, *hit;
} Cushions;

typedef struct {
    int laws;                  /* L: 2L coordinates */
    long N;                    /* nodes of the slab matrix */
    int max_it;
    double rtol, atol, dt;
    const double *A, *Ainv, *ACp;   /* A's bands and factors */
    const double *S;           /* (2L, 2L) row major, or NULL: S through A's bands */
    double *M;                 /* (2L, 2L) workspace of the dense step */
    double *B, *Binv, *BCp;    /* A + C F R and its factors (workspace) */
    double *g, *sol;           /* (2N) workspace */
    const double *V, *W;       /* 2 x 2: z to v, law terms to rows */
    const long *lnode;         /* (L, 2): each law's nodes, -1: none */
    const double *lsign;       /* (L, 2) */
    double *X;                 /* in: the law-free solution; out: the slab's (2N) */
    double *b;                 /* the running right-hand side (2N) */
    const double *CW;          /* 2 x 2: the carry of the laws' rows into b */
    double *u;                 /* the LawSet's node displacements at t^n */
    const double *f_prev;      /* the laws' terms of the previous slab */
    double *y0, *y, *trial, *r, *d, *sf;   /* (2L) */
    double *f, *tan;           /* (2L), (L, 4): terms and tangents of the evaluation */
    double *work;              /* (L): f . y of the converged slab */
    const int *key;            /* (L): each law's energy term */
    double *key_work;          /* out: the slab's work per energy term */
    int nkeys, nu, nheads;
    const long *unode;         /* (nu): the LawSet's nodes, global numbers */
    const int *head_law;       /* (nheads): laws whose work on one node is reported */
    const long *head_node;     /* its global node */
    const double *head_sign;
    SmithNodes soil;
    Cushions cushions;
    int (*others)(void);       /* the other laws at yeval into f, tan; 1 if any acts */
    double *yeval;             /* (2L): where the callback evaluates */
    int acted;                 /* in: whether the laws acted in the previous slab */
    int ran;                   /* in: whether a law acts at y0 */
    int iterations;            /* out */
    double norm;
} SmithSlab;

/* ---- Smith's integrals (kernels/smith.py, operation for operation) ---- */

typedef struct {
    double y1, y2, dt, k, Ru, J;
    int toe;
} Node;

static double wq(const double *b, double t)
{
    return b[0] + t * (b[1] + t * b[2]);
}

/* roots of w(theta) = level strictly inside (s, t), sorted */
static int roots_between(const double *b, double level, double s, double t, double *r)
{
    double w = t - s;
    int n = roots01(wq(b, s) - level, w * (b[1] + 2.0 * s * b[2]), w * w * b[2], r);
    for (int i = 0; i < n; i++)
        r[i] = s + w * r[i];
    return n;
}

/* 3-point Gauss on [s, t], where the law is smooth (plastic 0: elastic) */
static void gauss(double *out, const double *b, double p, const double *dp, double plastic,
                  double s, double t, const Node *n)
{
    static const double SQ = 0.7745966692414834;     /* Python's math.sqrt(0.6) */
    const double gx[3] = {0.5 - 0.5 * SQ, 0.5, 0.5 + 0.5 * SQ};
    const double gw[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
    double length = t - s;
    for (int i = 0; i < 3; i++) {
        double th = s + length * gx[i];
        double w = n->dt * length * gw[i];
        double v = n->y1 + (n->y2 - n->y1) * th;
        double T[2] = {1.0 - th, th}, Rs, dRs[2], R, dR[2];
        if (plastic == 0.0) {
            Rs = n->k * (wq(b, th) - p);
            double half = 0.5 * th * th;
            dRs[0] = n->k * (n->dt * (th - half) - dp[0]);
            dRs[1] = n->k * (n->dt * half - dp[1]);
            if (n->toe && Rs <= 0.0)
                continue;               /* the toe's gap is open */
        } else {
            Rs = plastic * n->Ru;
            dRs[0] = dRs[1] = 0.0;
        }
        if (n->toe) {
            double factor = 1.0 + n->J * v;
            if (factor <= 0.0)
                continue;
            R = Rs * factor;
            dR[0] = dRs[0] * factor + Rs * n->J * T[0];
            dR[1] = dRs[1] * factor + Rs * n->J * T[1];
        } else {
            double sign = Rs > 0.0 ? 1.0 : Rs < 0.0 ? -1.0 : 0.0;
            R = Rs + n->J * fabs(Rs) * v;
            dR[0] = dRs[0] * (1.0 + n->J * sign * v) + n->J * fabs(Rs) * T[0];
            dR[1] = dRs[1] * (1.0 + n->J * sign * v) + n->J * fabs(Rs) * T[1];
        }
        for (int a = 0; a < 2; a++) {
            out[a] += w * R * T[a];
            out[2 + 2 * a] += w * dR[0] * T[a];
            out[3 + 2 * a] += w * dR[1] * T[a];
        }
    }
}

/* [s, t], split at the toe where 1 + J v = 0 */
static void pieces(double *out, const double *b, double p, const double *dp, double plastic,
                   double s, double t, const Node *n)
{
    double cuts[3] = {s, t, t};
    int nc = 2;
    if (n->toe && n->J > 0.0 && n->y2 != n->y1) {
        double c = (-1.0 / n->J - n->y1) / (n->y2 - n->y1);
        if (s < c && c < t)
            cuts[1] = c, nc = 3;
    }
    for (int i = 0; i < nc - 1; i++)
        gauss(out, b, p, dp, plastic, cuts[i], cuts[i + 1], n);
}

/* an elastic stretch [s, t]: split where R_s changes sign */
static void elastic(double *out, const double *b, double p, const double *dp, double s,
                    double t, const Node *n)
{
    double cuts[4];
    int nc = 0;
    cuts[nc++] = s;
    nc += roots_between(b, p, s, t, cuts + 1);
    cuts[nc++] = t;
    for (int i = 0; i < nc - 1; i++)
        pieces(out, b, p, dp, 0.0, cuts[i], cuts[i + 1], n);
}

/* Whether the slab is one smooth elastic piece (SoilNode.force_batch's
 * test): w monotone, w - p of one sign and inside the quake at both ends,
 * the toe pressing with a positive damping factor throughout.  Then the
 * general path below would find no cut: the same Gauss sums without its
 * root solves. */
static int smooth(const double *b, double p, double q, const Node *n)
{
    double e0 = b[0] - p, e1 = b[0] - p + b[1] + b[2], lim = q * (1.0 - 1e-12);
    if (b[1] * (b[1] + 2.0 * b[2]) < 0.0 || !(e0 * e1 > 0.0) || !(fabs(e0) < lim)
        || !(fabs(e1) < lim))
        return 0;
    return !n->toe || (e0 > 0.0 && 1.0 + n->J * n->y1 > 0.0 && 1.0 + n->J * n->y2 > 0.0);
}

/* out[7] = (f1, f2, df1/dy1, df1/dy2, df2/dy1, df2/dy2, slip at the end);
 * 0 when the node exerts nothing */
static int smith_integrals(double wn, double p, const Node *n, double *out)
{
    double b[3] = {wn, n->dt * n->y1, 0.5 * n->dt * (n->y2 - n->y1)};
    double q = n->Ru / n->k, edges[3] = {0.0, 1.0, 1.0}, dp[2] = {0.0, 0.0};
    int ne = 2;
    for (int i = 0; i < 6; i++)
        out[i] = 0.0;
    if (smooth(b, p, q, n)) {
        gauss(out, b, p, dp, 0.0, 0.0, 1.0, n);
        out[6] = p;
        return 1;
    }
    if (b[2] != 0.0 && 0.0 < -b[1] / (2.0 * b[2]) && -b[1] / (2.0 * b[2]) < 1.0)
        edges[1] = -b[1] / (2.0 * b[2]), ne = 3;
    for (int e = 0; e < ne - 1; e++) {
        double s = edges[e], t = edges[e + 1], mid = 0.5 * (s + t);
        double direction = b[1] + 2.0 * mid * b[2] > 0.0 ? 1.0 : -1.0;
        int yields = direction > 0.0 || !n->toe;
        double limit = p + direction * q, ty = t, ups[2];
        if (yields) {
            if (direction * (wq(b, s) - p) >= q * (1.0 - 1e-12))
                ty = s;                 /* already flowing */
            else
                ty = roots_between(b, limit, s, t, ups) ? ups[0] : t;
        }
        if (ty > s)
            elastic(out, b, p, dp, s, ty, n);
        if (ty < t) {
            pieces(out, b, p, dp, direction, ty, t, n);
            p = wq(b, t) - direction * q;
            double half = 0.5 * t * t;
            dp[0] = n->dt * (t - half), dp[1] = n->dt * half;
        }
    }
    out[6] = p;
    for (int i = 0; i < 6; i++)
        if (out[i] != 0.0)
            return 1;
    return 0;
}

/* ---- a cushion's integrals (line/laws/cushion.py, operation for operation) ---- */

static const double GX[3] = {0.5 - 0.5 * 0.7745966692414834, 0.5, 0.5 + 0.5 * 0.7745966692414834};
static const double GW[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

/* the piece [p, q] with F = stiffness (delta - shift); ``factor`` and dM
 * when the shift is factor M with M reached inside the slab (dM NULL: not) */
static void cushion_add(double *out, const double *c, double p, double q, double dt,
                        double stiffness, double shift, double factor, const double *dM)
{
    double length = q - p;
    for (int i = 0; i < 3; i++) {
        double t = p + length * GX[i];
        double w = dt * length * GW[i];
        double F = stiffness * (c[0] + t * (c[1] + t * c[2]) - shift);
        double half = 0.5 * t * t;
        double g1 = stiffness * dt * (t - half), g2 = stiffness * dt * half;
        if (dM) {
            g1 -= stiffness * factor * dM[0];
            g2 -= stiffness * factor * dM[1];
        }
        double T[2] = {1.0 - t, t};
        for (int a = 0; a < 2; a++) {
            out[a] += w * F * T[a];
            out[2 + 2 * a] += w * g1 * T[a];
            out[3 + 2 * a] += w * g2 * T[a];
        }
    }
}

/* the loading interval [*t1, *t2] where delta rises above M; 0 when none */
static int cushion_loading(const double *c, double M, double *t1, double *t2)
{
    double top = 1.0, ups[2];
    if (c[2] < 0.0) {
        double vertex = -c[1] / (2.0 * c[2]);
        if (0.0 < vertex && vertex < 1.0)
            top = vertex;
    }
    if (c[0] + top * (c[1] + top * c[2]) <= M)
        return 0;
    double start = 0.0;
    if (!(c[0] >= M && c[1] >= 0.0)) {
        int n = roots01(c[0] - M, c[1], c[2], ups), m = 0;
        for (int i = 0; i < n; i++)
            if (ups[i] < top)
                ups[m++] = ups[i];
        start = m ? ups[m - 1] : 0.0;
    }
    *t1 = start, *t2 = top;
    return 1;
}

/* out[7] (forces, tangents, M at the end) and the spans where it pushes;
 * 0 when it exerts nothing */
static int cushion_integrals(double gn, double d1, double d2, double dt, double k, double ku,
                             double M, double *out, double *spans, int *nspans)
{
    double c[3] = {-gn, -(-dt * d1), -(0.5 * dt * (d1 - d2))};
    M = c[0] > M ? c[0] : M;                       /* Python's max(M, c0) */
    double zero = M * (1.0 - k / ku);
    *nspans = 0;
    for (int i = 0; i < 6; i++)
        out[i] = 0.0;
    if (!closed_somewhere(gn + zero, -dt * d1, 0.5 * dt * (d1 - d2)))
        return 0;
    double t1 = 0.0, t2 = 0.0, M2 = M, dM2[2] = {0.0, 0.0};
    int loads = cushion_loading(c, M, &t1, &t2);
    if (loads) {
        M2 = c[0] + t2 * (c[1] + t2 * c[2]);
        double half = 0.5 * t2 * t2;
        dM2[0] = dt * (t2 - half), dM2[1] = dt * half;
    }
    /* the pieces: before (M), load, after (M2) */
    double pieces[3][2] = {{0.0, loads ? t1 : 1.0}, {t1, t2}, {t2, 1.0}};
    for (int piece = 0; piece < (loads ? 3 : 1); piece++) {
        double p = pieces[piece][0], q = pieces[piece][1];
        if (!(q > p))
            continue;
        if (piece == 1) {
            cushion_add(out, c, p, q, dt, k, 0.0, 0.0, NULL);
            spans[2 * *nspans] = p, spans[2 * *nspans + 1] = q, (*nspans)++;
            continue;
        }
        double m = piece == 0 ? M : M2, shift = m * (1.0 - k / ku), w = q - p, r[2];
        double edges[4];
        int ne = 0;
        edges[ne++] = p;
        int nr = roots01(c[0] - shift + p * (c[1] + p * c[2]), w * (c[1] + 2.0 * p * c[2]),
                         w * w * c[2], r);
        for (int i = 0; i < nr; i++)
            edges[ne++] = p + w * r[i];
        edges[ne++] = q;
        for (int e = 0; e < ne - 1; e++) {
            double s0 = edges[e], s1 = edges[e + 1], mid = 0.5 * (s0 + s1);
            if (c[0] + mid * (c[1] + mid * c[2]) > shift) {
                cushion_add(out, c, s0, s1, dt, ku, shift, 1.0 - k / ku,
                            piece == 0 ? NULL : dM2);
                spans[2 * *nspans] = s0, spans[2 * *nspans + 1] = s1, (*nspans)++;
            }
        }
    }
    out[6] = M2 > M ? M2 : M;
    for (int i = 0; i < 6; i++)
        if (out[i] != 0.0)
            return 1;
    return 0;
}

/* ---- the slab ---- */

/* whether Smith node i acts for the coordinates y (SoilNode.acts) */
static int soil_acts(const SmithSlab *c, int i, const double *y)
{
    const SmithNodes *s = &c->soil;
    int j = s->law[i];
    double y1 = y[2 * j], y2 = y[2 * j + 1];
    if (!s->toe[i])
        return s->wn[i] != s->p[i] || y1 != 0.0 || y2 != 0.0;
    return closed_somewhere(s->p[i] - s->wn[i], -c->dt * y1, -0.5 * c->dt * (y2 - y1));
}

/* law j's terms and tangent from its integrals o (f1, f2, t11, t12, t21, t22) */
static void put(SmithSlab *c, int j, const double *o)
{
    c->f[2 * j] = o[0], c->f[2 * j + 1] = o[1];
    memcpy(c->tan + 4 * j, o + 2, 4 * sizeof(double));
}

/* every law at y into f and tan; whether any acts */
static int evaluate(SmithSlab *c, const double *y)
{
    SmithNodes *s = &c->soil;
    int any = 0;
    if (c->others) {
        memcpy(c->yeval, y, 2 * c->laws * sizeof(double));
        any = c->others();
    }
    for (int i = 0; i < s->count; i++) {
        int j = s->law[i];
        Node n = {y[2 * j], y[2 * j + 1], c->dt, s->k[i], s->Ru[i], s->J[i], s->toe[i]};
        double *o = s->out + 7 * i;
        s->hit[i] = smith_integrals(s->wn[i], s->p[i], &n, o);
        put(c, j, o);
        any |= s->hit[i];
    }
    Cushions *cu = &c->cushions;
    for (int i = 0; i < cu->count; i++) {
        int j = cu->law[i];
        double *o = cu->out + 7 * i;
        cu->hit[i] = cushion_integrals(cu->gn[i], y[2 * j], y[2 * j + 1], c->dt, cu->k[i],
                                       cu->ku[i], cu->M[i], o, cu->spans + 2 * SPANS * i,
                                       cu->nspans + i);
        put(c, j, o);
        any |= cu->hit[i];
    }
    return any;
}

/* Cushion.start_slab and Cushion.acts at y0 for cushion i */
static int cushion_start(SmithSlab *c, int i)
{
    Cushions *cu = &c->cushions;
    double moved = 0.0;
    for (int a = 0; a < 2; a++) {
        long n = cu->uidx[2 * i + a];
        if (n >= 0)
            moved += c->lsign[2 * cu->law[i] + a] * c->u[n];
    }
    cu->gn[i] = cu->g0[i] - moved;
    if (cu->gn[i] > 0.0)       /* the ends are apart: the next contact starts fresh */
        cu->M[i] = 0.0;
    int j = cu->law[i];
    double d1 = c->y0[2 * j], d2 = c->y0[2 * j + 1];
    double zero = cu->M[i] * (1.0 - cu->k[i] / cu->ku[i]);
    return closed_somewhere(cu->gn[i] + zero, -c->dt * d1, 0.5 * c->dt * (d1 - d2));
}

/* out += each law's terms v_j (2 a law) on its nodes' rows, sign M v_j */
static void add_rows(const SmithSlab *c, const double *M, const double *v, double *out)
{
    for (int j = 0; j < c->laws; j++) {
        if (v[2 * j] == 0.0 && v[2 * j + 1] == 0.0)
            continue;
        double w[2];
        mv2(M, v + 2 * j, w);
        for (int a = 0; a < 2; a++) {
            long node = c->lnode[2 * j + a];
            if (node >= 0) {
                out[2 * node] += c->lsign[2 * j + a] * w[0];
                out[2 * node + 1] += c->lsign[2 * j + a] * w[1];
            }
        }
    }
}

/* g = C v: the laws' terms v on their rows (sign W v_j) */
static void scatter(const SmithSlab *c, const double *v, double *g)
{
    memset(g, 0, 2 * c->N * sizeof(double));
    add_rows(c, c->W, v, g);
}

/* y = R x: each law's coordinates, sign V x at its nodes */
static void coordinates(const SmithSlab *c, const double *x, double *y)
{
    for (int j = 0; j < c->laws; j++) {
        y[2 * j] = y[2 * j + 1] = 0.0;
        for (int a = 0; a < 2; a++) {
            long node = c->lnode[2 * j + a];
            if (node >= 0) {
                double v[2];
                mv2(c->V, x + 2 * node, v);
                y[2 * j] += c->lsign[2 * j + a] * v[0];
                y[2 * j + 1] += c->lsign[2 * j + a] * v[1];
            }
        }
    }
}

/* sf = S v = R A^{-1} C v */
static void times_s(SmithSlab *c, const double *v, double *sf)
{
    if (c->S) {                /* few laws on many nodes: the dense S */
        int n = 2 * c->laws;
        for (int i = 0; i < n; i++)
            sf[i] = 0.0;
        for (int m = 0; m < n; m++)
            if (v[m] != 0.0)
                for (int i = 0; i < n; i++)
                    sf[i] += c->S[i * n + m] * v[m];
        return;
    }
    scatter(c, v, c->g);
    bands_solve(c->N, c->A, c->Ainv, c->ACp, c->g, c->sol);
    coordinates(c, c->sol, sf);
}

/* r = y - y0 + S f(y) after evaluating at y; returns max |S f| */
static double residual(SmithSlab *c, const double *y, int *any)
{
    int n = 2 * c->laws;
    *any = evaluate(c, y);
    times_s(c, c->f, c->sf);
    for (int i = 0; i < n; i++)
        c->r[i] = y[i] - c->y0[i] + c->sf[i];
    return max_abs(c->sf, n);
}

/* d = (I + S F)^{-1} r with the dense S: Gaussian elimination with
 * partial pivoting; 0 when singular or not finite */
static int dense_step(SmithSlab *c)
{
    int n = 2 * c->laws;
    double *M = c->M;
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < c->laws; j++) {
            const double *F = c->tan + 4 * j, *Si = c->S + i * n + 2 * j;
            M[i * n + 2 * j] = Si[0] * F[0] + Si[1] * F[2];
            M[i * n + 2 * j + 1] = Si[0] * F[1] + Si[1] * F[3];
        }
        M[i * n + i] += 1.0;
        c->d[i] = c->r[i];
    }
    for (int k = 0; k < n; k++) {
        int p = k;
        for (int i = k + 1; i < n; i++)
            if (fabs(M[i * n + k]) > fabs(M[p * n + k]))
                p = i;
        if (M[p * n + k] == 0.0)
            return 0;
        if (p != k) {
            for (int j = 0; j < n; j++) {
                double t = M[k * n + j];
                M[k * n + j] = M[p * n + j], M[p * n + j] = t;
            }
            double t = c->d[k];
            c->d[k] = c->d[p], c->d[p] = t;
        }
        for (int i = k + 1; i < n; i++) {
            double l = M[i * n + k] / M[k * n + k];
            if (l == 0.0)
                continue;
            for (int j = k; j < n; j++)
                M[i * n + j] -= l * M[k * n + j];
            c->d[i] -= l * c->d[k];
        }
    }
    for (int k = n - 1; k >= 0; k--) {
        double t = c->d[k];
        for (int j = k + 1; j < n; j++)
            t -= M[k * n + j] * c->d[j];
        c->d[k] = t / M[k * n + k];
        if (!isfinite(c->d[k]))
            return 0;
    }
    return 1;
}

/* d = (I + S F)^{-1} r = r - R (A + C F R)^{-1} C F r; 0 when not finite */
static int step(SmithSlab *c)
{
    int n = 2 * c->laws;
    if (c->S)
        return dense_step(c);
    memcpy(c->B, c->A, 12 * c->N * sizeof(double));
    for (int j = 0; j < c->laws; j++) {
        const double *F = c->tan + 4 * j;
        mv2(F, c->r + 2 * j, c->d + 2 * j);          /* F r, for C F r */
        if (F[0] == 0.0 && F[1] == 0.0 && F[2] == 0.0 && F[3] == 0.0)
            continue;
        double WF[4], WFV[4];
        mul2(c->W, F, WF);
        mul2(WF, c->V, WFV);
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 2; b++) {
                long k = c->lnode[2 * j + a], l = c->lnode[2 * j + b];
                if (k < 0 || l < 0)
                    continue;
                double s = c->lsign[2 * j + a] * c->lsign[2 * j + b];
                double *blk = c->B + 12 * k + 4 * (1 + l - k);    /* |k - l| <= 1 */
                for (int m = 0; m < 4; m++)
                    blk[m] += s * WFV[m];
            }
    }
    bands_factor(c->N, c->B, c->Binv, c->BCp);
    scatter(c, c->d, c->g);
    bands_solve(c->N, c->B, c->Binv, c->BCp, c->g, c->sol);
    coordinates(c, c->sol, c->d);
    for (int i = 0; i < n; i++) {
        c->d[i] = c->r[i] - c->d[i];
        if (!isfinite(c->d[i]))
            return 0;
    }
    return 1;
}

/* ReducedNewton.solve from c->y; 0 when converged */
static int newton(SmithSlab *c, int warm)
{
    int n = 2 * c->laws, any;
    double sf = residual(c, c->y, &any);
    if (warm && !any) {        /* a start where no law acts: from y0 */
        memcpy(c->y, c->y0, n * sizeof(double));
        sf = residual(c, c->y, &any);
    }
    double size = max_abs(c->y0, n), norm = max_abs(c->r, n);
    for (int it = 0; it <= c->max_it; it++) {
        if (norm <= fmax(c->atol, c->rtol * (size + sf))) {
            c->iterations = it;
            c->norm = norm;
            return 0;
        }
        if (it == c->max_it || !step(c))
            break;
        double lam = 1.0, fresh = norm;
        for (int h = 0; h < 20; h++) {   /* full step, halved while |r| grows */
            for (int i = 0; i < n; i++)
                c->trial[i] = c->y[i] - lam * c->d[i];
            sf = residual(c, c->trial, &any);
            fresh = max_abs(c->r, n);
            if (fresh < norm || lam < 1e-5)
                break;
            lam *= 0.5;
        }
        memcpy(c->y, c->trial, n * sizeof(double));
        norm = fresh;
    }
    c->norm = norm;
    return 1;
}

/* The slab's start from the law-free solution X: the Smith nodes'
 * start_slab, the coordinates y0; whether a Smith node acts there (the
 * caller then tests the other laws at y0) */
int vst_smith_start(SmithSlab *c)
{
    SmithNodes *s = &c->soil;
    int any = 0;
    for (int i = 0; i < s->count; i++)              /* SoilNode.start_slab */
        s->wn[i] = s->sign[i] * c->u[s->uidx[i]];
    coordinates(c, c->X, c->y0);
    for (int i = 0; i < c->cushions.count; i++)
        any |= cushion_start(c, i);
    for (int i = 0; i < s->count && !any; i++)
        any = soil_acts(c, i, c->y0);
    return any;
}

/* SoilNode.finish_slab for every Smith node: the impulse, the slip, the
 * slab's work (f . y) summed per table, then added to its running sum;
 * Cushion's M moves on where it pushed (its finish_slab in Python does the
 * rest) */
static void finish(SmithSlab *c)
{
    SmithNodes *s = &c->soil;
    double slab[s->tables > 0 ? s->tables : 1];
    for (int t = 0; t < s->tables; t++)
        slab[t] = 0.0;
    for (int i = 0; i < s->count; i++) {
        const double *o = s->out + 7 * i;
        int j = s->law[i];
        if (!s->hit[i]) {
            s->impulse[i] = 0.0;
            continue;
        }
        s->impulse[i] = o[0] + o[1];
        slab[s->table[i]] += o[0] * c->y[2 * j] + o[1] * c->y[2 * j + 1];
        s->p[i] = o[6];
    }
    for (int t = 0; t < s->tables; t++)
        s->tally[t] += slab[t];
    Cushions *cu = &c->cushions;
    for (int i = 0; i < cu->count; i++)
        if (cu->hit[i])
            cu->M[i] = cu->out[7 * i + 6];
}

/* The slab after vst_smith_start (``ran``: whether a law acts): the start
 * guess, Newton, the work, the laws' terms into X, the Smith nodes' and
 * cushions' finish.  Returns 0 (converged, or nothing acts), 1 (not
 * converged). */
int vst_smith_solve(SmithSlab *c)
{
    SmithNodes *s = &c->soil;
    int n = 2 * c->laws;
    if (!c->ran) {            /* the laws give nothing (LawSet.evaluate at y0) */
        for (int i = 0; i < s->count; i++)
            s->hit[i] = 0;
        for (int i = 0; i < c->cushions.count; i++)
            c->cushions.hit[i] = 0;
        memset(c->f, 0, n * sizeof(double));
        finish(c);
        return 0;
    }
    if (c->acted) {
        times_s(c, c->f_prev, c->sf);
        for (int i = 0; i < n; i++)
            c->y[i] = c->y0[i] - c->sf[i];
    } else {
        memcpy(c->y, c->y0, n * sizeof(double));
    }
    int code = newton(c, c->acted);
    for (int k = 0; k < c->nkeys; k++)
        c->key_work[k] = 0.0;
    for (int j = 0; j < c->laws; j++) {
        c->work[j] = c->f[2 * j] * c->y[2 * j] + c->f[2 * j + 1] * c->y[2 * j + 1];
        c->key_work[c->key[j]] += c->work[j];
    }
    /* the laws' terms into the solution: X -= A^{-1} C f, which the last
     * residual (at the solution: Newton stops right after one) left in sol
     * (with the dense S the caller subtracts them on their columns' spans) */
    if (!c->S)
        for (long i = 0; i < 2 * c->N; i++)
            c->X[i] -= c->sol[i];
    finish(c);
    return code;
}

/* The whole slab when every law is compiled (no callback): the start, the
 * test, the solve */
int vst_smith_slab(SmithSlab *c)
{
    c->ran = vst_smith_start(c);
    return vst_smith_solve(c);
}

/* LawSolver.advance: the laws' nodes' displacements (u += z_2); after an
 * acting slab its terms carried into the running sum b (b += carry W P f
 * on the laws' rows) and the marked laws' work on their node, -sign (f1 v^1
 * + f2 v^2), returned. */
double vst_smith_advance(SmithSlab *c, int acted)
{
    double transferred = 0.0;
    for (int i = 0; i < c->nu; i++)
        c->u[i] += c->X[2 * c->unode[i] + 1];
    if (!acted)
        return 0.0;
    add_rows(c, c->CW, c->f, c->b);
    for (int h = 0; h < c->nheads; h++) {
        double v[2];
        int j = c->head_law[h];
        mv2(c->V, c->X + 2 * c->head_node[h], v);
        transferred += c->head_sign[h] * (c->f_prev[2 * j] * v[0] + c->f_prev[2 * j + 1] * v[1]);
    }
    return transferred;
}

/* A's factors, once a run */
void vst_smith_factor_a(const double *A, long N, double *Ainv, double *ACp)
{
    bands_factor(N, A, Ainv, ACp);
}

/* One cushion's integrals (tests): in = (gn, d1, d2, dt, k, ku, M), out[7]
 * and spans[2 SPANS], their count in *nspans */
int vst_cushion_integrals(const double *in, double *out, double *spans, int *nspans)
{
    return cushion_integrals(in[0], in[1], in[2], in[3], in[4], in[5], in[6], out, spans,
                             nspans);
}

/* One node's integrals (tests): in = (wn, p, y1, y2, dt, k, Ru, J, toe),
 * out[7] as smith_integrals; whether it exerts anything */
int vst_smith_node(const double *in, double *out)
{
    Node n = {in[2], in[3], in[4], in[5], in[6], in[7], in[8] != 0.0};
    return smith_integrals(in[0], in[1], &n, out);
}
